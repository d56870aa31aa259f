"""CF conventions on a runner file, inverse dynamics and simulation alike:
every variable has a long_name and units that UDUNITS-2 parses (through
cf-units), status has flag_values and flag_meanings covering every
rps3_status, warn its flag_masks, the root Conventions, git_revision and a
history line per program that wrote the file (merge appends its own)."""

import subprocess

import cf_units
import h5py
import numpy as np
import pytest
import rps3
from conftest import ROOT, RUNNER, run, write_scene
from rps3 import h5io

# a sweep with the kinds of coordinates a file can have: a component of a
# list key, an enum, an integer, and a span that differs between cases
# (case_time)
SCENE = """\
manipulator: {R: 0.2286, rho: 0.5, M: 0.18, m: 0.09, d: 0.1524}
trajectory: {kind: sine, mean: [0, 0.05, 0.15], amp: [0.3, 0, 0.05],
             freq: [0.5, 0, 0.5], duration: 2, samples: 11}
sweep:
  trajectory.amp[2]: [0.05, 0.2]
  solver.method: [lagrange, newton_euler]
  solver.max_iter: [10, 20]
  trajectory.samples: [11, 21]
"""


# a simulated sweep (runner/sim_output.c) with the same kinds of
# coordinates: amp 0.4 drives z_c below reach, so that those cases fail
SIM_SCENE = """\
manipulator: {R: 0.2286, rho: 0.5, M: 0.18, m_over_M: 0.5, d: 0.1524}
trajectory: {kind: sine, mean: [0.31, 0.21, 0.30], amp: [1.03, 0.083, 0.029],
             freq: [1.07, 2.03, 3.01], phase: [0, 0, 3.1416], duration: 0.1,
             dt: 0.01}
simulate: {controller: pd_gravity, rate: 1000, h: 0.001}
sweep:
  trajectory.amp[2]: [0.029, 0.4]
  simulate.controller: [pd, computed_torque]
  trajectory.duration: [0.1, 0.15]
"""


@pytest.fixture(scope="module")
def sim_file(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("cfsim")
    scene = write_scene(tmp / "sim.yaml", SIM_SCENE)
    out = tmp / "sim.h5"
    proc = run(scene, out, "-q")
    assert proc.returncode == 1, proc.stderr          # amp 0.4 fails
    return scene, out


@pytest.fixture(scope="module")
def cf_file(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("cf")
    scene = write_scene(tmp / "s.yaml", SCENE)
    out = tmp / "s.h5"
    proc = run(scene, out, "-q")
    assert proc.returncode == 1, proc.stderr          # amp 0.2 fails
    return scene, out


def variables(f):
    out = {}
    f.visititems(lambda n, o: out.__setitem__(n, o)
                 if isinstance(o, h5py.Dataset) else None)
    return out


def check_variables(f):
    """Every variable's long_name and UDUNITS units; the variables by name."""
    names = variables(f)
    for name, ds in names.items():
        long_name = h5io.text(ds.attrs["long_name"])
        assert len(long_name) >= 4 and "\n" not in long_name, name
        units = h5io.text(ds.attrs["units"])
        u = cf_units.Unit(units)          # raises when UDUNITS cannot
        assert not u.is_no_unit() and not u.is_unknown(), (name, units)
    # the component of a list key has that component's unit
    assert h5io.text(f["trajectory.amp[2]"].attrs["units"]) == "m"
    return names


def check_status(st):
    """status: flag_values and flag_meanings of every rps3_status and
    "not computed"; the file's statuses among them."""
    values = st.attrs["flag_values"]
    meanings = h5io.text(st.attrs["flag_meanings"]).split()
    assert values.dtype == st.dtype and len(values) == len(meanings)
    assert len(set(meanings)) == len(meanings)
    codes = [v for v in range(-100, 100)
             if rps3.strerror(v) != "unknown status"]
    assert sorted(codes + [-1000]) == sorted(values.tolist())
    assert meanings[list(values).index(0)] == "ok"
    assert meanings[list(values).index(-1000)] == "not_computed"
    assert set(st[()].tolist()) <= set(values.tolist())


def check_root(f, rev):
    """Conventions, git_revision and the one history line of the program
    that wrote the file; the history."""
    assert h5io.text(f.attrs["Conventions"]) == "CF-1.10"
    git = h5io.text(f.attrs["git_revision"])
    if rev.returncode == 0:
        assert git.startswith(rev.stdout.strip()), (git, rev.stdout)
    history = h5io.text(f.attrs["history"]).splitlines()
    assert len(history) == 1
    version = h5io.text(f.attrs["rps3_version"])
    assert history[0].endswith(f"(rps3 {version}, git {git})")
    assert h5io.text(f.attrs["command_line"]) in history[0]
    return history


def git_describe():
    return subprocess.run(["git", "describe", "--always", "--abbrev=12"],
                          cwd=ROOT, capture_output=True, text=True)


def test_every_variable_has_long_name_and_udunits(cf_file):
    _, out = cf_file
    with h5py.File(out, "r") as f:
        names = check_variables(f)
        assert {"case_time", "trajectory.amp[2]", "solver.method",
                "status", "warn", "force"} <= names.keys()
        assert cf_units.Unit(h5io.text(f["length_accel"].attrs["units"])) \
            == cf_units.Unit("m s-2")


def test_status_and_warn_flags(cf_file):
    _, out = cf_file
    with h5py.File(out, "r") as f:
        check_status(f["status"])
        w = f["warn"]
        masks = w.attrs["flag_masks"]
        assert masks.tolist() == [1, 2, 4, 8]
        assert len(h5io.text(w.attrs["flag_meanings"]).split()) == 4
        assert np.all(w[()] < 16)


def test_conventions_history_and_revision(cf_file, tmp_path):
    scene, out = cf_file
    with h5py.File(out, "r") as f:
        check_root(f, git_describe())
    # merge: the part's history, then a line of its own (the sweep is one
    # job: one shard)
    parts = [tmp_path / "p0.h5"]
    assert run(scene, parts[0], "-q", "--shard", "0/1").returncode == 1
    for copy in ([], ["--copy"]):
        merged = tmp_path / f"m{len(copy)}.h5"
        proc = subprocess.run([RUNNER, "merge", str(merged)] +
                              [str(p) for p in parts] + copy,
                              capture_output=True, text=True, timeout=60)
        assert proc.returncode == 1, proc.stderr
        with h5py.File(merged, "r") as f:
            lines = h5io.text(f.attrs["history"]).splitlines()
            assert len(lines) == 2, lines
            assert "--shard 0/1" in lines[0] and " merge " in lines[1]
            assert h5io.text(f.attrs["Conventions"]) == "CF-1.10"


def test_simulation_file(sim_file):
    """The file of a simulated scene: the same conventions, its status
    (the rps3_status that stopped a case) under the same flags."""
    _, out = sim_file
    with h5py.File(out, "r") as f:
        names = check_variables(f)
        assert {"case_time", "trajectory.amp[2]", "simulate.controller",
                "trajectory.duration", "status", "force", "scene",
                "kinetic_energy", "message"} <= names.keys()
        assert h5io.text(f["trajectory.duration"].attrs["units"]) == "s"
        assert cf_units.Unit(h5io.text(f["length_rate"].attrs["units"])) \
            == cf_units.Unit("m s-1")
        check_status(f["status"])
        statuses = set(f["status"][()].tolist())
        assert 0 in statuses and len(statuses) > 1  # some cases failed
        check_root(f, git_describe())
        assert h5io.text(f.attrs["content"]) == "simulation"
