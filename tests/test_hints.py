"""Values that look like a unit mistake are named on stderr (a warning with
FILE:LINE:COL and the key, the run goes on): lengths above 10 m
(millimetres), beta above pi/2 rad and other angles beyond 2 pi rad
(degrees), in the file, in a sweep, in waypoints and in a table's rows.
The shipped configs raise none.  ("Did you mean" for mistyped keys, values
and columns is in tests/bad_scenes/ and tests/test_table.py.)"""

import os

import pytest
from conftest import CONFIGS, run, write_scene

MM = """\
manipulator: {R: 228.6, rho: 0.5, M: 0.18, m_over_M: 0.5, d: 152.4}
trajectory:
  kind: sine
  mean: [0, 0.05, 300]
  amp: [0.1, 0, 0]
  freq: [1, 0, 0]
  phase: [90, 0, 0]
  duration: 1
  samples: 11
sweep:
  trajectory.amp[1]: [0.01, 3]
"""


def warnings(proc):
    return [ln for ln in proc.stderr.splitlines() if ": warning: " in ln]


def test_millimetres_and_degrees_are_named(runner, tmp_path):
    scene = write_scene(tmp_path / "mm.yaml", MM)
    proc = run(scene, None, "--check")
    assert proc.returncode == 0, proc.stderr  # valid, in millimetres
    got = warnings(proc)
    want = [f"{scene}:1:18: warning: manipulator.R: 228.6 m looks like "
            "millimetres (above 10 m)",
            f"{scene}:1:62: warning: manipulator.d: 152.4 m looks like "
            "millimetres",
            f"{scene}:4:9: warning: trajectory.mean[2]: 300 m looks like "
            "millimetres",
            f"{scene}:7:10: warning: trajectory.phase[0]: 90 rad looks like "
            "degrees (above 2 pi rad = 360 deg)",
            f"{scene}:11:29: warning: trajectory.amp[1]: 3 rad looks like "
            "degrees (beta above pi/2 rad = 90 deg)"]
    assert len(got) == len(want), proc.stderr
    for w in want:
        assert any(g.startswith(w) for g in got), (w, proc.stderr)


def test_degrees_in_waypoints(runner, tmp_path):
    """beta = 30 (meant as degrees) in a waypoint: a valid angle of the
    closed-form kinematics (30 rad is 30 - 8 pi = 4.87 rad), so only the
    warning tells."""
    scene = write_scene(tmp_path / "wp.yaml", """\
manipulator: {R: 0.2286, rho: 0.5, M: 0.18, m_over_M: 0.5, d: 0.1524}
trajectory:
  kind: waypoints
  waypoints:
    times: [0, 1]
    poses: [[0.1, 0.05, 0.3], [0.2, 30, 0.3]]
  samples: 11
""")
    proc = run(scene, None, "--check")
    assert warnings(proc) == [
        f"{scene}:6:31: warning: trajectory.waypoints.poses[1][1]: 30 rad "
        "looks like degrees (beta above pi/2 rad = 90 deg); scene angles are "
        "in radians"], proc.stderr


def test_table_rows_in_degrees(runner, tmp_path):
    (tmp_path / "m.csv").write_text(
        "t, alpha, beta, z_c\n0, 0.3, 0.08, 0.3\n0.5, 0.31, 0.081, 0.301\n"
        "1.0, 0.33, 5.2, 0.303\n1.5, 0.34, 0.08, 0.304\n")
    scene = write_scene(tmp_path / "s.yaml", """\
manipulator: {R: 0.2286, rho: 0.5, M: 0.18, m_over_M: 0.5, d: 0.1524}
trajectory:
  kind: table
  table: {file: m.csv}
  samples: 11
""")
    proc = run(scene, None, "--check")
    assert (f"{scene}:4:17: warning: trajectory.table.file: "
            f"{tmp_path / 'm.csv'}:4: column beta: 5.2 rad looks like degrees"
            in proc.stderr), proc.stderr


@pytest.mark.parametrize("name", sorted(f for f in os.listdir(CONFIGS)
                                        if f.endswith(".yaml")))
def test_configs_raise_no_warning(runner, name):
    proc = run(os.path.join(CONFIGS, name), None, "--check")
    assert warnings(proc) == [], proc.stderr
