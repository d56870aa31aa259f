"""Trajectory kind table through the runner: the paper's helix sampled into
a table gives the helix's forces (exactly at the rows with rates and
accelerations; away from the blend corners with the spline), CSV and HDF5
tables agree, and every bad table is refused at --check (exit 2) with a
message naming the scene key, the file and the row (and column).  The
interpolants themselves are tested in tests/test_table.c."""

import h5py
import numpy as np
import pytest
from conftest import CONFIGS, run, write_scene

# Table II (configs/paper.yaml): R, rho, r*, pitch h, z_i, T*, t_a
R, RHO, RS, PITCH, Z0, T, TA = 0.2286, 0.5, 0.000266, 0.03048, 0.3048, 10.0, 1.0
POSE = ("alpha", "beta", "z_c")

SCENE = """\
manipulator: {R: 0.2286, rho: 0.5, M: 0.18, m_over_M: 0.5, d: 0.1524}
trajectory:
  kind: table
  table: {file: FILE}
  samples: SAMPLES
effects: [platform_gravity, link_gravity, platform_inertia, link_inertia]
sweep:
  manipulator.m_over_M: [0, 0.5]
"""


def helix(t):
    """The paper's helix (35)-(37) with Table I's LSPB phi, from the paper's
    numbers alone: pose, rate, acceleration, each (n, 3).  A time on a
    blend corner takes the segment that starts there, T* the last one's
    end, as rps3_traj_eval."""
    r = RHO * R
    wmax = 2 * np.pi / (T - TA)
    acc = wmax / TA
    a, b = t < TA, t < T - TA
    phi = np.where(a, 0.5 * acc * t * t,
                   np.where(b, wmax * (t - 0.5 * TA),
                            2 * np.pi - 0.5 * acc * (T - t) ** 2))
    dphi = np.where(a, acc * t, np.where(b, wmax, acc * (T - t)))
    ddphi = np.where(a, acc, np.where(b, 0.0, -acc))
    one, zero = np.ones_like(t), np.zeros_like(t)
    q = np.stack([np.pi / 2 - phi / 2,
                  2 * np.arcsin(np.sqrt(RS / r)) * one,
                  Z0 + PITCH * t / T], axis=1)
    dq = np.stack([-dphi / 2, zero, PITCH / T * one], axis=1)
    ddq = np.stack([-ddphi / 2, zero, zero], axis=1)
    return q, dq, ddq


def write_csv(path, t, q, dq=None, ddq=None, names=POSE):
    cols = ["t", *names]
    data = [t[:, None], q]
    if dq is not None:
        cols += [n + "_dot" for n in names]
        data.append(dq)
    if ddq is not None:
        cols += [n + "_ddot" for n in names]
        data.append(ddq)
    rows = np.hstack(data)
    with open(path, "w") as f:
        f.write("# the paper's helix, Table II\n")
        f.write(", ".join(cols) + "\n")
        for row in rows:
            f.write(",".join("%.17g" % x for x in row) + "\n")
    return path


def helix_grid(n=1001):
    t = np.linspace(0, T, n)
    t[-1] = T
    return t


def run_table(tmp_path, name, samples=1001, scene_text=None,
              names=("time", "force", "force_by_effect", *POSE)):
    """Run the scene (SCENE by default) on table `name`: its datasets."""
    scene = write_scene(tmp_path / "s.yaml",
                        (scene_text or SCENE).replace("FILE", name)
                        .replace("SAMPLES", str(samples)))
    out = tmp_path / (name + ".h5")
    proc = run(scene, out, "-q")
    assert proc.returncode == 0, proc.stderr
    with h5py.File(out, "r") as f:
        return {k: f[k][()] for k in names}


@pytest.fixture(scope="module")
def helix_forces(runner, tmp_path_factory):
    out = tmp_path_factory.mktemp("helix") / "paper.h5"
    proc = run(f"{CONFIGS}/paper.yaml", out, "-q")
    assert proc.returncode == 0, proc.stderr
    with h5py.File(out, "r") as f:
        return {k: f[k][()] for k in ("time", "force", "force_by_effect")}


def test_helix_table_with_rates_is_the_helix(helix_forces, tmp_path):
    """Rows with the helix's rates and accelerations on the output grid:
    the quintic Hermite interpolant takes the row's value, rate and
    acceleration at each row, so the forces are the helix kind's to
    rounding (1e-12 of the largest force: the helix's phi is computed here
    and in C with different roundings, ~1e-15)."""
    t = helix_grid()
    write_csv(tmp_path / "h.csv", t, *helix(t))
    got = run_table(tmp_path, "h.csv")
    want = helix_forces["force"]
    assert np.abs(got["force"] - want).max() <= 1e-12 * np.abs(want).max()


def test_helix_table_hdf5_is_the_csv(runner, tmp_path):
    """The same rows as HDF5 datasets give the same numbers, bit for bit."""
    t = helix_grid()
    q, dq, ddq = helix(t)
    write_csv(tmp_path / "h.csv", t, q, dq, ddq)
    with h5py.File(tmp_path / "h.h5", "w") as f:
        f["t"] = t
        for k, n in enumerate(POSE):
            f[n] = q[:, k]
            f[n + "_dot"] = dq[:, k]
            f[n + "_ddot"] = ddq[:, k]
    a = run_table(tmp_path, "h.csv")
    b = run_table(tmp_path, "h.h5")
    np.testing.assert_array_equal(a["force"], b["force"])


def test_helix_table_of_poses_by_spline(helix_forces, tmp_path):
    """Poses only, every 0.01 s: the not-a-knot spline is exact for the
    helix's pieces (quadratic alpha, linear z_c, constant beta) but smooths
    the acceleration jumps of the LSPB corners t_a, T* - t_a; that error
    decays by 2 - sqrt(3) = 0.27 per row away from a corner (the spline's
    decay factor), below 1e-11 of the jump after 20 rows.  So: 1e-12 of
    the largest force beyond 20 rows of a corner, and near a corner no more
    than the inertia shares (what the acceleration drives) twice over."""
    t = helix_grid()
    write_csv(tmp_path / "p.csv", t, helix(t)[0])
    got = run_table(tmp_path, "p.csv")
    want = helix_forces["force"]
    scale = np.abs(want).max()
    err = np.abs(got["force"] - want).max(axis=(0, 2))
    near = (np.abs(t - TA) < 0.2 + 1e-9) | (np.abs(t - (T - TA)) < 0.2 + 1e-9)
    assert err[~near].max() <= 1e-12 * scale
    inertia = np.abs(helix_forces["force_by_effect"][:, :, 2:, :]).sum(axis=2)
    assert (err[near] <= 2 * inertia.max(axis=(0, 2))[near] + 1e-12 * scale
            ).all()
    assert err[near].max() > 1e-9 * scale  # the corners do show


def bad(tmp_path, csv_text, name="m.csv"):
    """--check on a scene whose table is csv_text: the one stderr line."""
    (tmp_path / name).write_text(csv_text)
    scene = write_scene(tmp_path / "s.yaml",
                        SCENE.replace("FILE", name).replace("SAMPLES", "11"))
    proc = run(scene, None, "--check")
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith(f"{scene}:4:17: trajectory.table.file: "), \
        lines[0]
    return lines[0]


GOOD = ["0, 0.3, 0.08, 0.30", "0.5, 0.31, 0.081, 0.301",
        "1.0, 0.33, 0.082, 0.303", "1.5, 0.34, 0.08, 0.304",
        "2.0, 0.35, 0.079, 0.305"]


def table(*rows, header="t, alpha, beta, z_c"):
    return "# a comment\n" + header + "\n" + "\n".join(rows) + "\n"


@pytest.mark.parametrize("rows,words", [
    # bad CSV syntax: line and column of the field
    ((GOOD[0], GOOD[1], "1.0, 0.33, abc, 0.303", *GOOD[3:]),
     "m.csv:5:12: column beta: expected a number, got 'abc'"),
    ((GOOD[0], "0.5, 0.31, , 0.301", *GOOD[2:]),
     "m.csv:4:12: column beta: empty field"),
    ((GOOD[0], GOOD[1], "1.0, 0.33, 0.082", *GOOD[3:]),
     "m.csv:5: 3 fields, the header has 4 columns"),
    ((GOOD[0], "0.5, 0.31, 0.081, 0.301, 7", *GOOD[2:]),
     "m.csv:4:24: more fields than the header's 4 columns"),
    # NaN and infinity
    ((GOOD[0], GOOD[1], "1.0, nan, 0.082, 0.303", *GOOD[3:]),
     "m.csv:5:6: column alpha: 'nan' is not a finite number"),
    ((*GOOD[:4], "2.0, 0.35, 0.079, 1e999"),
     "m.csv:7:19: column z_c: '1e999' is not a finite number"),
    # time that does not increase
    ((GOOD[0], GOOD[1], "0.5, 0.33, 0.082, 0.303", *GOOD[3:]),
     "m.csv:5: column t: 0.5 after 0.5: times must increase strictly"),
    # too few rows for the spline
    (GOOD[:3], "m.csv: 3 rows; a table needs at least 4 without rate "
               "columns"),
    # an unreachable row: named by the file's line
    ((GOOD[0], GOOD[1], "1.0, 0.33, 0.082, -0.05", *GOOD[3:]),
     "m.csv:5: case 0: trajectory.table.pose[2] = -0.05: pose unreachable"),
])
def test_bad_table_names_file_and_row(runner, tmp_path, rows, words):
    line = bad(tmp_path, table(*rows))
    assert words in line, line


@pytest.mark.parametrize("header,words", [
    ("t, alpha, beta", "m.csv: missing column z_c"),
    ("t, alpha, beta, zc",
     "m.csv:2:17: column 'zc': unknown column (did you mean z_c?)"),
    ("t, alpha, beta, z_c, alpha_dot",
     "m.csv: missing column beta_dot (give the three rates or none)"),
    ("t, alpha, alpha, z_c", "m.csv:2:11: column 'alpha': given twice"),
    ("t;alpha;beta;z_c", "m.csv:2: the columns are separated by semicolons"),
])
def test_bad_header(runner, tmp_path, header, words):
    line = bad(tmp_path, table(*GOOD, header=header))
    assert words in line, line


def test_byte_order_mark_and_crlf(runner, tmp_path):
    """A spreadsheet's CSV: a UTF-8 byte order mark and CRLF line ends."""
    (tmp_path / "m.csv").write_bytes(
        b"\xef\xbb\xbf" + table(*GOOD).replace("\n", "\r\n").encode())
    scene = write_scene(tmp_path / "s.yaml", SCENE.replace("FILE", "m.csv")
                        .replace("SAMPLES", "5"))
    proc = run(scene, None, "--check")
    assert proc.returncode == 0, proc.stderr


@pytest.mark.parametrize("name", ["fifo.csv", "dir.h5", "dir.csv"])
def test_table_not_a_regular_file(runner, tmp_path, name):
    """A FIFO (opening it would wait for a writer) or a directory is
    refused before anything opens it, as CSV and as HDF5."""
    import os
    if name.startswith("fifo"):
        os.mkfifo(tmp_path / name)
    else:
        (tmp_path / name).mkdir()
    scene = write_scene(tmp_path / "s.yaml", SCENE.replace("FILE", name)
                        .replace("SAMPLES", "5"))
    proc = run(scene, None, "--check", timeout=20)
    assert proc.returncode == 2
    assert f"{name}: not a regular file" in proc.stderr, proc.stderr


def test_missing_file_and_hdf5_errors(runner, tmp_path):
    scene = write_scene(tmp_path / "s.yaml", SCENE.replace("FILE", "nope.csv")
                        .replace("SAMPLES", "5"))
    proc = run(scene, None, "--check")
    assert proc.returncode == 2
    assert "nope.csv: cannot open: No such file" in proc.stderr
    with h5py.File(tmp_path / "h.h5", "w") as f:
        f["t"] = np.linspace(0, 2, 5)
        f["alpha"] = np.full(5, 0.3)
        f["beta"] = np.full(5, 0.08)
        f["z_c"] = np.array([0.3, 0.3, np.nan, 0.3, 0.3])
    scene = write_scene(tmp_path / "s.yaml",
                        SCENE.replace("FILE", "h.h5").replace("SAMPLES", "5"))
    proc = run(scene, None, "--check")
    assert proc.returncode == 2
    assert "h.h5: dataset /z_c, row 2: nan is not a finite number" in \
        proc.stderr, proc.stderr


def test_table_key_cannot_be_swept(runner, tmp_path):
    (tmp_path / "m.csv").write_text(table(*GOOD))
    scene = write_scene(tmp_path / "s.yaml", SCENE.replace("FILE", "m.csv")
                        .replace("SAMPLES", "5")
                        .replace("manipulator.m_over_M: [0, 0.5]",
                                 "trajectory.table.file: [m.csv]"))
    proc = run(scene, None, "--check")
    assert proc.returncode == 2
    assert "cannot be swept" in proc.stderr


PATH_SCENE = """\
manipulator: {R: 0.2286, rho: 0.5, M: 0.18, m_over_M: 0.5, d: 0.1524}
trajectory:
  kind: path
  path: {shape: table, file: FILE}
  samples: SAMPLES
effects: [platform_gravity, link_gravity, platform_inertia, link_inertia]
sweep:
  manipulator.m_over_M: [0, 0.5]
"""

CENTRE = ("x", "y", "z")


def helix_centre(t):
    """The helix's centre (35): radius r* about the axis at angle phi(t),
    rising by h in T*; with its rate and acceleration."""
    q, dq, ddq = helix(t)
    phi, dphi, ddphi = (np.pi - 2 * q[:, 0]), -2 * dq[:, 0], -2 * ddq[:, 0]
    c = np.stack([RS * np.cos(phi), RS * np.sin(phi), q[:, 2]], axis=1)
    dc = np.stack([-RS * np.sin(phi) * dphi, RS * np.cos(phi) * dphi,
                   dq[:, 2]], axis=1)
    ddc = np.stack([-RS * (np.sin(phi) * ddphi + np.cos(phi) * dphi**2),
                    RS * (np.cos(phi) * ddphi - np.sin(phi) * dphi**2),
                    ddq[:, 2]], axis=1)
    return c, dc, ddc


def run_path_table(tmp_path, name, samples=1001):
    return run_table(tmp_path, name, samples, PATH_SCENE,
                     ("force", "x_c", "y_c", "z_c", "scene_resolved"))


def test_helix_centre_table_is_the_helix(helix_forces, tmp_path):
    """The helix's centre (x, y, z) with its rates and accelerations at the
    output grid, as a path of shape table: through the inversion of
    (3)-(4) the forces are the helix kind's.  1e-11 of the largest force:
    the table's rho = sqrt(x^2 + y^2) of a radius-0.266 mm circle carries
    rounding of ~1e-16 relative into beta (the helix kind takes r* itself),
    and the rates of alpha divide by rho^2."""
    t = helix_grid()
    c = helix_centre(t)
    write_csv(tmp_path / "c.csv", t, *c, names=CENTRE)
    got = run_path_table(tmp_path, "c.csv")
    want = helix_forces["force"]
    assert np.abs(got["force"] - want).max() <= 1e-11 * np.abs(want).max()
    # and the centre the runner writes (from the pose, by (3)-(4)) is the
    # table's, at every row: 1e-12 of r* in x, y (the inversion and (3)-(4)
    # again, a few roundings of values ~r*), rounding of z_c
    for k, name in enumerate(("x_c", "y_c")):
        assert np.abs(got[name] - c[0][:, k]).max() <= 1e-12 * RS, name
    assert np.abs(got["z_c"] - c[0][:, 2]).max() <= 1e-15


def test_path_table_resolved_scene_reruns(runner, tmp_path):
    """The resolved scene names the table by its absolute path: it reruns
    from another directory to the same forces."""
    t = helix_grid(201)
    write_csv(tmp_path / "c.csv", t, helix_centre(t)[0], names=CENTRE)
    got = run_path_table(tmp_path, "c.csv", samples=101)
    from rps3 import h5io
    text = h5io.text(got["scene_resolved"][0])
    assert f"file: {tmp_path / 'c.csv'}" in text, text
    (tmp_path / "elsewhere").mkdir()
    alone = write_scene(tmp_path / "elsewhere" / "alone.yaml", text)
    proc = run(alone, tmp_path / "o.h5", "-q")
    assert proc.returncode == 0, proc.stderr
    with h5py.File(tmp_path / "o.h5", "r") as g:
        np.testing.assert_array_equal(g["force"][0], got["force"][0])


@pytest.mark.parametrize("rows,words", [
    (("0, 0.01, 0.01, 0.3", "1, 0.011, 0.012, 0.3", "2, 0, 0, 0.3",
      "3, 0.012, 0.011, 0.3"),
     "c.csv:5: case 0: trajectory.path.table.centre[2] = 0: the centre must "
     "keep 0 < sqrt(x^2 + y^2) < r/2"),
    (("0, 0.01, 0.01, 0.3", "1, 0.011, 0.012, 0.3", "2, 0.012, 0.013, abc",
      "3, 0.012, 0.011, 0.3"),
     "c.csv:5:18: column z: expected a number, got 'abc'"),
])
def test_bad_path_table(runner, tmp_path, rows, words):
    (tmp_path / "c.csv").write_text(table(*rows, header="t, x, y, z"))
    scene = write_scene(tmp_path / "s.yaml", PATH_SCENE.replace("FILE", "c.csv")
                        .replace("SAMPLES", "11"))
    proc = run(scene, None, "--check")
    assert proc.returncode == 2
    assert f"{scene}:4:30: trajectory.path.file: " in proc.stderr, proc.stderr
    assert words in proc.stderr, proc.stderr


def test_path_table_keys_of_other_shapes(runner, tmp_path):
    (tmp_path / "c.csv").write_text(table("0, 0.01, 0.01, 0.3",
                                          "1, 0.011, 0.012, 0.3",
                                          "2, 0.012, 0.013, 0.3",
                                          "3, 0.012, 0.011, 0.3",
                                          header="t, x, y, z"))
    text = PATH_SCENE.replace("FILE", "c.csv").replace("SAMPLES", "11")
    proc = run(write_scene(tmp_path / "s.yaml", text.replace(
        "file: c.csv}", "file: c.csv, duration: 3}")), None, "--check")
    assert proc.returncode == 2
    assert "trajectory.path.duration: not a key of a table path" in \
        proc.stderr, proc.stderr
    proc = run(write_scene(tmp_path / "s.yaml", text.replace(
        "shape: table", "shape: line, duration: 2, start: [0.01, 0.01, 0.3], "
        "end: [0.02, 0.01, 0.3]")), None, "--check")
    assert proc.returncode == 2
    assert "trajectory.path.file: not a key of a line path" in proc.stderr
    assert run(write_scene(tmp_path / "s.yaml", text), None,
               "--check").returncode == 0


@pytest.mark.parametrize("col,units,fixed,ok", [
    ("beta", "deg", False, False), ("z_c", "mm", True, False),
    ("beta", "rad", False, True), ("z_c", "metres", True, True),
    ("t", "ms", False, False)])
def test_hdf5_units_attribute(runner, tmp_path, col, units, fixed, ok):
    """A units attribute, when a dataset has one, must name the column's SI
    unit (variable- or fixed-length string): degrees or millimetres are
    refused, naming the dataset, rather than misread."""
    with h5py.File(tmp_path / "h.h5", "w") as f:
        f["t"] = np.linspace(0, 2, 5)
        f["alpha"] = np.full(5, 0.3)
        f["beta"] = np.full(5, 0.08)
        f["z_c"] = np.full(5, 0.3)
        if fixed:
            f[col].attrs.create("units", np.bytes_(units))
        else:
            f[col].attrs["units"] = units
    scene = write_scene(tmp_path / "s.yaml",
                        SCENE.replace("FILE", "h.h5").replace("SAMPLES", "5"))
    proc = run(scene, None, "--check")
    if ok:
        assert proc.returncode == 0, proc.stderr
    else:
        assert proc.returncode == 2
        assert f"h.h5: dataset /{col}: units '{units}', but the table is in" \
            in proc.stderr, proc.stderr


def test_python_table_is_the_library_table():
    """rps3.trajectory.table: the helix's rows with rates and accelerations
    give the helix at the rows to rounding (the quintic Hermite passes
    through them); poses alone give the spline, which reproduces a cubic
    exactly; a bad row is named."""
    import rps3
    t = helix_grid()
    h = rps3.trajectory.helix(t=t)
    a = rps3.trajectory.table(t, h.pose, h.dpose, h.ddpose, t=t)
    for x, y in ((a.pose, h.pose), (a.dpose, h.dpose), (a.ddpose, h.ddpose)):
        assert np.abs(x - y).max() <= 1e-12 * max(np.abs(y).max(), 1.0)
    rows = np.array([0.21, 0.6, 1.37, 1.9, 2.7, 3.05])
    c = np.array([[0.3, 0.2, -0.05, 0.01], [0.08, 0.01, -0.004, 0.0007],
                  [0.3, 0.01, 0.002, -0.0011]])
    def cubic(x, d=0):
        p = np.polynomial.polynomial
        return np.stack([p.polyval(x, p.polyder(ck, d)) for ck in c], axis=1)
    s = rps3.trajectory.table(rows, cubic(rows), samples=101)
    ta = rows[0] + s.t
    for d, got in enumerate((s.pose, s.dpose, s.ddpose)):
        assert np.abs(got - cubic(ta, d)).max() <= 1e-11, d
    bad = h.pose.copy()
    bad[3, 2] = -0.1
    with pytest.raises(ValueError, match=r"pose: trajectory.table.pose\[3\]"):
        rps3.trajectory.table(t, bad)
    with pytest.raises(ValueError, match="times: the spline needs at least 4"):
        rps3.trajectory.table(t[:3], h.pose[:3])
