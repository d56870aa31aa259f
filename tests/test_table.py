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
    kind = "a FIFO" if name.startswith("fifo") else "a directory"
    assert (f"{name}: is {kind}: a table is a regular file of at most 1 GiB"
            in proc.stderr), proc.stderr


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
    (("0, 0.01, 0.01, 0.3", "1, 0.011, 1e-310, 0.3", "2, 0.012, 0.013, 0.3",
      "3, 0.012, 0.011, 0.3"),
     "c.csv:4:11: column y: '1e-310' is subnormal"),
    (("0, 0.01, 0.01, 0.3", "1e-200, 0.011, 0.012, 0.3",
      "2, 0.012, 0.013, 0.3", "3, 0.012, 0.011, 0.3"),
     "c.csv:4: column t: 1e-200 after 0: the rows are 1e-200 s apart, too "
     "close relative to the time scale 3 s"),
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


# --- hostile tables: every refusal names the file, the row or dataset and
# the real cause, in printable text -----------------------------------------

def check_refused(tmp_path, name, scene_text=SCENE, key="trajectory.table.file",
                  col=17):
    """--check on a scene whose table is tmp_path/name, under a 4 GiB
    address-space limit (a reader that allocated what a file declares
    would fail rather than take the machine's memory): exit 2 and one
    stderr line, printable text, on the file key; that line."""
    import resource
    import subprocess

    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))

    scene = write_scene(tmp_path / "s.yaml", scene_text.replace("FILE", name)
                        .replace("SAMPLES", "11"))
    proc = subprocess.run([RUNNER_PATH, str(scene), "--check"],
                          capture_output=True, timeout=60, preexec_fn=limit)
    text = proc.stderr.decode("utf-8")  # strict: valid UTF-8 or it fails
    assert proc.returncode == 2, text
    lines = text.splitlines()
    assert len(lines) == 1, text
    assert lines[0].isprintable(), repr(lines[0])
    assert lines[0].startswith(f"{scene}:4:{col}: {key}: {tmp_path / name}"), \
        lines[0]
    return lines[0]


from conftest import RUNNER as RUNNER_PATH  # noqa: E402


def h5_table(path, n=5, skip=()):
    """A valid pose table of n rows at path, less the datasets in skip;
    the open h5py.File for the caller to add the hostile one."""
    f = h5py.File(path, "w")
    cols = {"t": np.linspace(0, 2, n), "alpha": np.full(n, 0.3),
            "beta": np.full(n, 0.08), "z_c": np.full(n, 0.3)}
    for k, v in cols.items():
        if k not in skip:
            f[k] = v
    return f


def hostile_dangling(f, col, tmp):
    f[col] = h5py.SoftLink("/nowhere/" + col)


def hostile_elink_missing(f, col, tmp):
    f[col] = h5py.ExternalLink(str(tmp / "gone.h5"), "/" + col)


def hostile_elink(f, col, tmp):
    with h5py.File(tmp / "other.h5", "w") as g:
        g[col] = np.linspace(0, 2, 5) if col == "t" else np.full(5, 0.3)
    f[col] = h5py.ExternalLink(str(tmp / "other.h5"), "/" + col)


def hostile_group(f, col, tmp):
    f.create_group(col)


def hostile_compound(f, col, tmp):
    f[col] = np.zeros(5, dtype=[("a", "f8"), ("b", "i4")])


def hostile_string(f, col, tmp):
    f[col] = np.array([b"0.3"] * 5)


def hostile_2d(f, col, tmp):
    f[col] = np.zeros((5, 2))


def hostile_scalar(f, col, tmp):
    f[col] = 0.3


def hostile_vds_missing(f, col, tmp):
    with h5py.File(tmp / "src.h5", "w") as g:
        g["d"] = np.full(5, 0.3)
    lay = h5py.VirtualLayout(shape=(5,), dtype="f8")
    lay[:] = h5py.VirtualSource(str(tmp / "src.h5"), "d", shape=(5,))
    f.create_virtual_dataset(col, lay)
    (tmp / "src.h5").unlink()


def hostile_vds(f, col, tmp):
    with h5py.File(tmp / "src.h5", "w") as g:
        g["d"] = np.linspace(0, 2, 5) if col == "t" else np.full(5, 0.3)
    lay = h5py.VirtualLayout(shape=(5,), dtype="f8")
    lay[:] = h5py.VirtualSource(str(tmp / "src.h5"), "d", shape=(5,))
    f.create_virtual_dataset(col, lay)


def hostile_external(f, col, tmp):
    f.create_dataset(col, shape=(5,), dtype="f8",
                     external=[("/etc/passwd", 0, 40)])


def hostile_external_own(f, col, tmp):
    raw = tmp / "raw.bin"
    (np.linspace(0, 2, 5) if col == "t" else np.full(5, 0.3)).tofile(raw)
    f.create_dataset(col, shape=(5,), dtype="<f8", external=[(str(raw), 0, 40)])


@pytest.mark.parametrize("col", ["t", "z_c"])
@pytest.mark.parametrize("make,words", [
    (hostile_dangling, "a soft link to '/nowhere/COL', which names no object "
                       "of the file (a dangling link)"),
    (hostile_elink_missing, "an external link to TMP/gone.h5:/COL: a table's "
                            "columns must be stored in the table file itself"),
    (hostile_elink, "an external link to TMP/other.h5:/COL"),
    (hostile_group, "a group, not a dataset"),
    (hostile_compound, "of a compound type, not numbers"),
    (hostile_string, "of a string type, not numbers"),
    (hostile_2d, "2 dimensions; a column has one"),
    (hostile_scalar, "a single value (a scalar)"),
    (hostile_vds_missing, "a virtual dataset, its rows in TMP/src.h5:d, which "
                          "is missing"),
    (hostile_vds, "a virtual dataset, its rows in TMP/src.h5:d: a table's "
                  "columns must be stored in the table file itself"),
    (hostile_external, "stored in the external raw file '/etc/passwd': a "
                       "table's columns must be stored in the table file"),
    (hostile_external_own, "stored in the external raw file 'TMP/raw.bin'"),
])
def test_hdf5_dataset_that_cannot_be_read(runner, tmp_path, col, make, words):
    """A column's dataset that exists but cannot be opened or read as the
    table's own numbers (a dangling soft link, an external link, a group,
    a compound, string or 2-D type, a virtual dataset, storage in an
    external raw file: rows from files the table's checks never saw) is
    refused naming the file, the dataset and the cause, in printable
    text; /t (which gives the rows) and a value column alike."""
    with h5_table(tmp_path / "h.h5", skip=(col,)) as f:
        make(f, col, tmp_path)
    line = check_refused(tmp_path, "h.h5")
    want = words.replace("COL", col).replace("TMP", str(tmp_path))
    assert f"h.h5: dataset /{col}: {want}" in line, line


@pytest.mark.parametrize("rows,cols,words", [
    # one dataset of 4e8 rows: 3.2 GB, in a file of a few kB
    ({"t": 400_000_000}, ("t", "alpha", "beta", "z_c"),
     "dataset /t: declares 400000000 rows of 8-byte numbers, 3.2 GB as read: "
     "above the table limit of 1 GiB"),
    ({"z_c": 400_000_000}, ("t", "alpha", "beta", "z_c"),
     "dataset /z_c: declares 400000000 rows of 8-byte numbers"),
    # each under the limit, together above it
    ({}, ("t", "alpha", "beta", "z_c"), None),
])
def test_hdf5_declared_size_is_checked(runner, tmp_path, rows, cols, words):
    """Datasets declared huge but stored in unwritten chunks (the file
    stays a few kB, far below the 1 GiB file limit) are refused from what
    they declare (rows x element size, each and summed) before anything
    is allocated: at once, within a 4 GiB address space."""
    n = 40_000_000  # 4 x 4e7 x 8 bytes = 1.28 GB together
    with h5py.File(tmp_path / "h.h5", "w") as f:
        for c in cols:
            m = rows.get(c, n if not rows else 5)
            f.create_dataset(c, shape=(m,), dtype="f8", chunks=(min(m, 1024),))
    assert (tmp_path / "h.h5").stat().st_size < 64 * 1024
    line = check_refused(tmp_path, "h.h5")
    if words is None:
        words = ("dataset /z_c: with it the datasets declare 1.28 GB as read "
                 "(40000000 rows each): above the table limit of 1 GiB")
    assert words in line, line


def test_hdf5_memory_size_is_checked(runner, tmp_path):
    """Ten columns of 1.3e7 rows declare 1.04 GB (under 1 GiB), but the
    table holds 88 bytes a row in memory (the spline's work with it):
    1.14 GB, refused before anything is allocated."""
    n = 13_000_000
    names = ("t", *POSE, *(c + "_dot" for c in POSE),
             *(c + "_ddot" for c in POSE))
    with h5py.File(tmp_path / "h.h5", "w") as f:
        for c in names:
            f.create_dataset(c, shape=(n,), dtype="f8", chunks=(4096,))
    line = check_refused(tmp_path, "h.h5")
    assert ("h.h5: 13000000 rows need 1.14 GB in memory (88 bytes a row): "
            "above the table limit of 1 GiB") in line, line


@pytest.mark.parametrize("col", ["t", "alpha"])
def test_hdf5_subnormal_and_time_causes(runner, tmp_path, col):
    """The numeric causes named for CSV cells are named for datasets too,
    with the dataset and the row."""
    with h5_table(tmp_path / "h.h5", skip=(col,)) as f:
        v = np.linspace(0, 2, 5) if col == "t" else np.full(5, 0.3)
        v[3] = 1e-310 if col == "alpha" else v[3]
        if col == "t":
            v[:] = [-1e308, -0.5e308, 0, 0.5e308, 1e308]
        f[col] = v
    line = check_refused(tmp_path, "h.h5")
    if col == "alpha":
        assert "h.h5: dataset /alpha, row 3: 1e-310 is subnormal" in line, line
    else:
        assert ("h.h5, row 4: dataset /t: 1e+308 is more "
                "than 1.8e308 s after the first row's") in line, line
        assert "the time range overflows a double" in line, line


def test_hdf5_missing_dataset_is_named_as_one(runner, tmp_path):
    with h5_table(tmp_path / "h.h5", skip=("beta",)):
        pass
    line = check_refused(tmp_path, "h.h5")
    assert "h.h5: missing dataset /beta (a table has t, alpha" in line, line


def line_ends(text, end):
    return text.replace("\n", end)


@pytest.mark.parametrize("end", ["\r\n", "\r", "mixed"])
def test_csv_line_ends_are_accepted(runner, tmp_path, end):
    """LF, CR LF (Windows) and CR alone (classic Mac OS) all end a line:
    the same rows give the same forces bit for bit, and a bad cell is
    named at the same line and column whatever the line ends."""
    rows = table(*GOOD)
    if end == "mixed":
        parts = rows.split("\n")
        text = "".join(p + ("\r\n", "\r", "\n")[i % 3]
                       for i, p in enumerate(parts[:-1]))
    else:
        text = line_ends(rows, end)
    (tmp_path / "lf.csv").write_bytes(rows.encode())
    (tmp_path / "x.csv").write_bytes(text.encode())
    a = run_table(tmp_path, "lf.csv", samples=11)
    b = run_table(tmp_path, "x.csv", samples=11)
    np.testing.assert_array_equal(a["force"], b["force"])
    bad_rows = table(GOOD[0], GOOD[1], "1.0, 0.33, abc, 0.303", *GOOD[3:])
    if end == "mixed":
        parts = bad_rows.split("\n")
        text = "".join(p + ("\r\n", "\r", "\n")[i % 3]
                       for i, p in enumerate(parts[:-1]))
    else:
        text = line_ends(bad_rows, end)
    (tmp_path / "x.csv").write_bytes(text.encode())
    line = check_refused(tmp_path, "x.csv")
    assert "x.csv:5:12: column beta: expected a number, got 'abc'" in line, line


@pytest.mark.parametrize("cell", [
    "0.3" + "0" * 69 + "1",            # 73 characters
    "0.3" + "0" * 996 + "1",           # 1000
    "0" * 4000 + "0.3",                # leading zeros
    "3" + "0" * 300 + "e-301",         # a long mantissa, a scaled exponent
    "0.29999999999999998889776975374843459576368331909179687500000000000001",
])
def test_csv_long_decimals_parse(runner, tmp_path, cell):
    """A decimal of any length that strtod reads is read (and rounded as
    strtod rounds it): the same forces as the short 0.3."""
    short = table(*GOOD)
    rows = list(GOOD)
    rows[2] = rows[2].replace("0.33", "0.3")
    (tmp_path / "a.csv").write_text(table(*rows))
    rows[2] = rows[2].replace("0.3,", cell + ",", 1)
    assert cell in rows[2]
    (tmp_path / "b.csv").write_text(table(*rows))
    assert float(cell) == 0.3
    a = run_table(tmp_path, "a.csv", samples=11)
    b = run_table(tmp_path, "b.csv", samples=11)
    np.testing.assert_array_equal(a["force"], b["force"])
    del short


def test_csv_long_bad_cell_is_quoted_short(runner, tmp_path):
    cell = "0.3" + "0" * 100 + "x"
    rows = list(GOOD)
    rows[2] = "1.0, " + cell + ", 0.082, 0.303"
    (tmp_path / "m.csv").write_text(table(*rows))
    line = check_refused(tmp_path, "m.csv")
    assert ("m.csv:5:6: column alpha: expected a number, got '0.3" +
            "0" * 37 + "'...") in line, line


@pytest.mark.parametrize("rows,words", [
    # subnormal and underflowing numbers: named as such, not as infinite
    (("1e-310, 0.3, 0.08, 0.30", *GOOD[1:]),
     "m.csv:3:1: column t: '1e-310' is subnormal (nonzero but below 2.2e-308"),
    ((GOOD[0], "0.5, -4.9e-320, 0.081, 0.301", *GOOD[2:]),
     "m.csv:4:6: column alpha: '-4.9e-320' is subnormal"),
    ((GOOD[0], "0.5, 0.31, 1e-400, 0.301", *GOOD[2:]),
     "m.csv:4:12: column beta: '1e-400' underflows to 0"),
    ((GOOD[0], "0.5, 0.31, 0.081, -1e999", *GOOD[2:]),
     "m.csv:4:19: column z_c: '-1e999' is not a finite number (beyond the "
     "largest double"),
    # a time range that overflows a double
    (("-1e308, 0.3, 0.08, 0.30", "-0.5e308, 0.31, 0.081, 0.301",
      "0, 0.33, 0.082, 0.303", "0.5e308, 0.34, 0.08, 0.304",
      "1e308, 0.35, 0.079, 0.305"),
     "m.csv:7: column t: 1e+308 is more than 1.8e308 s after the first row's "
     "-1e+308: the time range overflows a double"),
    # rows so close that the step's square underflows
    (tuple("%g, %s" % (i * 1e-300, g.split(", ", 1)[1])
           for i, g in enumerate(GOOD)),
     "m.csv:4: column t: 1e-300 after 0: the rows are 1e-300 s apart, a "
     "spacing too small for a double: the interpolant's acceleration divides "
     "by the step squared, which underflows"),
    # rows close relative to the time scale (1e-300 s after 0, then 1 s
    # steps; and microseconds at 1e9 s)
    (("0, 0.3, 0.08, 0.30", "1e-300, 0.31, 0.081, 0.301",
      "1, 0.33, 0.082, 0.303", "2, 0.34, 0.08, 0.304"),
     "m.csv:4: column t: 1e-300 after 0: the rows are 1e-300 s apart, too "
     "close relative to the time scale 2 s"),
    (tuple("%.17g, %s" % (1e9 + i * 1e-6, g.split(", ", 1)[1])
           for i, g in enumerate(GOOD)),
     "too close relative to the time scale 1e+09 s (the largest |t|)"),
    # rows whose change overflows the interpolant's acceleration
    (tuple("%g, %s, 0.08, 0.3" % (i * 2e-154, 0.3 + 0.2 * (i % 2))
           for i in range(5)),
     "m.csv:4: column alpha: changes by 0.2 in 2e-154 s from the previous "
     "row: the spacing of the rows is too small for so large a change"),
    (("0, 0.3, 0.08, 0.30", "0.5, 0.31, 0.081, 0.301",
      "1.0, 0.33, 1.7e308, 0.303", *GOOD[3:]),
     "m.csv:5: column beta: changes by 1.7e+308 in 0.5 s from the previous "
     "row: the spacing of the rows is too small for so large a change"),
    # values whose change overflows a double
    (("0, 1e308, 0.08, 0.30", "0.5, -1e308, 0.081, 0.301", *GOOD[2:]),
     "m.csv:4: column alpha: -1e+308 after 1e+308: the change between the "
     "rows overflows a double"),
])
def test_csv_numeric_causes(runner, tmp_path, rows, words):
    """Each numeric cause is named with its row (and column), not as
    another: a subnormal or underflowing cell, a time range or a value
    change that overflows a double, a spacing too small."""
    (tmp_path / "m.csv").write_text(table(*rows))
    line = check_refused(tmp_path, "m.csv")
    assert words in line, line


def test_csv_bytes_quoted_printably(runner, tmp_path):
    """Control characters and bytes that are not UTF-8 in a quoted header
    name or cell are written as \\xNN: the message is printable text."""
    (tmp_path / "m.csv").write_bytes(
        b"t, alpha, beta, z_c\x01\xff\n" + "\n".join(GOOD).encode() + b"\n")
    line = check_refused(tmp_path, "m.csv")
    assert "column 'z_c\\x01\\xFF': unknown column" in line, line
    rows = "\n".join(GOOD[:2]).encode() + b"\n1.0, 0.3\x1b[2J\xc3, 0.08, 0.3\n"
    (tmp_path / "m.csv").write_bytes(b"t, alpha, beta, z_c\n" + rows)
    line = check_refused(tmp_path, "m.csv")
    assert "got '0.3\\x1B[2J\\xC3'" in line, line


def test_hdf5_long_units_are_checked(runner, tmp_path):
    """A units attribute longer than the reader's buffer is quoted (cut)
    and refused, not taken for no units."""
    units = "degrees" + " (of arc, as written by the logger)" * 4
    with h5_table(tmp_path / "h.h5") as f:
        f["beta"].attrs.create("units", np.bytes_(units))
    line = check_refused(tmp_path, "h.h5")
    assert "h.h5: dataset /beta: units 'degrees (of arc" in line, line


def test_csv_rows_in_memory_are_checked(runner, tmp_path):
    """A CSV table's rows take 68 bytes each in memory (8 numbers and the
    line number) against 8 in the file: 16 million short rows (128 MB of
    file, under the 1 GiB file limit) would need 1.09 GB, refused before
    anything is allocated for them."""
    n = 16_000_000
    with open(tmp_path / "m.csv", "wb") as f:
        f.write(b"t,alpha,beta,z_c\n")
        f.write(b"0,0,0,0\n" * n)
    try:
        line = check_refused(tmp_path, "m.csv")
    finally:
        (tmp_path / "m.csv").unlink()
    assert (f"m.csv: {n} rows need 1.09 GB in memory (68 bytes a row): above "
            "the table limit of 1 GiB") in line, line


def hostile_filter(f, col, tmp):
    # lzf is h5py's own filter: the HDF5 library the runner links lacks it
    f.create_dataset(col, data=np.linspace(0, 2, 5), compression="lzf")


def hostile_enum(f, col, tmp):
    f.create_dataset(col, data=np.zeros(5, dtype="i1"),
                     dtype=h5py.enum_dtype({"a": 0, "b": 1}, basetype="i1"))


def hostile_vlen(f, col, tmp):
    f.create_dataset(col, shape=(5,), dtype=h5py.vlen_dtype("f8"))


def hostile_null(f, col, tmp):
    f.create_dataset(col, data=h5py.Empty("f8"))


def hostile_control_link(f, col, tmp):
    f[col] = h5py.SoftLink("/n\u00e9\x01\x1b[2J")


@pytest.mark.parametrize("make,words", [
    (hostile_filter, "cannot read it as numbers: can't read data: required "
                     "filter 'lzf' is not registered"),
    (hostile_enum, "of an enumeration type, not numbers"),
    (hostile_vlen, "of a variable-length type, not numbers"),
    (hostile_null, "holds nothing (a null dataspace)"),
    (hostile_control_link, "a soft link to '/n\u00e9\\x01\\x1B[2J', which "
                           "names no object"),
])
def test_hdf5_more_unreadable_datasets(runner, tmp_path, make, words):
    """More of the class: a filter the library lacks, other non-numeric
    types, a null dataspace, a link target with control characters (quoted
    as \\xNN, UTF-8 kept)."""
    with h5_table(tmp_path / "h.h5", skip=("z_c",)) as f:
        make(f, "z_c", tmp_path)
    line = check_refused(tmp_path, "h.h5")
    assert f"h.h5: dataset /z_c: {words}" in line, line


def test_hdf5_newer_format_and_damaged_files(runner, tmp_path):
    """A compound written with the newest format (a datatype message the
    runner's HDF5 may not know), a truncated file and a file whose root
    group is damaged: each a printable message naming the file, and the
    dataset where one is concerned, with HDF5's cause."""
    with h5py.File(tmp_path / "h.h5", "w", libver="latest") as f:
        for k, v in (("t", np.linspace(0, 2, 5)), ("alpha", np.full(5, 0.3)),
                     ("beta", np.full(5, 0.08))):
            f[k] = v
        f["z_c"] = np.zeros(5, dtype=[("a", "f8"), ("b", "i4")])
    line = check_refused(tmp_path, "h.h5")
    assert ("h.h5: dataset /z_c: cannot be opened: " in line or
            "h.h5: dataset /z_c: of a compound type" in line), line
    with h5_table(tmp_path / "h.h5"):
        pass
    data = (tmp_path / "h.h5").read_bytes()
    (tmp_path / "h.h5").write_bytes(data[:len(data) // 2])
    line = check_refused(tmp_path, "h.h5")
    assert "h.h5: cannot open as an HDF5 file: unable to open file: " \
        "truncated file" in line, line
    # the root group's symbol table node (after the superblock and the
    # root's object header), its signature overwritten
    with h5_table(tmp_path / "h.h5"):
        pass
    data = bytearray((tmp_path / "h.h5").read_bytes())
    at = data.find(b"SNOD")
    assert at > 0
    data[at:at + 4] = b"XXXX"
    (tmp_path / "h.h5").write_bytes(bytes(data))
    line = check_refused(tmp_path, "h.h5")
    assert ("h.h5: dataset /t: cannot look it up in the file's root group: "
            "unable to get link info: bad symbol table node signature"
            ) in line, line


def test_csv_rates_that_overflow_the_interpolant(runner, tmp_path):
    """Finite rates so large for their step that the cubic Hermite
    interpolant's acceleration (rate / step) overflows: named by the rate
    column and the row, not as a pose out of reach or a failed spline."""
    rows = ["%s, 0, 0, 0" % g for g in GOOD]
    rows[2] = GOOD[2] + ", 0, 1e308, 0"
    (tmp_path / "m.csv").write_text(table(
        *rows, header="t, alpha, beta, z_c, alpha_dot, beta_dot, z_c_dot"))
    line = check_refused(tmp_path, "m.csv")
    assert ("m.csv:5: column beta_dot: 0 and 1e+308 across a step of 0.5 s: "
            "the interpolant's acceleration there (of order rate / step) "
            "overflows a double") in line, line
