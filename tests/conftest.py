"""Fixtures for the Python tests: the runner, and runs of the configs.

The tests write with the C runner (build/rps3-run) and read with h5py,
the rps3 package (installed into .venv by `make venv`) and xarray.  `make check-py` builds the runner first.
"""

import importlib.util
import os
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RUNNER = os.path.join(ROOT, "build", "rps3-run")
CONFIGS = os.path.join(ROOT, "configs")
ANALYSIS = os.path.join(ROOT, "analysis")
BAD_SCENES = os.path.join(ROOT, "tests", "bad_scenes")



def script(name):
    """The analysis script analysis/NAME.py as a module (its main() not
    run), for tests of its functions."""
    spec = importlib.util.spec_from_file_location(
        name, os.path.join(ANALYSIS, name + ".py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def run(scene, out=None, *args, timeout=60, **kw):
    """Run rps3-run on `scene` (into `out`), return the CompletedProcess."""
    cmd = [RUNNER, str(scene)] + (["-o", str(out)] if out else []) + list(args)
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout,
                          **kw)


@pytest.fixture(scope="session")
def runner():
    if not os.access(RUNNER, os.X_OK):
        pytest.fail(f"{RUNNER} is missing: run `make runner` first")
    return RUNNER


#: configs that are a study behind a make target (make ident-mc), too long
#: for the tests: not run by config_runs (their small versions are tested)
STUDY_CONFIGS = {"ident_mc.yaml", "ident_general_mc.yaml"}


@pytest.fixture(scope="session")
def config_runs(runner, tmp_path_factory):
    """Every configs/*.yaml run once: {name: (path of the .h5, process)}."""
    out = tmp_path_factory.mktemp("configs")
    runs = {}
    for name in sorted(os.listdir(CONFIGS)):
        if name.endswith(".yaml") and name not in STUDY_CONFIGS:
            h5 = out / name.replace(".yaml", ".h5")
            runs[name[:-5]] = (h5, run(os.path.join(CONFIGS, name), h5, "-q"))
    return runs


@pytest.fixture(scope="session")
def paper_h5(config_runs):
    h5, proc = config_runs["paper"]
    assert proc.returncode == 0, proc.stderr
    return h5


def write_scene(path, text):
    path.write_text(text)
    return path


FAILING_SINE = """\
manipulator: {R: 0.2286, rho: 0.5, M: 0.18, m: 0.09, d: 0.1524}
trajectory:
  kind: sine
  mean: [0, 0.05, 0.15]
  amp: [0.3, 0, 0.05]
  freq: [0.5, 0, 0.5]
  duration: 2
  samples: SAMPLES
solver: {theta: THETA}
sweep:
  trajectory.amp[2]: [0.05, 0.2, 0.1]
"""


def failing_sine(samples=201, theta="closed_form"):
    """Three cases; the middle one drives the platform below the base."""
    return FAILING_SINE.replace("SAMPLES", str(samples)).replace("THETA", theta)


def run_tmp(out, pid, rank=0):
    """The temporary file rps3-run process `pid` writes for `out` outside a
    Slurm job (runner/core/tmpout.h): OUT.tmp.HOST.PID.jobnone.rankR."""
    import re
    import socket
    host = re.sub(r"[^A-Za-z0-9_-]", "_",
                  socket.gethostname().split(".")[0]) or "unknown"
    return out.parent / f"{out.name}.tmp.{host}.{pid}.jobnone.rank{rank}"
