"""CF conventions on a runner file, inverse dynamics and simulation alike:
every variable has a long_name and units that UDUNITS-2 parses (through
cf-units), status has flag_values and flag_meanings covering every
rps3_status, warn its flag_masks, the root Conventions, git_revision and a
history line per program that wrote the file (merge appends its own).

And every kind of file the runner and rps3-study write (a sweep on a shared
time grid and one whose grid differs by case, a simulation of each, a part,
its join by virtual datasets and by copy, the two study files) passes IOOS
compliance-checker's CF-1.10 checks without an error, offline; its
warnings are the ones docs/hdf5.md explains."""

import os
import socket
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


# a simulated sweep (runner/exec/simulate.c) with the same kinds of
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
    out = tmp / "sim.nc"
    proc = run(scene, out, "-q")
    assert proc.returncode == 1, proc.stderr          # amp 0.4 fails
    return scene, out


@pytest.fixture(scope="module")
def cf_file(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("cf")
    scene = write_scene(tmp / "s.yaml", SCENE)
    out = tmp / "s.nc"
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
    assert h5io.text(f["trajectory__amp_2"].attrs["units"]) == "m"
    # a swept key's variable: its CF name, the dotted key in scene_key
    for key in h5io.sweep_keys(f):
        ds = f[h5io.key_name(key)]
        assert h5io.text(ds.attrs["scene_key"]) == key
        assert key in h5io.text(ds.attrs["long_name"])
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
        assert {"case_time", "trajectory__amp_2", "solver__method",
                "status", "warn", "force"} <= names.keys()
        assert h5io.sweep_keys(f) == ["trajectory.amp[2]", "solver.method",
                                      "solver.max_iter", "trajectory.samples"]
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
        assert {"case_time", "trajectory__amp_2", "simulate__controller",
                "trajectory__duration", "status", "force", "scene",
                "kinetic_energy", "message"} <= names.keys()
        assert h5io.text(f["trajectory__duration"].attrs["units"]) == "s"
        assert cf_units.Unit(h5io.text(f["length_rate"].attrs["units"])) \
            == cf_units.Unit("m s-1")
        check_status(f["status"])
        statuses = set(f["status"][()].tolist())
        assert 0 in statuses and len(statuses) > 1  # some cases failed
        check_root(f, git_describe())
        assert h5io.text(f.attrs["content"]) == "simulation"


def test_coordinates_name_variables_of_the_file(cf_file, sim_file, paper_h5,
                                                config_runs):
    """Every name of every coordinates attribute is a variable of the file
    whose dimensions are among the variable's (CF 5): case_time on the
    per-sample variables of a file whose grid differs, never on the
    per-case ones, and never in a file on one grid (a simulation on one
    grid listed it)."""
    closed_loop, _ = config_runs["closed_loop"]
    for path in (cf_file[1], sim_file[1], paper_h5, closed_loop):
        with h5py.File(path, "r") as f:
            differs = "sample" in f
            for name, ds in variables(f).items():
                coords = h5io.text(ds.attrs.get("coordinates", "")).split()
                for c in coords:
                    assert c in f, (path, name, c)
                    assert set(h5io.dims(f[c])) <= set(h5io.dims(ds)), \
                        (path, name, c)
                if "coordinates" in ds.attrs:
                    assert ("case_time" in coords) == \
                        (differs and ds.ndim >= 2), (path, name)


def test_time_axis(paper_h5, cf_file):
    """On one grid `time` is a CF time coordinate in seconds (a nominal
    reference date); when the grid differs, the samples' dimension is
    `sample`, an index, and case_time holds the seconds."""
    with h5py.File(paper_h5, "r") as f:
        t = f["time"]
        assert h5io.text(t.attrs["standard_name"]) == "time"
        u = cf_units.Unit(h5io.text(t.attrs["units"]),
                          calendar=h5io.text(t.attrs["calendar"]))
        assert u.is_time_reference() and u.is_convertible(
            cf_units.Unit("days since 2000-01-01",
                          calendar="proleptic_gregorian"))
        assert t[0] == 0 and t[-1] == 10.0       # the seconds, as before
    with h5py.File(cf_file[1], "r") as f:
        assert "time" not in f and h5io.dims(f["force"])[1] == "sample"
        assert f["sample"][()].tolist() == list(range(f["sample"].shape[0]))
        assert h5io.text(f["case_time"].attrs["units"]) == "s"


# ------------------------------------------------ compliance-checker CF-1.10

# the warnings the files keep (docs/hdf5.md, "CF"): the cases' dimension
# comes before time, so that a case's samples are contiguous
ALLOWED_WARNINGS = ("§2.4 Dimensions",)
# the checker's own exception on a coordinate variable of strings (effect,
# trajectory): it subtracts neighbours to check monotonicity
ALLOWED_EXCEPTIONS = ("check_coordinate_variables_strict_monotonicity",)


def compliance(path, tmp_path):
    """compliance-checker --test=cf:1.10 PATH, in this process with no
    network: (errors, warnings, exceptions) as lists of strings."""
    from compliance_checker.suite import CheckSuite
    CheckSuite.load_all_available_checkers()
    suite = CheckSuite()
    ds = suite.load_dataset(str(path))
    try:
        groups, exceptions = suite.run_all(ds, ["cf:1.10"])["cf:1.10"]
    finally:
        ds.close()
    # limit 3: every priority, as `compliance-checker --criteria lenient`
    res = suite.build_structure("cf:1.10", groups, str(path), limit=3)

    def msgs(group):
        return [f"{r.name}: {m}" for r in res[group] for m in r.msgs]
    exc = [f"{name}: {err[0]}" for name, err in exceptions.items()]
    return msgs("high_priorities"), msgs("medium_priorities") + \
        msgs("low_priorities"), exc


@pytest.fixture
def offline(monkeypatch, tmp_path):
    """No connection can be made, and no table cached in the home: the
    checker uses the standard-name table of its own package (it downloads
    one only for a file whose standard_name_vocabulary names another)."""
    def refuse(*args, **kwargs):
        raise OSError("network access in a test")
    monkeypatch.setattr(socket.socket, "connect", refuse)
    monkeypatch.setattr(socket, "create_connection", refuse)
    monkeypatch.setenv("XDG_DATA_HOME", str(tmp_path / "xdg"))
    monkeypatch.setenv("HOME", str(tmp_path / "home"))


@pytest.fixture(scope="module")
def file_kinds(cf_file, sim_file, runner, tmp_path_factory):
    """{kind: path} of every kind of file, named .nc (the checker wants
    the suffix; the runner writes any name)."""
    tmp = tmp_path_factory.mktemp("kinds")
    kinds = {}

    def runner_file(kind, text, *args, code=0):
        scene = write_scene(tmp / f"{kind}.yaml", text)
        out = tmp / f"{kind}.nc"
        proc = run(scene, out, "-q", *args)
        assert proc.returncode == code, proc.stderr
        kinds[kind] = out
        return scene

    kinds["sweep_grid_differs"] = cf_file[1]
    kinds["simulation_grid_differs"] = sim_file[1]
    runner_file("sweep_one_grid", SCENE.replace("trajectory.samples: [11, 21]",
                                                "manipulator.rho: [0.4, 0.5]"),
                code=1)
    runner_file("sweep_no_sweep", SCENE.split("sweep:")[0])
    runner_file("simulation_one_grid", SIM_SCENE.replace(
        "trajectory.duration: [0.1, 0.15]", "simulate.rate: [1000, 2000]"),
        code=1)
    # shards of a sweep of two jobs, joined by virtual datasets and copied
    big = write_scene(tmp / "big.yaml", SCENE.split("sweep:")[0] +
                      "sweep:\n  manipulator.rho: {from: 0.3, to: 0.6, num: 20}"
                      "\n  trajectory.samples: [11, 21]\n")
    parts = [tmp / f"part{k}.nc" for k in range(2)]
    for k, part in enumerate(parts):
        proc = run(big, part, "-q", "--shard", f"{k}/2")
        assert proc.returncode == 0, proc.stderr
    kinds["part"] = parts[0]
    for kind, extra in (("joined", []), ("merged", ["--copy"])):
        out = tmp / f"{kind}.nc"
        proc = subprocess.run([RUNNER, "merge", str(out), *map(str, parts),
                               "-q", *extra], capture_output=True, text=True,
                              timeout=120)
        assert proc.returncode == 0, proc.stderr
        kinds[kind] = out
    with h5py.File(kinds["joined"], "r") as f:
        assert f["force"].is_virtual
    study = os.path.join(ROOT, "build", "rps3-study")
    for kind, args in (("study_workspace", ["workspace", "--quick"]),
                       ("study_accuracy", ["accuracy", "--samples", "10",
                                           "--repeats", "1"])):
        out = tmp / f"{kind}.nc"
        proc = subprocess.run([study, args[0], "-o", str(out), *args[1:]],
                              capture_output=True, text=True, timeout=300)
        assert proc.returncode == 0, proc.stderr
        kinds[kind] = out
    return kinds


KINDS = ["sweep_grid_differs", "sweep_one_grid", "sweep_no_sweep",
         "simulation_grid_differs", "simulation_one_grid", "part", "joined",
         "merged", "study_workspace", "study_accuracy"]


@pytest.mark.parametrize("kind", KINDS)
def test_compliance_checker_cf_1_10(kind, file_kinds, offline, tmp_path):
    path = file_kinds[kind]
    with h5py.File(path, "r") as f:
        assert "standard_name_vocabulary" not in f.attrs
        assert h5io.text(f.attrs["Conventions"]) == "CF-1.10"
    errors, warnings, exceptions = compliance(path, tmp_path)
    assert errors == [], errors
    assert all(w.startswith(ALLOWED_WARNINGS) for w in warnings), warnings
    assert all(any(a in e for a in ALLOWED_EXCEPTIONS) for e in exceptions), \
        exceptions


def test_compliance_checker_finds_errors(cf_file, offline, tmp_path):
    """The check can fail: a copy of a file with a dotted variable name in
    coordinates and a coordinates entry the file lacks has errors."""
    import shutil
    bad = tmp_path / "bad.nc"
    shutil.copy(cf_file[1], bad)
    with h5py.File(bad, "r+") as f:
        f.move("trajectory__amp_2", "trajectory.amp[2]")
        f["force"].attrs["coordinates"] = "trajectory.amp[2] case_time"
        f["failed_at"].attrs["coordinates"] = "case_time"
    errors, _, _ = compliance(bad, tmp_path)
    assert any("trajectory.amp[2]" in e for e in errors), errors
    assert any("case_time" in e and "failed_at" in e for e in errors), errors
