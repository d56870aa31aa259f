"""Trajectory kinds waypoints and path through the runner: the paper's helix
as a path gives the helix's results, the rates and accelerations the runner
writes are the derivatives of what it writes (central differences of the
sampled output), the centre traces the requested shape, a case's resolved
scene reruns alone to the same numbers, and every refusal names its key
(the refusals themselves are scenes in tests/bad_scenes/).  The tight
derivative checks are in tests/test_traj_kinds.c."""

import h5py
import numpy as np
import pytest
import yaml
from conftest import run, write_scene
from rps3 import h5io

KINDS = ("paper_path", "pick_place", "circle", "line")


def load(h5, *names):
    with h5py.File(h5, "r") as f:
        return [f[n][()] for n in names]


def test_helix_as_path_is_the_helix(config_runs):
    """Round trip: configs/paper_path.yaml (the helix written as a path of
    the centre) against configs/paper.yaml (the helix kind).  1e-12: the two
    compute phi(t) with different roundings (tests/test_traj_kinds.c)."""
    names = ("time", "alpha", "beta", "z_c", "x_c", "y_c", "length",
             "length_rate", "length_accel", "force", "force_by_effect")
    a = load(config_runs["paper"][0], *names)
    b = load(config_runs["paper_path"][0], *names)
    for n, x, y in zip(names, a, b):
        scale = max(np.abs(x).max(), 1e-300)
        assert np.abs(x - y).max() <= 1e-12 * scale, n


@pytest.mark.parametrize("name", KINDS)
def test_rates_are_derivatives_of_the_output(config_runs, name):
    """length_rate and length_accel against central differences of length
    and length_rate over the output grid.  A central difference is off by
    h^2/6 times the third derivative (estimated from the written
    accelerations); twice that bounds the error.  Where an LSPB
    acceleration jumps (a blend corner) the samples around the jump are
    left out of the second check."""
    t, l, dl, ddl = load(config_runs[name][0], "time", "length",
                         "length_rate", "length_accel")
    with h5py.File(config_runs[name][0], "r") as f:
        traj = yaml.safe_load(h5io.text(f["scene"][()]))["trajectory"]
    # a minimum-jerk path's acceleration is smooth: no jump to leave out
    # (its snap peaks where the speed does, far above its median)
    smooth = traj.get("path", {}).get("law") == "minimum_jerk"
    h = t[1] - t[0]
    assert np.allclose(np.diff(t), h, rtol=1e-9)
    for c in range(l.shape[0]):
        d4 = np.abs(ddl[c, 2:] - 2 * ddl[c, 1:-1] + ddl[c, :-2]) / h**2
        # a jump shows as a second difference far above its neighbours'
        jump = (d4 > 100 * np.median(d4, axis=0) + 1e-9).any(axis=1)
        jump &= not smooth
        ok = ~(jump | np.roll(jump, 1) | np.roll(jump, -1))
        assert ok.mean() > 0.98
        e1 = np.abs((l[c, 2:] - l[c, :-2]) / (2 * h) - dl[c, 1:-1])
        d3 = np.abs(ddl[c, 2:] - ddl[c, :-2]) / (2 * h)
        assert e1[ok].max() <= (2 * h * h / 6 * d3[ok].max() +
                                1e-12 * np.abs(dl).max())
        e2 = np.abs((dl[c, 2:] - dl[c, :-2]) / (2 * h) - ddl[c, 1:-1])
        bound = 2 * h * h / 6 * d4[ok].max() + 1e-12 * np.abs(ddl).max()
        assert e2[ok].max() <= bound, (name, c, e2[ok].max(), bound)


def path_keys(h5):
    """The path section of the scene a file was run from."""
    with h5py.File(h5, "r") as f:
        return yaml.safe_load(h5io.text(f["scene"][()]))["trajectory"]["path"]


def test_circle_is_traced(config_runs):
    h5 = config_runs["circle"][0]
    x, y, z = load(h5, "x_c", "y_c", "z_c")
    path = path_keys(h5)
    (cx, cy, cz), radius = path["centre"], path["radius"]
    r = np.hypot(x - cx, y - cy)
    assert np.abs(r - radius).max() <= 1e-12
    assert np.abs(z - cz).max() <= 1e-15
    # one whole turn: the polar angle about the circle's centre covers 2 pi
    ang = np.unwrap(np.arctan2(y - cy, x - cx), axis=1)
    assert np.allclose(ang[:, -1] - ang[:, 0], 2 * np.pi, rtol=1e-12)


def test_line_is_traced(config_runs):
    h5 = config_runs["line"][0]
    x, y, z = load(h5, "x_c", "y_c", "z_c")
    path = path_keys(h5)
    p0 = np.array(path["start"])
    p1 = np.array(path["end"])
    p = np.stack([x[0], y[0], z[0]], axis=1)
    d = (p1 - p0) / np.linalg.norm(p1 - p0)
    off = np.cross(p - p0, d)
    assert np.abs(off).max() <= 1e-12
    assert np.allclose(p[0], p0, atol=1e-15) and np.allclose(p[-1], p1,
                                                             atol=1e-15)


@pytest.mark.parametrize("name", ("circle", "line"))
def test_example_paths_keep_clear_of_singular_spikes(config_runs, name):
    """The shipped example paths stay where the force transmission is
    moderate: no sample above trans_warn (warn bit 8), forces of the order
    of the platform's weight, not the thousands of newtons near the
    singular tilts."""
    h5, proc = config_runs[name]
    assert proc.returncode == 0, proc.stderr
    with h5py.File(h5, "r") as f:
        assert not (f["warn"][0] & 8).any()
        assert np.nanmax(f["transmission"][0]) < 100
        # |F| below 20 N: 10 times the weights the links carry (M g and
        # the links' m g, about 2.6 N), far from the 1900-3000 N spikes
        assert np.nanmax(np.abs(f["force"][0])) < 20


def test_pick_place_hits_waypoints_and_keeps_limits(config_runs):
    h5 = config_runs["pick_place"][0]
    t, a, b, z = load(h5, "time", "alpha", "beta", "z_c")
    with h5py.File(h5, "r") as f:
        scene = yaml.safe_load(h5io.text(f["scene"][()]))
    wp = scene["trajectory"]["waypoints"]
    poses = np.array(wp["poses"])
    assert np.allclose([a[0, 0], b[0, 0], z[0, 0]], poses[0], atol=1e-15)
    assert np.allclose([a[0, -1], b[0, -1], z[0, -1]], poses[-1], atol=1e-15)
    # the limits stretched the turn: the span is longer than asked
    assert t[-1] > wp["times"][-1] + 0.5
    # and the sampled rate never exceeds them
    rate = np.abs(np.diff(a[0])) / np.diff(t)
    assert rate.max() <= wp["vmax"][0] * (1 + 1e-9)
    # every waypoint pose is visited (rests are at the waypoints)
    q = np.stack([a[0], b[0], z[0]], axis=1)
    for p in poses:
        assert np.abs(q - p).max(axis=1).min() <= 1e-3


@pytest.mark.parametrize("name", ("pick_place", "circle"))
def test_resolved_scene_reruns(runner, config_runs, tmp_path, name):
    """The resolved scene of a new kind (lists of waypoints, the path's
    shape keys) is a full scene: run alone it gives the same forces."""
    h5 = config_runs[name][0]
    with h5py.File(h5, "r") as f:
        text = h5io.text(f["scene_resolved"][0])
        force = f["force"][0]
    alone = write_scene(tmp_path / f"{name}.yaml", text)
    proc = run(alone, tmp_path / "o.h5", "-q")
    assert proc.returncode == 0, proc.stderr
    with h5py.File(tmp_path / "o.h5", "r") as g:
        np.testing.assert_array_equal(g["force"][0], force)


def test_trajectory_figures_are_written(config_runs, tmp_path):
    """analysis/trajectories.py, as `make trajectories` runs it."""
    import os
    import subprocess
    import sys

    from conftest import ANALYSIS
    # and tables of the pose and of the centre (configs/measured.yaml,
    # path_table.yaml), whose rates the C tests check
    names = KINDS + ("measured", "path_table")
    runs = [str(config_runs[n][0]) for n in names]
    proc = subprocess.run([sys.executable,
                           os.path.join(ANALYSIS, "trajectories.py"),
                           str(tmp_path)] + runs,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    for n in names:
        data = (tmp_path / f"traj_{n}.png").read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20000, n
