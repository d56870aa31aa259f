"""cffi build script (API mode) of the extension rps3._rps3.

The declarations given to cffi are include/rps3.h itself, run through the C
preprocessor: no struct layout or prototype is written here, and cffi's
generated C code is compiled against the same header, so that a header
change either rebuilds consistently or fails to compile.

Where the library comes from:
  - RPS3_PREFIX set: an installed rps3 (`make install PREFIX=...`):
    PREFIX/include/rps3.h, linked against PREFIX/lib/librps3.so;
  - otherwise the repository this file sits in: include/rps3.h and
    build/librps3-pic.a (made with `make lib` when missing), linked in.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess

from cffi import FFI

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))

# a C loop over samples for trajectories (the library evaluates one time
# per call), writing the component-major layout of the batch entry points
# (component c of sample i at [c * n + i]) so that the samples go to
# Model.inverse without a transposing copy; compiled into the extension,
# next to cffi's code
HELPERS = r"""
static int rps3py_traj_eval_n(const rps3_model *m, const rps3_traj *tr,
                              size_t n, const double *t, double *pose,
                              double *dpose, double *ddpose) {
  size_t i, c;
  for (i = 0; i < n; i++) {
    double q[3], dq[3], ddq[3];
    int s = rps3_traj_eval(m, tr, t[i], q, dq, ddq);
    if (s != RPS3_OK) return s;
    for (c = 0; c < 3; c++) {
      pose[c * n + i] = q[c];
      dpose[c * n + i] = dq[c];
      ddpose[c * n + i] = ddq[c];
    }
  }
  return RPS3_OK;
}
static const char *rps3py_header_version(void) { return RPS3_VERSION_STRING; }
"""

HELPER_DECLS = """
int rps3py_traj_eval_n(const rps3_model *m, const rps3_traj *tr, size_t n,
                       const double *t, double *pose, double *dpose,
                       double *ddpose);
const char *rps3py_header_version(void);
"""


def _sh(cmd: list[str], **kw: object) -> str:
    return subprocess.run(cmd, check=True, capture_output=True, text=True,
                          **kw).stdout  # type: ignore[call-overload]


def _where() -> tuple[str, dict[str, list[str]]]:
    """The header's directory and the link arguments for set_source."""
    gsl = shlex.split(_sh(["gsl-config", "--libs"]))
    libs = [a[2:] for a in gsl if a.startswith("-l")]
    libdirs = [a[2:] for a in gsl if a.startswith("-L")]
    prefix = os.environ.get("RPS3_PREFIX")
    if prefix:
        lib = os.path.join(prefix, "lib")
        return os.path.join(prefix, "include"), {
            "depends": [os.path.join(lib, "librps3.so")],
            "libraries": ["rps3", *libs],
            "library_dirs": [lib, *libdirs],
            "runtime_library_dirs": [lib],
        }
    archive = os.path.join(ROOT, "build", "librps3-pic.a")
    if not os.path.exists(archive):
        # the calling make's jobserver is not ours
        env = {k: v for k, v in os.environ.items()
               if k not in ("MAKEFLAGS", "MFLAGS", "MAKELEVEL")}
        subprocess.run(["make", "-C", ROOT, "lib"], check=True, env=env)
    return os.path.join(ROOT, "include"), {
        # a rebuilt library relinks the extension
        "depends": [archive, os.path.join(ROOT, "include", "rps3.h")],
        "extra_objects": [archive],
        "libraries": libs,
        "library_dirs": libdirs,
    }


def _declarations(header: str) -> str:
    """rps3.h as cffi's cdef takes it: preprocessed without the standard
    headers (cffi knows size_t) and without the visibility attribute, plus
    the header's integer macros as `#define NAME ...` (values from the
    compiler)."""
    text = open(header).read()
    macros = re.findall(r"^#define (RPS3_[A-Z0-9_]+)[ \t]+(?:\\\n[ \t]*)?[(0-9]", text, re.M)
    body = re.sub(r"^#include .*$", "", text, flags=re.M)
    cc = os.environ.get("CC", "cc")
    pre = _sh([cc, "-E", "-P", "-U__GNUC__", "-x", "c", "-"], input=body)
    keep = [m for m in macros if m not in ("RPS3_H",)]
    return pre + "\n" + "".join(f"#define {m} ...\n" for m in keep)


include_dir, link = _where()
ffibuilder = FFI()
ffibuilder.cdef(_declarations(os.path.join(include_dir, "rps3.h")) + HELPER_DECLS)
ffibuilder.set_source(
    "rps3._rps3",
    '#include "rps3.h"\n' + HELPERS,
    include_dirs=[include_dir],
    extra_compile_args=["-std=c99"],
    **link,  # type: ignore[arg-type]
)

if __name__ == "__main__":
    ffibuilder.compile(verbose=True)
