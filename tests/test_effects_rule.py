"""The rule for configured effects (docs/runner.md, "Effects"): an omitted
`effects` list selects the paper's four effects plus a configured payload
or pin friction; an explicit list that leaves out a configured one is
refused with FILE:LINE:COL naming both keys (tests/bad_scenes/ has the two
plain cases).  A 0.5 kg payload left out silently would give a peak
force 4.66 times too small."""

import h5py
import numpy as np

from conftest import run, write_scene

BASE = """\
manipulator:
  R: 0.2286
  rho: 0.5
  M: 0.18
  m: 0.09
  d: 0.1524
  payload: {mass: 0.5, com: [0, 0, 0.02], inertia: [1e-4, 1e-4, 1e-4]}
  pin_friction: {viscous: 0.01}
trajectory: {kind: sine, mean: [0, 0.05, 0.3], amp: [0.3, 0.02, 0.03],
             freq: [0.5, 1, 1], duration: 1, samples: 21}
"""
ALL = ("effects: [platform_gravity, link_gravity, platform_inertia, "
       "link_inertia, payload, pin_friction]\n")


def forces(tmp_path, name, text):
    out = tmp_path / f"{name}.h5"
    proc = run(write_scene(tmp_path / f"{name}.yaml", text), out, "-q")
    assert proc.returncode == 0, proc.stderr
    with h5py.File(out, "r") as f:
        return f["force"][0], f["scene_resolved"][0]


def test_omitted_list_selects_what_is_configured(runner, tmp_path):
    implicit, scene = forces(tmp_path, "implicit", BASE)
    explicit, _ = forces(tmp_path, "explicit", BASE + ALL)
    np.testing.assert_array_equal(implicit, explicit)
    text = scene.decode() if isinstance(scene, bytes) else str(scene)
    # the resolved scene's own effects: line (solver.outputs names an
    # "effects" output too)
    effects = [ln for ln in text.splitlines() if ln.startswith("effects:")]
    assert len(effects) == 1 and "payload" in effects[0], text
    # without the payload and friction keys: the paper's four
    bare = BASE.replace("  payload: {mass: 0.5, com: [0, 0, 0.02], "
                        "inertia: [1e-4, 1e-4, 1e-4]}\n", "") \
        .replace("  pin_friction: {viscous: 0.01}\n", "")
    four, _ = forces(tmp_path, "four", bare)
    paper4, _ = forces(tmp_path, "paper4", bare + "effects: [platform_gravity,"
                       " link_gravity, platform_inertia, link_inertia]\n")
    np.testing.assert_array_equal(four, paper4)
    assert np.abs(implicit).max() > 2 * np.abs(four).max()


def test_explicit_list_must_name_configured(runner, tmp_path):
    scene = write_scene(tmp_path / "s.yaml", BASE + ALL.replace(
        ", pin_friction]", "]"))
    proc = run(scene, tmp_path / "o.h5")
    assert proc.returncode == 2
    assert proc.stderr.startswith(f"{scene}:11:10: effects: leaves out "
                                  "pin_friction, but manipulator.pin_friction"
                                  ".viscous is configured (8:27)"), proc.stderr
    assert not (tmp_path / "o.h5").exists()


def test_swept_payload_is_checked_per_case(runner, tmp_path):
    text = BASE.replace("mass: 0.5", "mass: 0") + ALL.replace(
        ", payload, pin_friction]", ", pin_friction]") + \
        "sweep:\n  manipulator.payload.mass: [0, 0.25]\n"
    text = text.replace("inertia: [1e-4, 1e-4, 1e-4]", "inertia: [0, 0, 0]")
    scene = write_scene(tmp_path / "s.yaml", text)
    proc = run(scene, tmp_path / "o.h5")
    assert proc.returncode == 2
    assert "case 1: leaves out payload" in proc.stderr, proc.stderr
    assert "manipulator.payload.mass" in proc.stderr
