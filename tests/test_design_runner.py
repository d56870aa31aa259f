"""Design studies in rps3-run (docs/runner.md, "Design studies"): the
design keys are scene keys, checked where they are written; every case of
the sweep is one design, evaluated by the library over the section's grid
of poses and along the scene's trajectory; the file has the conventions of
a sweep's (CF-1.10, units everywhere, the swept keys as coordinates), so
that shards merge into the file of one run and rps3.open_dataset selects
by design variable.  The values are those of the C API called directly
(through the Python package's cffi binding of include/rps3.h)."""

import math
import os
import re
import subprocess

import cf_units
import h5py
import numpy as np
import pytest
import rps3
from conftest import RUNNER, run, write_scene
from rps3 import h5io
from test_cf import ALLOWED_EXCEPTIONS, ALLOWED_WARNINGS, compliance, offline  # noqa: F401
from test_scale import MPIRUN, RUNNER_MPI, assert_same_content, mpirun

MANIP = """\
manipulator:
  R: 0.2286
  rho: 0.5
  M: 0.18
  m_over_M: 0.5
  d: 0.1524
  stroke:
    min: 0.2286
    max: 0.4572
"""

GRID = """\
design:
  alpha: [-3.141592653589793, 3.141592653589793, 8]
  beta: [0.0, 0.5, 5]
  z_c: [0.3, 0.45, 6]
"""

HELIX = """\
trajectory:
  kind: helix
  radius: 0.000266
  pitch: 0.03048
  z0: 0.3048
  period: 10.0
  blend: 1.0
  samples: 51
"""

# an atlas of 2 x 3 designs with the task and the per-pose indices; the
# stroke [0.2286, 0.25] m reaches no pose of the grid (each link is at least
# as long as the height of its ball joint, and every ball joint is above
# z_c - r sin(beta) >= 0.3125 - 0.11 sin(0.45) > 0.25 m): an empty
# workspace
ATLAS = MANIP + HELIX + GRID + "  per_pose: true\n" + """\
sweep:
  manipulator.rho: [0.3, 0.5]
  manipulator.stroke.max: [0.25, 0.4572, 0.6]
"""


def one_line(text):
    lines = text.strip().splitlines()
    assert len(lines) == 1, text
    return lines[0]


@pytest.fixture(scope="module")
def atlas(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("design")
    scene = write_scene(tmp / "atlas.yaml", ATLAS)
    out = tmp / "atlas.h5"
    proc = run(scene, out)
    assert proc.returncode == 0, proc.stderr
    return scene, out, proc


# ------------------------------------------------------------ bad scenes

def set_key(text, old, new):
    assert old in text
    return text.replace(old, new, 1)


BAD = [
    # (name, edit of ATLAS, key named, words of the message)
    ("negative stroke", ("    min: 0.2286", "    min: -0.1"),
     "manipulator.stroke.min", "must be >= 0, got -0.1"),
    ("zero l_max", ("    max: 0.4572", "    max: 0"),
     "manipulator.stroke.max", "must be > 0, got 0"),
    # the later of the two keys is named (max: the line below min)
    ("inverted stroke", ("    min: 0.2286", "    min: 0.5"),
     "manipulator.stroke.max", "[0.5, 0.4572] m is inverted: needs min < "
     "max"),
    ("empty stroke", ("    min: 0.2286", "    min: 0.4572"),
     "manipulator.stroke.max", "is empty: needs min < max"),
    ("inverted pin range",
     ("  stroke:\n", "  pin: {min: 1.0, max: 0.5}\n  stroke:\n"),
     "manipulator.pin.max", "is inverted"),
    ("ball beyond pi", ("  stroke:\n", "  ball: {max: 4}\n  stroke:\n"),
     "manipulator.ball.max", "must be <= 3.14159"),
    ("misspelt design key", ("  per_pose: true", "  per_pos: true"),
     "design.per_pos", "did you mean design.per_pose?"),
    ("grid without cells", ("beta: [0.0, 0.5, 5]", "beta: [0.0, 0.5, 0]"),
     "design.beta", "a whole number of cells >= 1"),
    ("fractional cells", ("beta: [0.0, 0.5, 5]", "beta: [0.0, 0.5, 2.5]"),
     "design.beta", "a whole number of cells >= 1"),
    ("inverted grid", ("z_c: [0.3, 0.45, 6]", "z_c: [0.45, 0.3, 6]"),
     "design.z_c", "is inverted"),
    ("grid overflows", ("z_c: [0.3, 0.45, 6]", "z_c: [-1e308, 1e308, 6]"),
     "design", "is not a finite number"),
    ("missing grid", ("  z_c: [0.3, 0.45, 6]\n", ""),
     "design.z_c", "missing required key of a design study"),
    ("missing stroke", ("    max: 0.4572\n", ""),
     "manipulator.stroke.max", "missing required key of a design study"),
    ("swept grid", ("sweep:\n", "sweep:\n  design.alpha[2]: [4, 8]\n"),
     "design.alpha[2]", "cannot be swept"),
    ("link inertia", ("  d: 0.1524\n", "  d: 0.1524\n  link_Ic: 0.001\n"),
     "manipulator.link_Ic", "a design study does not read this key"),
    ("solver key", ("design:\n", "solver: {theta: multiroot}\ndesign:\n"),
     "solver.theta", "a design study does not read this key"),
    ("payload off the normal",
     ("  d: 0.1524\n", "  d: 0.1524\n  payload: {mass: 1, com: [0.1, 0, 0]}\n"),
     "manipulator.payload.com", "a point on the platform normal"),
    ("simulate beside design", ("design:\n", "simulate: {}\ndesign:\n"),
     "design", "a design study or a simulation, not both"),
]


@pytest.mark.parametrize("edit,key,words", [b[1:] for b in BAD],
                         ids=[b[0] for b in BAD])
def test_bad_design_scene(tmp_path, edit, key, words):
    """Refused before anything is written: exit 2, one line naming the
    file, the line and column of the key (or of its section), the key and
    what is wrong; no output file."""
    text = set_key(ATLAS.replace(
        "  manipulator.stroke.max: [0.25, 0.4572, 0.6]\n", ""), *edit)
    scene = write_scene(tmp_path / "bad.yaml", text)
    out = tmp_path / "out.h5"
    proc = run(scene, out)
    assert proc.returncode == 2, proc.stderr
    line = one_line(proc.stderr)
    m = re.match(rf"{re.escape(str(scene))}:(\d+):(\d+): (\S+): (.*)$", line)
    assert m, line
    assert m.group(3) == key and words in m.group(4), line
    # the position is that of the key's value, or, for a key that is
    # missing or a section that does not fit, the start of its section
    row, col = int(m.group(1)), int(m.group(2))
    lines = text.splitlines()
    leaf = key.rsplit(".", 1)[-1].split("[")[0]
    section = key.split(".")[0] + ":"
    first_of_section = (lines.index(section) + 2 if section in lines
                        else None)
    assert (leaf in lines[row - 1][:col - 1] or
            lines[row - 1][col - 1:].startswith(leaf) or
            (row, col) == (first_of_section, 3)), (line, lines[row - 1])
    assert not out.exists() and os.listdir(tmp_path) == ["bad.yaml"]
    # --check says the same
    assert one_line(run(scene, None, "--check").stderr) == line


def test_a_swept_value_is_named_with_its_case(tmp_path):
    """An inverted stroke made by one swept value: the message points at
    that value of the sweep and names the case."""
    text = ATLAS.replace("[0.25, 0.4572, 0.6]", "[0.25, 0.2, 0.6]")
    scene = write_scene(tmp_path / "s.yaml", text)
    proc = run(scene, tmp_path / "o.h5")
    assert proc.returncode == 2
    line = one_line(proc.stderr)
    row = next(i for i, t in enumerate(text.splitlines(), 1)
               if "stroke.max: [" in t)
    col = text.splitlines()[row - 1].index("0.2,") + 1
    assert line.startswith(f"{scene}:{row}:{col}: manipulator.stroke.max: "
                           "case 1: the stroke [min, max] = [0.2286, 0.2] m "
                           "is inverted"), line


def test_design_keys_need_a_design_section(tmp_path):
    scene = write_scene(tmp_path / "s.yaml", MANIP + HELIX)
    proc = run(scene, tmp_path / "o.h5")
    assert proc.returncode == 2
    assert re.match(rf"{re.escape(str(scene))}:8:10: manipulator.stroke.min: "
                    "only a design study reads this key",
                    one_line(proc.stderr)), proc.stderr


def test_keys_and_schema_are_listed(runner):
    keys = subprocess.run([RUNNER, "--keys"], capture_output=True,
                          text=True).stdout
    for key, unit in (("manipulator.stroke.min", "m"),
                      ("manipulator.stroke.max", "m"),
                      ("manipulator.pin.min", "rad"),
                      ("manipulator.ball.max", "rad"),
                      ("manipulator.link_radius", "m"),
                      ("manipulator.link_density", "kg/m"),
                      ("design.alpha", "rad, rad, 1"),
                      ("design.z_c", "m, m, 1"), ("design.good_lti", "1")):
        row = next(r for r in keys.splitlines() if r.startswith(f"| `{key}`"))
        assert row.split("|")[3].strip() == unit, row
    schema = subprocess.run([RUNNER, "--design-schema"], capture_output=True,
                            text=True).stdout
    rows = [r.split("|") for r in schema.splitlines()[2:]]
    assert {r[1].strip().strip("`") for r in rows} >= {
        "status", "nreach", "volume", "gti", "good_fraction", "task_F_peak",
        "lti", "pose_flags", "scene_resolved"}


# --------------------------------------------------------------- the file

def test_file_layout_units_and_cf(atlas):
    """Every variable has UDUNITS units and a long_name; the per-design
    ones are [case], the per-pose ones [case, z_c, beta, alpha]; the swept
    keys are the coordinates; the root says CF-1.10 and content design."""
    scene, out, proc = atlas
    with h5py.File(out, "r") as f:
        assert h5io.text(f.attrs["Conventions"]) == "CF-1.10"
        assert h5io.text(f.attrs["content"]) == "design"
        names = []
        f.visititems(lambda n, o: names.append(n)
                     if isinstance(o, h5py.Dataset) else None)
        for name in names:
            ds = f[name]
            u = cf_units.Unit(h5io.text(ds.attrs["units"]))
            assert not u.is_unknown(), name
            assert len(h5io.text(ds.attrs["long_name"])) >= 4, name
        assert h5io.sweep_keys(f) == ["manipulator.rho",
                                      "manipulator.stroke.max"]
        assert h5io.dims(f["gti"]) == ("case",)
        assert h5io.dims(f["task_F_peak"]) == ("case", "link")
        assert h5io.dims(f["lti"]) == ("case", "z_c", "beta", "alpha")
        assert f["lti"].shape == (6, 6, 5, 8)
        assert h5io.text(f["volume"].attrs["units"]) == "m rad^2"
        assert h5io.text(f["task_P_peak"].attrs["units"]) == "W"
        # cell centres of [lo, hi, cells]
        assert np.allclose(f["beta"][()], (np.arange(5) + 0.5) * 0.1)
        assert f["status"].attrs["flag_values"].tolist().count(-1000) == 1
        meanings = h5io.text(f["pose_flags"].attrs["flag_meanings"]).split()
        assert f["pose_flags"].attrs["flag_masks"].tolist() == [
            1 << k for k in range(len(meanings))]


def test_an_empty_workspace_is_a_result(atlas):
    """The stroke that reaches no pose: status 0, nreach 0, volume 0, every
    pose flagged stroke; the task fails at t = 0 (task_status EREACH, no
    statistics); the run exits 0 and says how many designs were empty."""
    scene, out, proc = atlas
    assert "2 designs with an empty workspace" in proc.stderr
    with h5py.File(out, "r") as f:
        smax = f["manipulator__stroke__max"][()]
        empty = smax == 0.25
        assert empty.sum() == 2
        assert (f["status"][()] == 0).all()
        assert (f["nreach"][()][empty] == 0).all()
        assert (f["nreach"][()][~empty] > 0).all()
        assert (f["volume"][()][empty] == 0).all()
        flags = f["pose_flags"][()][empty]
        stroke = 1 << h5io.text(
            f["pose_flags"].attrs["flag_meanings"]).split().index("stroke")
        assert (flags & stroke).all()
        from rps3._rps3 import lib
        assert (f["task_status"][()][empty] == lib.RPS3_EREACH).all()
        assert (f["task_status"][()][~empty] == 0).all()
        assert np.isnan(f["task_F_peak"][()][empty]).all()
        assert (f["task_fail_time"][()][empty] == 0).all()
        msg = [h5io.text(m) for m in f["task_message"][()][empty]]
        assert all(m.startswith("t = 0 s") and "stroke" in m for m in msg)


def test_xarray_selects_by_design_variable(atlas):
    """rps3.open_dataset: the swept keys become dimensions (rho, max), and
    sel picks the design whose row the file has."""
    scene, out, proc = atlas
    ds = rps3.open_dataset(out)
    assert ds.gti.dims == ("rho", "max")
    assert ds.lti.dims == ("rho", "max", "z_c", "beta", "alpha")
    with h5py.File(out, "r") as f:
        rho = f["manipulator__rho"][()]
        smax = f["manipulator__stroke__max"][()]
        for c in range(len(rho)):
            sel = ds.sel(rho=rho[c], max=smax[c])
            assert int(sel.case_index) == c
            for name in ("gti", "volume", "nreach", "good_fraction"):
                assert np.array_equal(sel[name].values, f[name][c],
                                      equal_nan=True), name
            assert np.array_equal(sel.task_F_peak.values,
                                  f["task_F_peak"][c], equal_nan=True)
            assert np.array_equal(sel.lti.values, f["lti"][c],
                                  equal_nan=True)
    assert ds.volume.attrs["units"] == "m rad^2"


def test_resolved_scene_reruns_one_design(atlas, tmp_path):
    """scene_resolved of a design is a design study of that design alone,
    and gives its row."""
    scene, out, proc = atlas
    with h5py.File(out, "r") as f:
        text = h5io.text(f["scene_resolved"][4])
        row = {k: f[k][4] for k in ("gti", "volume", "lti", "task_F_rms")}
    one = write_scene(tmp_path / "one.yaml", text)
    proc = run(one, tmp_path / "one.h5", "-q")
    assert proc.returncode == 0, proc.stderr
    with h5py.File(tmp_path / "one.h5", "r") as g:
        for k, v in row.items():
            assert np.array_equal(g[k][0], v, equal_nan=True), k


# ---------------------------------------------- the C API, called directly

def c_design(ffi, lib, R, rho, M, m, d, l_min, l_max):
    ds = ffi.new("rps3_design *")
    lib.rps3_design_default(ds)
    ds.R, ds.rho, ds.M = R, rho, M
    ds.actuator_mass, ds.actuator_d = m, d
    ds.l_min, ds.l_max = l_min, l_max
    return ds


def test_values_are_the_c_api_s(atlas):
    """For every design of the atlas: rps3_design_eval_grid over the same
    grid and rps3_design_task_eval along the same helix, called through
    cffi, give the file's numbers bit for bit."""
    from rps3._rps3 import ffi, lib
    scene, out, proc = atlas
    gr = ffi.new("rps3_design_grid *")
    gr.lo = [-math.pi, 0.0, 0.3]
    gr.hi = [math.pi, 0.5, 0.45]
    gr.n = [8, 5, 6]
    n = lib.rps3_design_grid_size(gr)
    assert n == 240
    wsp = ffi.new("rps3_design_ws **")
    assert lib.rps3_design_ws_alloc(wsp) == 0
    ws = wsp[0]
    tr = ffi.new("rps3_traj *")
    lib.rps3_traj_default(tr)
    tr.kind = lib.RPS3_TRAJ_HELIX
    tr.helix.radius, tr.helix.pitch = 0.000266, 0.03048
    tr.helix.z0, tr.helix.period, tr.helix.blend = 0.3048, 10.0, 1.0
    try:
        with h5py.File(out, "r") as f:
            for c in range(f["case"].shape[0]):
                ds = c_design(ffi, lib, 0.2286, f["manipulator__rho"][c],
                              0.18, 0.09, 0.1524, 0.2286,
                              f["manipulator__stroke__max"][c])
                flags = ffi.new("int[]", n)
                lti = ffi.new("double[]", n)
                cen = ffi.new("double[]", 3 * n)
                o = ffi.new("rps3_design_out *")
                o.flags, o.lti, o.c = flags, lti, cen
                s = ffi.new("rps3_design_summary *")
                rc = lib.rps3_design_eval_grid(ws, ds, ffi.NULL, gr, o, s)
                assert rc in (0, lib.RPS3_EEMPTY)
                assert f["nreach"][c] == s.nreach
                for name in ("volume", "gti", "good_fraction", "lti_min",
                             "cond_h_max", "xc_max", "spin_max"):
                    assert f[name][c] == getattr(s, name), (c, name)
                np.testing.assert_array_equal(
                    f["lti"][c].ravel(), np.frombuffer(ffi.buffer(lti)))
                np.testing.assert_array_equal(
                    f["pose_flags"][c].ravel(),
                    np.frombuffer(ffi.buffer(flags), dtype=np.intc))
                np.testing.assert_array_equal(
                    f["y_c"][c].ravel(),
                    np.frombuffer(ffi.buffer(cen))[n:2 * n])
                res = ffi.new("rps3_design_task *")
                rc = lib.rps3_design_task_eval(ws, ds, ffi.NULL, tr, 51,
                                               lib.RPS3_DESIGN_LINK_MASS, res)
                assert f["task_status"][c] == rc
                if res.nsamples:
                    assert f["task_F_peak"][c].tolist() == list(res.F_peak)
                    assert f["task_F_rms"][c].tolist() == list(res.F_rms)
                    assert f["task_P_peak"][c].tolist() == list(res.P_peak)
    finally:
        lib.rps3_design_ws_free(ws)


# ---------------------------------------------- threads, shards, merge

def shard_scene(tmp_path):
    """40 designs of 4000 poses: 3 work units (of up to 14 designs)."""
    text = MANIP + GRID.replace("8]", "20]").replace("5]", "10]").replace(
        "6]", "20]") + """\
sweep:
  manipulator.rho: {from: 0.3, to: 0.8, num: 8}
  manipulator.stroke.max: [0.25, 0.35, 0.4572, 0.55, 0.65]
"""
    return write_scene(tmp_path / "shards.yaml", text)


def test_check_counts_designs_and_work_units(tmp_path):
    scene = shard_scene(tmp_path)
    proc = run(scene, None, "--check")
    assert proc.returncode == 0, proc.stderr
    assert "design study: 40 designs x 4000 poses" in proc.stdout
    assert "3 work units of up to 14 designs" in proc.stdout
    assert re.search(r"run time about .* \(an estimate", proc.stdout)
    bad = run(scene, tmp_path / "p.h5", "--shard", "0/4")
    assert bad.returncode == 2
    assert "at most 3 shards can have work" in bad.stderr


def test_shards_and_threads_give_the_file_of_one_run(tmp_path):
    """-j 2, and 3 shards joined by virtual datasets or by copy: every
    dataset equal, bit for bit, to a single-threaded run's."""
    scene = shard_scene(tmp_path)
    one = tmp_path / "one.h5"
    assert run(scene, one, "-q").returncode == 0
    two = tmp_path / "two.h5"
    assert run(scene, two, "-q", "-j", "2").returncode == 0
    assert_same_content(one, two)
    parts = []
    for k in range(3):
        part = tmp_path / f"part{k}.h5"
        proc = run(scene, part, "-q", "--shard", f"{k}/3")
        assert proc.returncode == 0, proc.stderr
        with h5py.File(part, "r") as f:
            st = f["status"][()]
            assert (st == -1000).any() and (st == 0).any()
        parts.append(str(part))
    for extra in ([], ["--copy"]):
        out = tmp_path / f"merged{len(extra)}.h5"
        proc = subprocess.run([RUNNER, "merge", str(out), *parts[::-1],
                               "-q", *extra], capture_output=True, text=True,
                              timeout=120)
        assert proc.returncode == 0, proc.stderr
        assert_same_content(one, out)
    # a part already complete is kept by --resume
    proc = run(scene, parts[1], "--shard", "1/3", "--resume")
    assert proc.returncode == 0 and "not run again" in proc.stderr


@pytest.mark.skipif(MPIRUN is None, reason="mpirun (openmpi-bin) missing")
def test_mpirun_gives_the_file_of_one_run(tmp_path):
    """rps3-run-mpi on 2 ranks: the ranks' parts joined (and, with --copy,
    merged) into the datasets of one run."""
    if not os.access(RUNNER_MPI, os.X_OK):
        pytest.fail(f"{RUNNER_MPI} is missing: run `make runner-mpi` first")
    scene = shard_scene(tmp_path)
    one = tmp_path / "one.h5"
    assert run(scene, one, "-q").returncode == 0
    for extra in ([], ["--copy"]):
        out = tmp_path / f"mpi{len(extra)}.h5"
        proc = mpirun(2, RUNNER_MPI, scene, "-o", out, "-q", *extra)
        assert proc.returncode == 0, proc.stderr
        assert_same_content(one, out)


def test_compliance_checker_cf_1_10(atlas, tmp_path, offline):  # noqa: F811
    """The design file passes IOOS compliance-checker's CF-1.10 checks
    without an error (offline), its warnings those of docs/hdf5.md."""
    import shutil
    scene, out, proc = atlas
    nc = tmp_path / "atlas.nc"
    shutil.copy(out, nc)
    errors, warnings, exceptions = compliance(nc, tmp_path)
    assert errors == [], errors
    assert all(w.startswith(ALLOWED_WARNINGS) for w in warnings), warnings
    assert all(any(a in e for a in ALLOWED_EXCEPTIONS) for e in exceptions), \
        exceptions
