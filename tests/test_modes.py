"""Assembly modes through the runner: a sine scene around pose (0.5, 0.9,
0.2 m), condition number ~24, lies beyond the singular surface from the
level platform.  The multiroot route's cold start lands on the level-side
root with the same link lengths, whose forces are wrong ((5.69, -1.45,
-0.54) N against the true (-5.86, 4.23, 2.41) N); it must be a failed case
with RPS3_EMODE (7), never exit 0 with those forces."""

import h5py
import numpy as np

from conftest import run, write_scene

SCENE = """\
manipulator: {R: 0.2286, rho: 0.5, M: 0.18, m: 0.09, d: 0.1524}
trajectory:
  kind: sine
  mean: [0.5, 0.9, 0.2]
  amp: [0.05, 0.02, 0.01]
  freq: [0.5, 0.5, 0.5]
  duration: 2
  samples: 101
sweep:
  solver.theta: [closed_form, multiroot]
"""


def test_multiroot_on_another_mode_is_refused(runner, tmp_path):
    scene = write_scene(tmp_path / "s.yaml", SCENE)
    out = tmp_path / "o.h5"
    proc = run(scene, out, "-q")
    assert proc.returncode == 1, proc.stderr
    with h5py.File(out, "r") as f:
        np.testing.assert_array_equal(f["status"][()], [0, 7])
        msg = f["message"][1]
        msg = msg.decode() if isinstance(msg, bytes) else str(msg)
        assert "another assembly mode" in msg and "(39)" in msg, msg
        assert f["failed_at"][1] == 0
        # the closed form gives the true forces of this pose
        np.testing.assert_allclose(f["force"][0, 0], [-5.8573, 4.2312, 2.4129],
                                   atol=1e-4)
