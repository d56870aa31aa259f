"""The library's forces against two oracles that read only the model's inputs:

- the SymPy derivation of tests/oracle.py (Lagrangian in the pose
  coordinates, no multipliers, geometry from R, rho and the pin angles);
- MuJoCo, through the model of tests/mujoco_model.py (its own mass matrix,
  bias forces and Jacobians; the ball-joint reactions solved exactly).

Neither shares a line or a derived field with src/: a wrong inertia, a wrong
constant or a wrong Jacobian in the library shows here even when the
library's own identities (energy balance, Lagrange = Newton-Euler) still
hold.  States: the paper's helix (Table II, blend corners included) and
random sines through the workspace, with payload and pin friction.

Tolerances: both oracles are exact formulations evaluated in double, and
agree with the library to ~1e-15 (SymPy) and ~1e-11 (MuJoCo, whose pistons
carry EPS_MASS = 1e-12 kg because it refuses massless moving bodies: 1e-11
N against forces of ~1 N); 1e-9 of the largest force bounds both with room,
while a 1 % wrong inertia moves the forces by ~1e-4 and more.
"""

import numpy as np
import pytest

import mujoco
import mujoco_model
import oracle

TOL = 1e-9
LAGRANGE, NEWTON_EULER = 0, 1
CLOSED_FORM, MULTIROOT = 0, 1


@pytest.fixture(scope="module")
def shim(tmp_path_factory):
    return oracle.build_shim(tmp_path_factory.mktemp("shim"))


@pytest.fixture(scope="module")
def sym():
    return oracle.symbolic()


def helix():
    """41 samples of the paper's helix, both blend corners included."""
    t = np.unique(np.concatenate([np.linspace(0, 10, 39), [1.0, 9.0]]))
    return oracle.helix_states(t, oracle.PAPER)


def sines(n=4, samples=5, seed=2385):
    rng = np.random.default_rng(seed)
    parts = [oracle.sine_states(np.linspace(0.05, 1.95, samples),
                                *oracle.random_sine(rng)) for _ in range(n)]
    return tuple(np.concatenate([p[k] for p in parts]) for k in range(3))


def rel(a, b):
    return np.max(np.abs(a - b)) / np.max(np.abs(b))


CASES = [
    # the paper: Table II, its four effects
    ("paper-helix", oracle.PAPER, oracle.EFF_DEFAULT, helix),
    # every effect, high-entropy parameters, through the workspace
    ("entropy-sines", oracle.ENTROPY_PRISMATIC, oracle.EFF_ALL, sines),
]


@pytest.mark.parametrize("method", [LAGRANGE, NEWTON_EULER])
@pytest.mark.parametrize("name,p,effects,states", CASES,
                         ids=[c[0] for c in CASES])
def test_symbolic_inverse_dynamics(shim, sym, name, p, effects, states,
                                   method):
    st = states()
    F, Fe, status = oracle.library_forces(shim, p, effects, st, method)
    assert (status == 0).all()
    scale = np.max(np.abs(F))
    for k in range(len(F)):
        Fs, Fes = sym.forces(p, effects, st[0][k], st[1][k], st[2][k])
        assert np.max(np.abs(F[k] - Fs)) <= TOL * scale, (name, k, F[k], Fs)
        # each effect's share too: a wrong term cannot hide in a sum
        assert np.max(np.abs(Fe[k] - Fes)) <= TOL * scale, (name, k)


def test_symbolic_multiroot(shim, sym):
    """theta from the link lengths, warm-started along the trajectory: the
    solve stops at max |f| <= 1e-12, so the forces carry ~cond x 1e-12."""
    p, st = oracle.ENTROPY, sines(2, 8, seed=77)
    F, _, status = oracle.library_forces(shim, p, oracle.EFF_ALL, st,
                                         LAGRANGE, MULTIROOT)
    assert (status == 0).all()
    Fs = np.array([sym.forces(p, oracle.EFF_ALL, *(s[k] for s in st))[0]
                   for k in range(len(F))])
    assert rel(F, Fs) <= 1e-9


def test_symbolic_geometry_is_the_papers(sym):
    """The oracle's own geometry against two facts from the paper: the
    centre (3)-(4) that the pin planes imply, and theta from (39)."""
    rng = np.random.default_rng(11)
    p = oracle.ENTROPY
    r = p["rho"] * p["R"]
    for _ in range(20):
        pose = [rng.uniform(-3, 3), rng.uniform(0.05, 0.6), rng.uniform(0.2, 0.4)]
        k = sym.kinematics(p, pose, np.zeros(3), np.zeros(3))
        a, b = pose[0], pose[1]
        want = [-0.5 * r * (1 - np.cos(b)) * np.cos(2 * a),
                0.5 * r * (1 - np.cos(b)) * np.sin(2 * a)]
        assert np.allclose(k["c"][:2], want, rtol=0, atol=1e-15)
        assert np.allclose(k["rot"].T @ k["rot"], np.eye(3), atol=1e-15)


@pytest.mark.parametrize("name,p,effects,states", CASES,
                         ids=[c[0] for c in CASES])
def test_mujoco_forces(shim, sym, name, p, effects, states):
    st = states()
    F, _, status = oracle.library_forces(shim, p, effects, st)
    assert (status == 0).all()
    model = mujoco_model.build(p)
    data = mujoco.MjData(model)
    Fm = np.zeros_like(F)
    for k in range(len(F)):
        kin = sym.kinematics(p, st[0][k], st[1][k], st[2][k])
        qpos, qvel, qacc = mujoco_model.state(model, kin)
        data.qpos[:] = qpos
        mujoco.mj_kinematics(model, data)
        # the state closes the loops: MuJoCo's sites meet
        assert mujoco_model.closure_residual(model, data) < 1e-14
        Fm[k] = mujoco_model.actuator_forces(model, data, qpos, qvel, qacc, p)
    assert rel(F, Fm) <= TOL, (name, F, Fm)


def test_mujoco_model_is_the_mechanism():
    """What other tests may rely on: 15 dof (3 pins, 3 legs, a free
    platform), three motors on the legs, three ball-joint closures, the
    masses of the parameters."""
    p = oracle.ENTROPY
    model = mujoco_model.build(p)
    assert (model.nq, model.nv, model.nu, model.neq) == (13, 12, 3, 3)
    total = p["M"] + 3 * p["m"] + p["payload"]["mass"]
    assert abs(model.body_subtreemass[0] - total) < 1e-9
