"""Non-finite results through the runner: a case whose numbers overflow is
a failed case (exit 1, its status RPS3_ERANGE = 6 and a message naming the
quantity), the other cases of the sweep still complete; a mass whose weight
overflows is refused with the scene's FILE:LINE:COL."""

import h5py
import numpy as np

from conftest import run, write_scene

RANGE_SINE = """\
manipulator: {R: 0.2286, rho: 0.5, M: 0.18, m: 0.09, d: 0.1524}
trajectory:
  kind: sine
  mean: [0, 0.05, 0.3]
  amp: [0.3, 0, 0.05]
  freq: [0.5, 0, 3.7]
  duration: 1
  samples: 11
sweep:
  manipulator.M: [0.18, 1.5e307, 0.2]
"""


def test_overflowing_case_fails_alone(runner, tmp_path):
    # M = 1.5e307 kg passes the model check (M g is finite), but the forces,
    # a few times M g, overflow: that case fails with RPS3_ERANGE, the
    # others complete
    scene = write_scene(tmp_path / "s.yaml", RANGE_SINE)
    out = tmp_path / "o.h5"
    proc = run(scene, out, "-q")
    assert proc.returncode == 1, proc.stderr
    with h5py.File(out, "r") as f:
        np.testing.assert_array_equal(f["status"][()], [0, 6, 0])
        msg = f["message"][1]
        msg = msg.decode() if isinstance(msg, bytes) else str(msg)
        assert "result not finite" in msg and "is not finite" in msg, msg
        assert np.isfinite(f["force"][0]).all()
        assert np.isfinite(f["force"][2]).all()


def test_overflowing_mass_is_refused(runner, tmp_path):
    scene = write_scene(
        tmp_path / "s.yaml",
        RANGE_SINE.replace("M: 0.18", "M: 1e308")
        .replace("sweep:\n  manipulator.M: [0.18, 1.5e307, 0.2]\n", ""))
    proc = run(scene, tmp_path / "o.h5")
    assert proc.returncode == 2
    assert f"{scene}:1:" in proc.stderr and "manipulator.M" in proc.stderr, \
        proc.stderr
    assert "overflows" in proc.stderr
    assert not (tmp_path / "o.h5").exists()
