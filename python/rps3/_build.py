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

import json
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


# ------------------------------------------------------------------------
# Loops over points and over a simulation's output times for the modules
# dynamics, velocity, sim and control (one C call per Python call; the
# library's stages are called per point exactly as in the library's own
# batch loops), and the entry point of controllers written in Python.
# Each *_n loop computes point i from component-major inputs (component c
# at [c * n + i]) into component-major outputs, NaN and its status for a
# point that fails, and keeps the first failure's message, "point I: ...".
HELPERS += r"""
#include <stdio.h> /* snprintf */
static void rps3py_nan(double *a, size_t rows, size_t n, size_t i) {
  size_t r;
  if (a == NULL) return;
  for (r = 0; r < rows; r++) a[r * n + i] = (double)NAN;
}
static void rps3py_put(double *a, const double *v, size_t rows, size_t n,
                       size_t i) {
  size_t r;
  if (a == NULL) return;
  for (r = 0; r < rows; r++) a[r * n + i] = v[r];
}
static void rps3py_get(double *v, const double *a, size_t n, size_t i) {
  size_t r;
  for (r = 0; r < 3; r++) v[r] = a[r * n + i];
}
static void rps3py_fail(const rps3_data *d, size_t i, int st, size_t *nfail,
                        char *msg, size_t msgsz) {
  if ((*nfail)++ == 0)
    snprintf(msg, msgsz, "point %lu: %s", (unsigned long)i,
             d->err.msg[0] ? d->err.msg : rps3_strerror(st));
}

static size_t rps3py_fwddyn_n(const rps3_model *m, rps3_data *d, size_t n,
    const double *l, const double *dl, const double *F, double *ddl,
    double *pose, double *dpose, double *theta, double *dtheta,
    double *ddtheta, double *Mq, double *hq, double *Mcond, double *T,
    double *P, int *mode, int *status, char *msg, size_t msgsz) {
  size_t i, nfail = 0;
  for (i = 0; i < n; i++) {
    double e[2];
    int st;
    rps3py_get(d->l, l, n, i);
    rps3py_get(d->dl, dl, n, i);
    rps3py_get(d->F, F, n, i);
    d->err.msg[0] = 0;
    st = rps3_fwddyn(m, d);
    if (st == RPS3_OK) st = rps3_energy(m, d, &e[0], &e[1], NULL);
    status[i] = st;
    mode[i] = d->mode;
    if (st != RPS3_OK) {
      rps3py_fail(d, i, st, &nfail, msg, msgsz);
      rps3py_nan(ddl, 3, n, i); rps3py_nan(pose, 3, n, i);
      rps3py_nan(dpose, 3, n, i); rps3py_nan(theta, 3, n, i);
      rps3py_nan(dtheta, 3, n, i); rps3py_nan(ddtheta, 3, n, i);
      rps3py_nan(Mq, 9, n, i); rps3py_nan(hq, 3, n, i);
      rps3py_nan(Mcond, 1, n, i); rps3py_nan(T, 1, n, i);
      rps3py_nan(P, 1, n, i);
      continue;
    }
    rps3py_put(ddl, d->ddl, 3, n, i); rps3py_put(pose, d->pose, 3, n, i);
    rps3py_put(dpose, d->dpose, 3, n, i);
    rps3py_put(theta, d->theta, 3, n, i);
    rps3py_put(dtheta, d->dtheta, 3, n, i);
    rps3py_put(ddtheta, d->ddtheta, 3, n, i);
    rps3py_put(Mq, &d->Mq[0][0], 9, n, i); rps3py_put(hq, d->hq, 3, n, i);
    rps3py_put(Mcond, &d->Mcond, 1, n, i);
    rps3py_put(T, &e[0], 1, n, i); rps3py_put(P, &e[1], 1, n, i);
  }
  return nfail;
}

/* pose (+ rates, + accelerations) -> the joint and Cartesian motion:
   rps3_ik, rps3_velocity, rps3_acceleration (dpose, ddpose may be NULL) */
static size_t rps3py_velocity_n(const rps3_model *m, rps3_data *d, size_t n,
    const double *pose, const double *dpose, const double *ddpose,
    double *l, double *theta, double *c, double *dl, double *dtheta,
    double *vc, double *omega, double *ddl, double *ddtheta, double *ac,
    double *domega, double *omega_body, double *transform, int *status,
    char *msg, size_t msgsz) {
  size_t i, nfail = 0;
  for (i = 0; i < n; i++) {
    double T[4][4], wb[3];
    int st;
    rps3py_get(d->pose, pose, n, i);
    d->err.msg[0] = 0;
    st = rps3_ik(m, d);
    if (st == RPS3_OK && dpose != NULL) {
      rps3py_get(d->dpose, dpose, n, i);
      st = rps3_velocity(m, d);
    }
    if (st == RPS3_OK && dpose != NULL && ddpose != NULL) {
      rps3py_get(d->ddpose, ddpose, n, i);
      st = rps3_acceleration(m, d);
    }
    status[i] = st;
    if (st != RPS3_OK) {
      rps3py_fail(d, i, st, &nfail, msg, msgsz);
      rps3py_nan(l, 3, n, i); rps3py_nan(theta, 3, n, i);
      rps3py_nan(c, 3, n, i); rps3py_nan(dl, 3, n, i);
      rps3py_nan(dtheta, 3, n, i); rps3py_nan(vc, 3, n, i);
      rps3py_nan(omega, 3, n, i); rps3py_nan(ddl, 3, n, i);
      rps3py_nan(ddtheta, 3, n, i); rps3py_nan(ac, 3, n, i);
      rps3py_nan(domega, 3, n, i); rps3py_nan(omega_body, 3, n, i);
      rps3py_nan(transform, 16, n, i);
      continue;
    }
    rps3py_put(l, d->l, 3, n, i); rps3py_put(theta, d->theta, 3, n, i);
    rps3py_put(c, d->c, 3, n, i);
    rps3_transform(d, T);
    rps3py_put(transform, &T[0][0], 16, n, i);
    if (dpose != NULL) {
      rps3py_put(dl, d->dl, 3, n, i); rps3py_put(dtheta, d->dtheta, 3, n, i);
      rps3py_put(vc, d->vc, 3, n, i); rps3py_put(omega, d->omega, 3, n, i);
      rps3_omega_paper(m, d, wb);
      rps3py_put(omega_body, wb, 3, n, i);
    }
    if (dpose != NULL && ddpose != NULL) {
      rps3py_put(ddl, d->ddl, 3, n, i);
      rps3py_put(ddtheta, d->ddtheta, 3, n, i);
      rps3py_put(ac, d->ac, 3, n, i); rps3py_put(domega, d->domega, 3, n, i);
    }
  }
  return nfail;
}

/* lengths (+ rates, + accelerations) -> the platform's motion: rps3_fk,
   rps3_joint_velocity, rps3_joint_acceleration (dl, ddl may be NULL) */
static size_t rps3py_joint_velocity_n(const rps3_model *m, rps3_data *d,
    size_t n, const double *l, const double *dl, const double *ddl,
    double *pose, double *theta, double *c, double *dpose, double *dtheta,
    double *vc, double *omega, double *ddtheta, double *ac, double *domega,
    int *status, char *msg, size_t msgsz) {
  size_t i, nfail = 0;
  for (i = 0; i < n; i++) {
    int st;
    rps3py_get(d->l, l, n, i);
    d->err.msg[0] = 0;
    st = rps3_fk(m, d);
    if (st == RPS3_OK && dl != NULL) {
      rps3py_get(d->dl, dl, n, i);
      st = rps3_joint_velocity(m, d);
    }
    if (st == RPS3_OK && dl != NULL && ddl != NULL) {
      rps3py_get(d->ddl, ddl, n, i);
      st = rps3_joint_acceleration(m, d);
    }
    status[i] = st;
    if (st != RPS3_OK) {
      rps3py_fail(d, i, st, &nfail, msg, msgsz);
      rps3py_nan(pose, 3, n, i); rps3py_nan(theta, 3, n, i);
      rps3py_nan(c, 3, n, i); rps3py_nan(dpose, 3, n, i);
      rps3py_nan(dtheta, 3, n, i); rps3py_nan(vc, 3, n, i);
      rps3py_nan(omega, 3, n, i); rps3py_nan(ddtheta, 3, n, i);
      rps3py_nan(ac, 3, n, i); rps3py_nan(domega, 3, n, i);
      continue;
    }
    rps3py_put(pose, d->pose, 3, n, i); rps3py_put(theta, d->theta, 3, n, i);
    rps3py_put(c, d->c, 3, n, i);
    if (dl != NULL) {
      rps3py_put(dpose, d->dpose, 3, n, i);
      rps3py_put(dtheta, d->dtheta, 3, n, i);
      rps3py_put(vc, d->vc, 3, n, i); rps3py_put(omega, d->omega, 3, n, i);
    }
    if (dl != NULL && ddl != NULL) {
      rps3py_put(ddtheta, d->ddtheta, 3, n, i);
      rps3py_put(ac, d->ac, 3, n, i); rps3py_put(domega, d->domega, 3, n, i);
    }
  }
  return nfail;
}

/* the rate maps at a pose as matrices: column k of each is rps3_velocity's
   output for the unit rate of pose coordinate k (the maps are linear in
   dpose); J[r][k] of point i at [(r * 3 + k) * n + i] */
static size_t rps3py_jacobian_n(const rps3_model *m, rps3_data *d, size_t n,
    const double *pose, double *Jl, double *Jtheta, double *Jvc,
    double *Jomega, int *status, char *msg, size_t msgsz) {
  size_t i, nfail = 0;
  for (i = 0; i < n; i++) {
    int st, k, r;
    rps3py_get(d->pose, pose, n, i);
    d->err.msg[0] = 0;
    st = rps3_ik(m, d);
    for (k = 0; k < 3 && st == RPS3_OK; k++) {
      d->dpose[0] = d->dpose[1] = d->dpose[2] = 0.0;
      d->dpose[k] = 1.0;
      st = rps3_velocity(m, d);
      if (st != RPS3_OK) break;
      for (r = 0; r < 3; r++) {
        size_t at = ((size_t)r * 3 + (size_t)k) * n + i;
        Jl[at] = d->dl[r];
        Jtheta[at] = d->dtheta[r];
        Jvc[at] = d->vc[r];
        Jomega[at] = d->omega[r];
      }
    }
    status[i] = st;
    if (st != RPS3_OK) {
      rps3py_fail(d, i, st, &nfail, msg, msgsz);
      rps3py_nan(Jl, 9, n, i); rps3py_nan(Jtheta, 9, n, i);
      rps3py_nan(Jvc, 9, n, i); rps3py_nan(Jomega, 9, n, i);
    }
  }
  return nfail;
}

/* outputs of rps3py_sim_run, component-major over the n output times */
typedef struct {
  double *l, *dl, *pose, *dpose, *F, *F_cmd, *l_meas, *dl_meas, *l_des,
      *dl_des, *T, *P, *W, *residual;
  int *status;
} rps3py_sim_out;

static void rps3py_sim_record(const rps3_sim *s, const rps3_ctrl *ctrl,
                              size_t n, size_t i, rps3py_sim_out *o) {
  double w[2];
  w[0] = rps3_sim_now(s)->y[6];
  w[1] = rps3_sim_now(s)->y[7];
  rps3py_put(o->l, rps3_sim_now(s)->y, 3, n, i);
  rps3py_put(o->dl, rps3_sim_now(s)->y + 3, 3, n, i);
  rps3py_put(o->pose, rps3_sim_data(s)->pose, 3, n, i);
  rps3py_put(o->dpose, rps3_sim_data(s)->dpose, 3, n, i);
  rps3py_put(o->F, rps3_sim_now(s)->F, 3, n, i);
  rps3py_put(o->F_cmd, rps3_sim_now(s)->F_cmd, 3, n, i);
  rps3py_put(o->l_meas, rps3_sim_now(s)->l_meas, 3, n, i);
  rps3py_put(o->dl_meas, rps3_sim_now(s)->dl_meas, 3, n, i);
  if (rps3_sim_now(s)->nsteps == 0 && rps3_sim_now(s)->nticks == 0) {
    /* the start, before any advance: no force commanded yet (NaN, as the
       runner writes it) */
    rps3py_nan(o->F, 3, n, i); rps3py_nan(o->F_cmd, 3, n, i);
    rps3py_nan(o->l_meas, 3, n, i); rps3py_nan(o->dl_meas, 3, n, i);
    rps3py_nan(o->l_des, 3, n, i); rps3py_nan(o->dl_des, 3, n, i);
  } else if (ctrl != NULL) {
    double l_des[3], dl_des[3];
    rps3_ctrl_last(ctrl, NULL, l_des, dl_des, NULL);
    rps3py_put(o->l_des, l_des, 3, n, i);
    rps3py_put(o->dl_des, dl_des, 3, n, i);
  } else {
    rps3py_nan(o->l_des, 3, n, i); rps3py_nan(o->dl_des, 3, n, i);
  }
  rps3py_put(o->T, &rps3_sim_now(s)->T, 1, n, i); rps3py_put(o->P, &rps3_sim_now(s)->P, 1, n, i);
  rps3py_put(o->W, w, 2, n, i);
  rps3py_put(o->residual, &rps3_sim_now(s)->energy_residual, 1, n, i);
  o->status[i] = RPS3_OK;
}

/* the run through the output times t[0..n) (increasing, t[0] >= rps3_sim_now(s)->t):
   rps3_sim_advance to each, the state recorded there; a time equal to
   rps3_sim_now(s)->t records the state without advancing.  After a failure the times
   past it hold NaN and the status.  Returns the number of times reached */
static size_t rps3py_sim_run(rps3_sim *s, const rps3_controller *c,
                             const rps3_ctrl *ctrl, size_t n,
                             const double *t, rps3py_sim_out *o) {
  size_t i, done = 0;
  int st = rps3_sim_now(s)->status;
  for (i = 0; i < n; i++) {
    if (st == RPS3_OK && t[i] > rps3_sim_now(s)->t) st = rps3_sim_advance(s, c, t[i]);
    if (st != RPS3_OK) break;
    rps3py_sim_record(s, ctrl, n, i, o);
    done++;
  }
  for (; i < n; i++) {
    rps3py_nan(o->l, 3, n, i); rps3py_nan(o->dl, 3, n, i);
    rps3py_nan(o->pose, 3, n, i); rps3py_nan(o->dpose, 3, n, i);
    rps3py_nan(o->F, 3, n, i); rps3py_nan(o->F_cmd, 3, n, i);
    rps3py_nan(o->l_meas, 3, n, i); rps3py_nan(o->dl_meas, 3, n, i);
    rps3py_nan(o->l_des, 3, n, i); rps3py_nan(o->dl_des, 3, n, i);
    rps3py_nan(o->T, 1, n, i); rps3py_nan(o->P, 1, n, i);
    rps3py_nan(o->W, 2, n, i); rps3py_nan(o->residual, 1, n, i);
    o->status[i] = st;
  }
  return done;
}

/* a constant force law: state points to three forces [N] */
static int rps3py_constant_force(void *state, double t, const double l[3],
                                 const double dl[3], double F[3]) {
  const double *f = (const double *)state;
  (void)t; (void)l; (void)dl;
  F[0] = f[0]; F[1] = f[1]; F[2] = f[2];
  return RPS3_OK;
}

/* controllers written in Python: the extension's C entry point */
static int rps3py_control_py(void *, double, const double *, const double *,
                             double *);
static rps3_control_fn rps3py_control_py_fn(void) {
  return rps3py_control_py;
}
static rps3_control_fn rps3py_constant_force_fn(void) {
  return rps3py_constant_force;
}
static rps3_control_fn rps3py_ctrl_update_fn(void) {
  return rps3_ctrl_update;
}
"""

HELPER_DECLS += """
size_t rps3py_fwddyn_n(const rps3_model *m, rps3_data *d, size_t n,
    const double *l, const double *dl, const double *F, double *ddl,
    double *pose, double *dpose, double *theta, double *dtheta,
    double *ddtheta, double *Mq, double *hq, double *Mcond, double *T,
    double *P, int *mode, int *status, char *msg, size_t msgsz);
size_t rps3py_velocity_n(const rps3_model *m, rps3_data *d, size_t n,
    const double *pose, const double *dpose, const double *ddpose,
    double *l, double *theta, double *c, double *dl, double *dtheta,
    double *vc, double *omega, double *ddl, double *ddtheta, double *ac,
    double *domega, double *omega_body, double *transform, int *status,
    char *msg, size_t msgsz);
size_t rps3py_joint_velocity_n(const rps3_model *m, rps3_data *d,
    size_t n, const double *l, const double *dl, const double *ddl,
    double *pose, double *theta, double *c, double *dpose, double *dtheta,
    double *vc, double *omega, double *ddtheta, double *ac, double *domega,
    int *status, char *msg, size_t msgsz);
size_t rps3py_jacobian_n(const rps3_model *m, rps3_data *d, size_t n,
    const double *pose, double *Jl, double *Jtheta, double *Jvc,
    double *Jomega, int *status, char *msg, size_t msgsz);
typedef struct {
  double *l, *dl, *pose, *dpose, *F, *F_cmd, *l_meas, *dl_meas, *l_des,
      *dl_des, *T, *P, *W, *residual;
  int *status;
} rps3py_sim_out;
size_t rps3py_sim_run(rps3_sim *s, const rps3_controller *c,
                      const rps3_ctrl *ctrl, size_t n, const double *t,
                      rps3py_sim_out *o);
extern "Python" int rps3py_control_py(void *, double, const double *,
                                    const double *, double *);
rps3_control_fn rps3py_control_py_fn(void);
rps3_control_fn rps3py_constant_force_fn(void);
rps3_control_fn rps3py_ctrl_update_fn(void);
"""


# where the runner rps3-run of this build is (rps3.scene.find_runner): the
# installed prefix's bin/, or the repository's build/; read at run time,
# and skipped when it does not exist there
_RUNNER_HINT = (os.path.join(os.environ["RPS3_PREFIX"], "bin", "rps3-run")
                if os.environ.get("RPS3_PREFIX")
                else os.path.join(ROOT, "build", "rps3-run"))
HELPERS += ("static const char *rps3py_runner_hint(void) { return "
            + json.dumps(_RUNNER_HINT) + "; }\n")
HELPER_DECLS += "const char *rps3py_runner_hint(void);\n"


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
