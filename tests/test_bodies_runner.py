"""General bodies in scene files (docs/runner.md, "General bodies"): the
paper's bodies written as general ones give the paper's numbers, a leg's
own key overrides the key of every leg and changes what it should only,
prismatic friction's share is its law on the links' rates, a leg key
sweeps, and `--keys` lists the keys.  The refusals (a 5-number inertia, a
negative mass, an unreal inertia, typos, keys the bodies do not read) are
tests/bad_scenes/bodies_*.yaml."""

import subprocess

import h5py
import numpy as np
import yaml

from rps3 import h5io
from conftest import RUNNER, run, write_scene

# the paper's bodies and the general ones agree to rounding: the two
# routes sum the same terms in another order
TOL_EXACT = 1e-12

R, RHO, M, MASS, D, LINK_IC = 0.2286, 0.5, 0.18, 0.09, 0.1524, 0.0013
r = RHO * R
IP = (M * r * r / 4, M * r * r / 4, M * r * r / 2)

TRAJ = """\
trajectory: {kind: sine, mean: [0.1, 0.06, 0.3], amp: [0.4, 0.03, 0.04],
             freq: [0.5, 0.8, 1.1], duration: 2, samples: 81}
"""
# both formulations, the closed form and the multiroot theta
SOLVERS = """\
sweep:
  solver.method: [lagrange, newton_euler]
  solver.theta: [closed_form, multiroot]
"""
PAPER = f"""\
manipulator:
  R: {R}
  rho: {RHO}
  M: {M}
  m: {MASS}
  d: {D}
  link_Ic: {LINK_IC}
{TRAJ}{SOLVERS}"""


def general(legs="", extra=""):
    """A general scene whose platform and cylinders are the paper's, with
    `legs` under manipulator.legs and `extra` lines in the section."""
    return f"""\
manipulator:
  R: {R}
  rho: {RHO}
  bodies: general
  platform:
    mass: {M}
    inertia: [{IP[0]!r}, 0, 0, {IP[1]!r}, 0, {IP[2]!r}]
  legs:
    cylinder: {{mass: {MASS}, com: [{D}, 0, 0],
               inertia: [0, 0, 0, {LINK_IC}, 0, {LINK_IC}]}}
{legs}{extra}{TRAJ}"""


def compute(tmp_path, name, text):
    """Run the scene, return its file's path."""
    out = tmp_path / f"{name}.h5"
    proc = run(write_scene(tmp_path / f"{name}.yaml", text), out, "-q")
    assert proc.returncode == 0, proc.stderr
    return out


def read(path, *names):
    with h5py.File(path, "r") as f:
        assert not h5io.failed(f)
        return [f[n][()] for n in names]


def effect_names(path):
    with h5py.File(path, "r") as f:
        return [h5io.text(e) for e in f["effect"][()]]


def test_paper_bodies_written_general_give_the_papers_numbers(runner,
                                                              tmp_path):
    paper = compute(tmp_path, "paper", PAPER)
    gen = compute(tmp_path, "general", general() + SOLVERS)
    assert effect_names(paper) == effect_names(gen)
    names = ("force", "force_by_effect", "theta", "lambda", "length")
    for name, a, b in zip(names, read(paper, *names), read(gen, *names)):
        assert a.shape == b.shape == (4,) + a.shape[1:], name
        # lambda is the Lagrange route's (NaN from Newton-Euler)
        np.testing.assert_array_equal(np.isnan(a), np.isnan(b), err_msg=name)
        assert np.isfinite(a[0]).all(), name
        scale = np.nanmax(np.abs(a))
        assert scale > 0, name
        assert np.nanmax(np.abs(a - b)) <= TOL_EXACT * scale, name
    # link_Ic is read: without it the forces differ
    bare = compute(tmp_path, "bare", PAPER.replace(f"link_Ic: {LINK_IC}",
                                                   "link_Ic: 0"))
    (f_bare,), (f_gen,) = read(bare, "force"), read(gen, "force")
    assert np.abs(f_bare - f_gen).max() > 1e-6 * np.abs(f_gen).max()


PISTONS = """\
    piston: {mass: 0.05, com: [-0.04, 0, 0],
             inertia: [1e-5, 0, 0, 4e-5, 0, 4e-5]}
    prismatic_friction: {viscous: 2.0, coulomb: 0.3, vreg: 0.002}
"""
LEG2 = """\
  leg2:
    piston: {mass: 0.15}
    prismatic_friction: {coulomb: 0.7}
"""


def test_a_legs_own_key_overrides_that_key_only(runner, tmp_path):
    base = compute(tmp_path, "base", general(PISTONS))
    over = compute(tmp_path, "over", general(PISTONS, LEG2))
    # the same three legs written one by one
    one_by_one = "".join(
        f"  leg{i}:\n"
        f"    cylinder: {{mass: {MASS}, com: [{D}, 0, 0], inertia: "
        f"[0, 0, 0, {LINK_IC}, 0, {LINK_IC}]}}\n"
        f"    piston: {{mass: {0.15 if i == 2 else 0.05}, com: [-0.04, 0, 0], "
        f"inertia: [1e-5, 0, 0, 4e-5, 0, 4e-5]}}\n"
        "    prismatic_friction: {viscous: 2.0, "
        f"coulomb: {0.7 if i == 2 else 0.3}, vreg: 0.002}}\n"
        for i in (1, 2, 3))
    text = general(one_by_one).replace(
        "  legs:\n    cylinder: {mass: 0.09, com: [0.1524, 0, 0],\n"
        "               inertia: [0, 0, 0, 0.0013, 0, 0.0013]}\n", "")
    assert "legs:" not in text
    explicit = compute(tmp_path, "explicit", text)
    names = ("force", "force_by_effect")
    for a, b in zip(read(over, *names), read(explicit, *names)):
        np.testing.assert_array_equal(a, b)

    eff = effect_names(base)
    assert eff == effect_names(over)
    assert eff[-1] == "prismatic_friction"
    (fb, kb, lb), (fo, ko, lo) = (read(p, "force_by_effect", "theta",
                                       "length") for p in (base, over))
    # the motion is the same: kinematics do not see the bodies
    np.testing.assert_array_equal(kb, ko)
    np.testing.assert_array_equal(lb, lo)
    scale = np.abs(fb).max()
    share = {e: k for k, e in enumerate(eff)}
    for e in ("platform_gravity", "platform_inertia"):
        assert np.abs(fb[..., share[e], :] - fo[..., share[e], :]).max() \
            <= TOL_EXACT * scale, e
    # the heavier piston of leg 2 loads every actuator (through the
    # platform); its seal's friction is leg 2's force alone
    assert (np.abs(fb[..., share["link_gravity"], :] -
                   fo[..., share["link_gravity"], :]).max(axis=(0, 1))
            > 1e-3 * scale).all()
    fric = share["prismatic_friction"]
    for leg in (0, 2):
        np.testing.assert_array_equal(fb[..., fric, leg], fo[..., fric, leg])
    assert np.abs(fb[..., fric, 1] - fo[..., fric, 1]).max() > 0.1


def test_prismatic_friction_share_is_its_law(runner, tmp_path):
    """Prismatic friction with the paper's bodies: selected without an
    effects list, its share in leg i is viscous l' + coulomb tanh(l'/vreg)
    of that leg's own coefficients, and the shares sum to the force."""
    text = PAPER.replace(SOLVERS, "").replace(
        f"  link_Ic: {LINK_IC}\n",
        f"  link_Ic: {LINK_IC}\n"
        "  legs:\n"
        "    prismatic_friction: {viscous: 2.5, coulomb: 0.3, vreg: 0.004}\n"
        "  leg3:\n"
        "    prismatic_friction: {viscous: 0.5}\n")
    out = compute(tmp_path, "pf", text)
    eff = effect_names(out)
    assert eff == ["platform_gravity", "link_gravity", "platform_inertia",
                   "link_inertia", "prismatic_friction"]
    fe, force, rate = read(out, "force_by_effect", "force", "length_rate")
    viscous = np.array([2.5, 2.5, 0.5])
    law = viscous * rate[0] + 0.3 * np.tanh(rate[0] / 0.004)
    scale = np.abs(law).max()
    assert scale > 0.1
    assert np.abs(fe[0, :, 4, :] - law).max() <= TOL_EXACT * scale
    assert np.abs(fe.sum(axis=2) - force).max() <= \
        TOL_EXACT * np.abs(force).max()
    # without the friction keys the other shares are the same
    plain = compute(tmp_path, "plain", PAPER.replace(SOLVERS, ""))
    (fp,) = read(plain, "force_by_effect")
    assert np.abs(fp[0] - fe[0, :, :4, :]).max() <= \
        TOL_EXACT * np.abs(fp).max()


def test_sweep_over_a_leg_key(runner, tmp_path):
    """A sweep over the pistons' mass of every leg, and over one component
    of one leg's inertia: the swept values are float64 variables with their
    units, the force is affine in a mass (the dynamics are linear in the
    inertial parameters), and each case's resolved scene reruns alone."""
    sweep = ("sweep:\n"
             "  manipulator.legs.piston.mass: [0, 0.05, 0.1]\n"
             "  manipulator.leg2.piston.inertia[3]: [3e-5, 5e-5]\n")
    out = compute(tmp_path, "sw", general(PISTONS) + sweep)
    with h5py.File(out, "r") as f:
        assert h5io.sweep_keys(f) == ["manipulator.legs.piston.mass",
                                      "manipulator.leg2.piston.inertia[3]"]
        mass = h5io.sweep_value(f, "manipulator.legs.piston.mass")
        inertia = h5io.sweep_value(f, "manipulator.leg2.piston.inertia[3]")
        assert mass.dtype == inertia.dtype == np.float64
        np.testing.assert_array_equal(mass, [0, 0, 0.05, 0.05, 0.1, 0.1])
        np.testing.assert_array_equal(inertia, [3e-5, 5e-5] * 3)
        var = f[h5io.key_name("manipulator.legs.piston.mass")]
        assert h5io.text(var.attrs["units"]) == "kg"
        var = f[h5io.key_name("manipulator.leg2.piston.inertia[3]")]
        assert h5io.text(var.attrs["units"]) == "kg m^2"
        force = f["force"][()]
        text = h5io.text(f["scene_resolved"][3])
    step1, step2 = force[2] - force[0], force[4] - force[2]
    assert np.abs(step1).max() > 1e-3
    assert np.abs(step1 - step2).max() <= 1e-9 * np.abs(force).max()
    # the inertia is read
    assert np.abs(force[3] - force[2]).max() > 0
    # case 3: the pistons 0.05 kg each, leg 2's Iyy 5e-5, written leg by leg
    resolved = yaml.safe_load(text)["manipulator"]
    assert "legs" not in resolved and "M" not in resolved
    assert [resolved[f"leg{i}"]["piston"]["mass"] for i in (1, 2, 3)] == \
        [0.05] * 3
    # (PyYAML reads 5e-05 as a string: YAML 1.1 floats need a dot)
    assert float(resolved["leg2"]["piston"]["inertia"][3]) == 5e-5
    alone = compute(tmp_path, "alone", text)
    (again,) = read(alone, "force")
    np.testing.assert_array_equal(again[0], force[3])


def test_keys_lists_the_bodies_keys(runner):
    keys = subprocess.run([RUNNER, "--keys"], capture_output=True, text=True,
                          check=True).stdout
    rows = {r.split(" | ")[0].strip("| `"): r.split(" | ")
            for r in keys.splitlines()[2:]}
    assert rows["manipulator.bodies"][1] == "paper or general"
    assert rows["manipulator.M"][5] == "required with bodies: paper"
    assert rows["manipulator.platform.mass"][5] == \
        "required with bodies: general"
    assert rows["manipulator.platform.inertia"][1] == "[6 numbers]"
    for who in ("legs", "leg1", "leg2", "leg3"):
        for body in ("cylinder", "piston"):
            assert rows[f"manipulator.{who}.{body}.mass"][2] == "kg"
            assert rows[f"manipulator.{who}.{body}.com"][2] == "m"
            assert rows[f"manipulator.{who}.{body}.inertia"][2] == "kg m^2"
        for law, units in (("pin_friction", ("N m s/rad", "N m", "rad/s")),
                           ("prismatic_friction", ("N s/m", "N", "m/s"))):
            for part, unit in zip(("viscous", "coulomb", "vreg"), units):
                row = rows[f"manipulator.{who}.{law}.{part}"]
                assert row[2] == unit and row[3] == ">= 0", row
    assert sum(k.startswith("manipulator.leg") for k in rows) == 4 * 12


def test_bodies_are_checked_per_swept_case(runner, tmp_path):
    """An inertia that is no real body's in one case of a sweep: refused
    before anything is written, at that swept value."""
    text = general(PISTONS) + (
        "sweep:\n  manipulator.legs.piston.inertia[3]: [4e-5, 1e-3]\n")
    scene = write_scene(tmp_path / "s.yaml", text)
    proc = run(scene, tmp_path / "o.h5")
    assert proc.returncode == 2, proc.stderr
    line = text.splitlines().index(
        "  manipulator.legs.piston.inertia[3]: [4e-5, 1e-3]") + 1
    assert proc.stderr.startswith(
        f"{scene}:{line}:46: manipulator.legs.piston.inertia[3]: case 1: "
        "leg1.piston.inertia[0] = 1e-05: violates the triangle inequality"), \
        proc.stderr
    assert not (tmp_path / "o.h5").exists()
