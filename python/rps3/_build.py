"""cffi build script (API mode) of the extension rps3._rps3.

The declarations given to cffi are include/rps3.h itself, run through the C
preprocessor: no struct layout or prototype is written here, and cffi's
generated C code is compiled against the same header, so that a header
change either rebuilds consistently or fails to compile.

Where the library comes from (python/README.md, "Installing"):
  - RPS3_PREFIX set: an installed rps3 (`make install PREFIX=...`):
    PREFIX/include/rps3.h, linked against PREFIX/lib/librps3.so;
  - in the repository, with build/librps3-pic.a made (`make lib`, as
    `make venv` does) and newer than every file of src/ and include/:
    include/rps3.h, and that archive linked in (the objects of the shared
    library and of the runner's);
  - otherwise the library's C sources, compiled into the extension: the
    repository's src/ and include/, or their copy in an sdist (csrc/,
    written by setup.py's sdist command), with the flags the Makefile gives
    them (none of which changes a result: the same bits as the runner's).

Every build dependency that is missing (a C compiler, gsl-config and GSL's
headers, Python's headers, the library's sources) stops the build with a
message saying what to install, not a traceback.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sysconfig

from cffi import FFI

HERE = os.path.dirname(os.path.abspath(__file__))
PKG = os.path.dirname(HERE)  # python/, or the root of an unpacked sdist
ROOT = os.path.dirname(PKG)  # the repository, when built from it
VENDORED = os.path.join(PKG, "csrc")  # the sdist's copy of src/ and include/

# the library's compile flags (Makefile: OPT, KERNEL_FLAGS of the batch
# kernel, SIM_FLAGS of the simulation's path, -fvisibility=hidden of the
# shared objects), given here to every source: the kernel's and the
# simulation's flags change no result (no reassociation, no contraction),
# the others' code has no errno or trap to lose
LIB_FLAGS = ["-O2", "-fopenmp-simd", "-fno-math-errno", "-fno-trapping-math",
             "-ffp-contract=off", "-funroll-loops", "-fvisibility=hidden"]
LIB_MACROS = [("_POSIX_C_SOURCE", "200809L")]

GSL_HINT = ("install GSL's development files (Debian, Ubuntu: apt-get install "
            "libgsl-dev; Fedora: dnf install gsl-devel; macOS: brew install gsl; "
            "conda: conda install gsl), so that gsl-config is on PATH")


class BuildError(SystemExit):
    """A missing build dependency: pip prints the message, no traceback."""

    def __init__(self, message: str) -> None:
        super().__init__(f"rps3: cannot build the extension: {message}")


def _compiler() -> list[str]:
    """The C compiler setuptools will use (CC, else Python's own), checked
    to be on PATH."""
    cc = shlex.split(os.environ.get("CC") or sysconfig.get_config_var("CC") or "cc")
    if not cc or shutil.which(cc[0]) is None:
        name = cc[0] if cc else "cc"
        raise BuildError(
            f"no C compiler: {name!r} is not on PATH (it is $CC, or the compiler "
            "Python was built with); install one (Debian, Ubuntu: apt-get install "
            "gcc) or set CC to one")
    return cc


def _sh(cmd: list[str], **kw: object) -> str:
    return subprocess.run(cmd, check=True, capture_output=True, text=True,
                          **kw).stdout  # type: ignore[call-overload]


def _gsl(cc: list[str]) -> tuple[list[str], list[str]]:
    """GSL's compile and link flags from gsl-config, after checking that
    its headers are found."""
    if shutil.which("gsl-config") is None:
        raise BuildError(f"gsl-config is not on PATH: the library needs GSL; {GSL_HINT}")
    try:
        cflags = shlex.split(_sh(["gsl-config", "--cflags"]))
        libs = shlex.split(_sh(["gsl-config", "--libs"]))
    except (OSError, subprocess.CalledProcessError) as e:
        raise BuildError(f"gsl-config failed ({e}); {GSL_HINT}") from None
    probe = subprocess.run([*cc, *cflags, "-E", "-x", "c", "-"],
                           input="#include <gsl/gsl_multiroots.h>\n",
                           capture_output=True, text=True)
    if probe.returncode != 0:
        raise BuildError(f"GSL's headers are not found with gsl-config's flags "
                         f"{' '.join(cflags)!r}; {GSL_HINT}")
    return cflags, libs


def _python_headers() -> None:
    include = sysconfig.get_paths()["include"]
    if not os.path.isfile(os.path.join(include, "Python.h")):
        raise BuildError(
            f"Python's headers are missing ({include}/Python.h): install them "
            "(Debian, Ubuntu: apt-get install python3-dev; Fedora: dnf install "
            "python3-devel)")


def sources() -> str | None:
    """The directory holding the library's src/ and include/: the sdist's
    copy, else the repository's; None when neither is there."""
    for base in (VENDORED, ROOT):
        if (os.path.isfile(os.path.join(base, "include", "rps3.h"))
                and os.path.isdir(os.path.join(base, "src"))):
            return base
    return None


def _fresh(archive: str, dirs: list[str]) -> bool:
    """Whether the archive exists and is newer than every file of dirs: a
    stale one (sources edited since `make lib`) is not linked."""
    if not os.path.exists(archive):
        return False
    built = os.path.getmtime(archive)
    return all(os.path.getmtime(os.path.join(d, f)) <= built
               for d in dirs for f in os.listdir(d))


def _where(cc: list[str]) -> tuple[str, dict[str, list]]:
    """The header's directory and the arguments of set_source."""
    gsl_cflags, gsl = _gsl(cc)
    _python_headers()
    libs = [a[2:] for a in gsl if a.startswith("-l")]
    libdirs = [a[2:] for a in gsl if a.startswith("-L")]
    prefix = os.environ.get("RPS3_PREFIX")
    if prefix:
        lib = os.path.join(prefix, "lib")
        for need in (os.path.join(prefix, "include", "rps3.h"),
                     os.path.join(lib, "librps3.so")):
            if not os.path.exists(need):
                raise BuildError(
                    f"RPS3_PREFIX={prefix}: {need} is missing (install the "
                    f"library there with `make install PREFIX={prefix}`, or "
                    "unset RPS3_PREFIX to compile its sources)")
        # (setup.py's build_ext compiles at every build: no "depends")
        return os.path.join(prefix, "include"), {
            "libraries": ["rps3", *libs],
            "library_dirs": [lib, *libdirs],
            "runtime_library_dirs": [lib],
        }
    base = sources()
    if base is None:
        raise BuildError(
            f"the library's C sources are not here (neither {VENDORED} nor "
            f"{ROOT}/src and {ROOT}/include): build from the repository's "
            "python/ directory or from an sdist made by `python -m build`, or "
            "set RPS3_PREFIX to an installed rps3")
    include = os.path.join(base, "include")
    src = os.path.join(base, "src")
    archive = os.path.join(base, "build", "librps3-pic.a")
    if base == ROOT and _fresh(archive, [include, src]):
        return include, {
            "extra_objects": [archive],
            "libraries": libs,
            "library_dirs": libdirs,
        }
    # relative to setup.py's directory, as setuptools wants them
    rel = os.path.relpath(src, PKG)
    files = sorted(f for f in os.listdir(src) if f.endswith(".c"))
    return include, {
        "sources": [os.path.join(rel, f) for f in files],
        "include_dirs": [src, *(a[2:] for a in gsl_cflags if a.startswith("-I"))],
        "define_macros": LIB_MACROS,
        "extra_compile_args": LIB_FLAGS,
        "libraries": libs,
        "library_dirs": libdirs,
    }


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


def _declarations(header: str) -> str:
    """rps3.h as cffi's cdef takes it: preprocessed without the standard
    headers (cffi knows size_t) and without the visibility attribute, plus
    the header's integer macros as `#define NAME ...` (values from the
    compiler)."""
    text = open(header).read()
    macros = re.findall(r"^#define (RPS3_[A-Z0-9_]+)[ \t]+(?:\\\n[ \t]*)?[(0-9]", text, re.M)
    body = re.sub(r"^#include .*$", "", text, flags=re.M)
    pre = _sh([*CC, "-E", "-P", "-U__GNUC__", "-x", "c", "-"], input=body)
    keep = [m for m in macros if m not in ("RPS3_H",)]
    return pre + "\n" + "".join(f"#define {m} ...\n" for m in keep)


CC = _compiler()
include_dir, link = _where(CC)
ffibuilder = FFI()
ffibuilder.cdef(_declarations(os.path.join(include_dir, "rps3.h")) + HELPER_DECLS)
ffibuilder.set_source(
    "rps3._rps3",
    '#include "rps3.h"\n' + HELPERS,
    include_dirs=[include_dir, *link.pop("include_dirs", [])],
    extra_compile_args=["-std=c99", *link.pop("extra_compile_args", [])],
    **link,
)

if __name__ == "__main__":
    ffibuilder.compile(verbose=True)
