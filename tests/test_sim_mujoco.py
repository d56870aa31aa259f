"""The simulation against an external simulator: the same open-loop forces
(the library's inverse dynamics of the paper's helix and of a fast sine,
held over 1e-4 s) drive rps3_sim and MuJoCo's model of the mechanism
(tests/mujoco_model.py: its own mass matrix, Jacobians and integrator, the
ball joints closed by soft equality constraints); both start on the
trajectory.  The motions must agree within MuJoCo's constraint softness.

Windows are 0.1 s: open loop the mechanism is unstable (errors grow ~10x per
0.2 s), so a longer run would compare the two simulators' rounding,
amplified.  Tolerances: rps3's run (rk8pd, 1e-12) reproduces the trajectory
to ~1e-10 m (test_sim); MuJoCo's ball joints are soft constraints, whose
deflection with the settings of simulation_xml (below) was measured at
1.1e-5 m on the helix and 8.7e-5 m on the fast sine (payload, friction,
larger accelerations).  It is the softness: it scales as 1 / PISTON_MASS
(1e-5 kg gives 1.1e-4 and 4.9e-4 m; 1e-3 kg gives 1.2e-6 m on the helix,
where the pistons' inertia does not yet show).  The tolerances, 2e-5 and
2e-4 m, bound it with margin, while a wrong inertia or force direction
moves the platform by millimetres in 0.1 s.  Energy: rps3's T + P - W stays at rounding;
MuJoCo's own energy is not used.  A general plant (RPS3_BODIES_GENERAL:
offset centres of mass, full inertia tensors, massive pistons, friction in
every joint) is compared the same way (test_general_bodies_...).
"""

import ctypes
import re

import numpy as np
import pytest

import mujoco
import mujoco_model
import oracle

ROOT = oracle.ROOT
DT = 1e-4          # MuJoCo's timestep (mujoco_model.py) and the force hold
WINDOW = 0.1
RK8PD = 2


@pytest.fixture(scope="module")
def shims(tmp_path_factory):
    out = tmp_path_factory.mktemp("simshim")
    lib = oracle.build_sim_shim(out)
    return oracle.build_shim(out), lib, oracle.symbolic()


def rps3_run(lib, p, effects, pose0, dpose0, F):
    n = len(F)
    l = np.zeros((n + 1, 3))
    T, P, W = (np.zeros(n + 1) for _ in range(3))
    err = ctypes.create_string_buffer(256)
    par = np.append(oracle.param_vector(p), 0.0)  # vreg = 0: exact sign
    rc = lib.rps3_shim_sim(par, effects, RK8PD, 1e-3, 1e-12,
                           np.ascontiguousarray(pose0, float),
                           np.ascontiguousarray(dpose0, float), n, DT,
                           np.ascontiguousarray(F, float), l, T, P, W, err,
                           256)
    assert rc == 0, err.value.decode()
    return l, T + P - (T[0] + P[0]) - W


# MuJoCo's pistons carry 1e-12 kg (mujoco_model.EPS_MASS), fine for
# inverse dynamics but not for forward simulation: MuJoCo's constraints are
# soft in proportion to the inertia they act on, so a force on a massless
# piston pulls it away from its ball joint (metres in 0.1 s), or the step
# diverges.  For simulation the pistons get PISTON_MASS with their weight
# compensated (gravcomp; the library's pistons are massless) and the ball
# joints a stiff reference (time constant two steps, the least MuJoCo
# recommends): what remains is the constraint's static deflection, ~1e-6 m
# for 1e-4 kg, and the pistons' inertia, PISTON_MASS x ~0.1 m/s^2 = 1e-5 N.
PISTON_MASS = 1e-4


def simulation_xml(p):
    """mujoco_model's MJCF with the pistons and closures set for stepping."""
    xml = mujoco_model.mujoco_xml(p)
    pm = f"{PISTON_MASS:g}"
    xml = re.sub(r'<body name="piston_(\d)">(\s*<joint[^>]*/>\s*<inertial '
                 r'pos="0 0 0" mass=")[^"]*(" diaginertia=")[^"]*"',
                 lambda m: (f'<body name="piston_{m.group(1)}" gravcomp="1">'
                            f'{m.group(2)}{pm}{m.group(3)}{pm} {pm} {pm}"'),
                 xml)
    assert xml.count('gravcomp="1"') == 3
    return xml.replace("<connect ", f'<connect solref="{2 * DT:g} 1" ')


def mujoco_run(sym, p, states0, F):
    model = mujoco.MjModel.from_xml_string(simulation_xml(p))
    assert model.opt.timestep == DT
    data = mujoco.MjData(model)
    kin = sym.kinematics(p, *states0)
    qpos, qvel, _ = mujoco_model.state(model, kin)
    data.qpos[:] = qpos
    data.qvel[:] = qvel
    mujoco.mj_forward(model, data)
    legs = [model.joint(f"leg_{i}").qposadr[0] for i in range(3)]
    pins = [model.joint(f"pin_{i}").dofadr[0] for i in range(3)]
    l = [data.qpos[legs].copy()]
    for k in range(len(F)):
        data.ctrl[:] = F[k]
        # Coulomb pin friction, a known torque, as actuator_forces adds it
        data.qfrc_applied[:] = 0.0
        for dof in pins:
            data.qfrc_applied[dof] = (-p["friction"]["coulomb"] *
                                      np.sign(data.qvel[dof]))
        mujoco.mj_step(model, data)
        l.append(data.qpos[legs].copy())
    return np.array(l)


PATHS = {
    "paper-helix": (oracle.PAPER, oracle.EFF_DEFAULT,
                    lambda t: oracle.helix_states(t, oracle.PAPER), 2.37,
                    2e-5),
    "entropy-fast-sine": (oracle.ENTROPY, oracle.EFF_ALL,
                          lambda t: oracle.sine_states(
                              t, [0.31, 0.21, 0.27], [1.03, 0.083, 0.029],
                              [1.07, 2.03, 3.01], [0.0, 0.4, 0.0]), 0.61,
                          2e-4),
}


@pytest.mark.parametrize("name", sorted(PATHS))
def test_open_loop_forces_same_motion_as_mujoco(shims, name):
    shim, lib, sym = shims
    p, effects, states, t0, tol = PATHS[name]
    n = int(round(WINDOW / DT))
    # forces held over each step: the inverse dynamics at its midpoint
    tmid = t0 + (np.arange(n) + 0.5) * DT
    F, _, status = oracle.library_forces(shim, p, effects, states(tmid))
    assert (status == 0).all()
    s0 = [s[0] for s in states(np.array([t0]))]
    # rps3's simulation runs from t = 0: shift the trajectory's time
    l_rps3, e_res = rps3_run(lib, p, effects, s0[0], s0[1], F)
    l_mj = mujoco_run(sym, p, s0, F)
    # the desired lengths at the interval ends, by the oracle's kinematics
    ends = states(t0 + np.arange(n + 1) * DT)
    l_des = np.array([sym.kinematics(p, *(s[k] for s in ends))["l"]
                      for k in range(0, n + 1, 100)])
    diff = np.max(np.abs(l_rps3 - l_mj))
    track = np.max(np.abs(l_rps3[::100] - l_des))
    print(f"{name}: |l_rps3 - l_mujoco| <= {diff:.3g} m, "
          f"|l_rps3 - l_d| <= {track:.3g} m, energy residual "
          f"{np.max(np.abs(e_res)):.3g} J")
    assert diff <= tol, name
    # held forces: the trajectory within the hold's O(dt^2) error
    assert track <= 1e-6, name
    assert np.max(np.abs(e_res)) <= 1e-9, name


# ------------------------------------------------------------ general bodies
#
# A general plant (RPS3_BODIES_GENERAL): a platform with an offset centre of
# mass and a full inertia tensor, a cylinder and a piston a leg with theirs,
# viscous and Coulomb friction (exact sign) in every pin and prismatic
# joint, each leg its own.  MuJoCo gets the same bodies through the
# exporter's tree (mujoco_model.py): a leg's bodies have rps3's axes e1 =
# phi_i, e2 = the pin axis, e3 = e1 x e2, which at theta_i = 0 are (-u_i,
# the pin axis, their cross product) in the link's and the piston's MuJoCo
# frames (world-aligned there, turning with the hinge; the piston's origin
# at the ball joint); the platform's frame is rps3's.  The pistons carry
# real masses here, so the ball joints are stiffer than the paper case's.

GENERAL_SEED = 20261128
EFF_ALL7 = 0b1111111   # every effect, the prismatic joints' friction too


def _body(rng, mass, length):
    """A real body: mass, centre of mass and inertia about it (principal
    moments of 1 to 2 m length^2 about random axes), as
    tests/bodies_random.h's random_body."""
    m = rng.uniform(0.2, 1.0) * mass
    com = rng.uniform(-length, length, 3)
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    inertia = Q @ np.diag(rng.uniform(1.0, 2.0, 3) * m * length ** 2) @ Q.T
    return m, com, inertia


def general_plant():
    """Seven bodies (platform, cylinder 1, piston 1, ...) and each leg's
    (pin viscous, pin Coulomb, prismatic viscous, prismatic Coulomb)."""
    rng = np.random.default_rng(GENERAL_SEED)
    bodies = [_body(rng, 0.3, 0.05)]
    for _ in range(3):
        bodies += [_body(rng, 0.1, 0.08), _body(rng, 0.05, 0.06)]
    fric = np.array([[rng.uniform(0.001, 0.02), rng.uniform(0.001, 0.01),
                      rng.uniform(0.1, 2.0), rng.uniform(0.01, 0.5)]
                     for _ in range(3)])
    return bodies, fric


def _body_vector(bodies):
    """The shim's 7 x 10: mass, com, Ixx Ixy Ixz Iyy Iyz Izz."""
    out = []
    for m, com, inertia in bodies:
        out += [m, *com, inertia[0, 0], inertia[0, 1], inertia[0, 2],
                inertia[1, 1], inertia[1, 2], inertia[2, 2]]
    return np.array(out, float)


def _inertial(m, pos, inertia):
    """MJCF's inertial element: the centre of mass in the body's frame and
    the inertia about it (fullinertia: xx yy zz xy xz yz)."""
    def f(v):
        return " ".join(f"{x:.17g}" for x in v)
    full = [inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1],
            inertia[0, 2], inertia[1, 2]]
    return (f'<inertial pos="{f(pos)}" mass="{m:.17g}" '
            f'fullinertia="{f(full)}"/>')


def general_xml(p, bodies, fric):
    """The exporter's MJCF of p's geometry with the general bodies and the
    legs' viscous friction (the hinges' and slides' damping)."""
    xml = mujoco_model.mujoco_xml(p)
    m, com, inertia = bodies[0]
    xml, k = re.subn(r'(<freejoint name="platform"/>\s*)<inertial[^>]*/>',
                     lambda g: g.group(1) + _inertial(m, com, inertia), xml)
    assert k == 1
    for i in range(3):
        psi = 2.0 * np.pi * i / 3.0
        u = np.array([np.cos(psi), np.sin(psi), 0.0])
        ax = np.array([-np.sin(psi), np.cos(psi), 0.0])
        E = np.column_stack([-u, ax, np.cross(-u, ax)])
        cyl, pis = bodies[1 + 2 * i], bodies[2 + 2 * i]
        cyl_in = _inertial(cyl[0], E @ cyl[1], E @ cyl[2] @ E.T)
        pis_in = _inertial(pis[0], E @ pis[1], E @ pis[2] @ E.T)
        pin_damp, leg_damp = f"{fric[i, 0]:.17g}", f"{fric[i, 2]:.17g}"
        xml, k = re.subn(
            rf'(<joint name="pin_{i}"[^>]*damping=")[^"]*("/>\s*)'
            r'<inertial[^>]*/>',
            lambda g, a=pin_damp, b=cyl_in: g.group(1) + a + g.group(2) + b,
            xml)
        assert k == 1
        xml, k = re.subn(
            rf'(<joint name="leg_{i}"[^>]*)/>(\s*)<inertial[^>]*/>',
            lambda g, a=leg_damp, b=pis_in: (f'{g.group(1)} damping="{a}"/>'
                                             + g.group(2) + b), xml)
        assert k == 1
    return xml.replace("<connect ", f'<connect solref="{2 * DT:g} 1" ')


def test_general_bodies_same_motion_as_mujoco(shims):
    """The general plant under its own inverse dynamics' forces of the fast
    sine (held over 1e-4 s): rps3_sim (rk8pd, 1e-12) and MuJoCo's model of
    the same bodies give the same link lengths over 0.1 s, within MuJoCo's
    constraint softness (measured 2.8e-7 m over a motion of 4.8 cm: the
    pistons' real masses keep the ball joints stiffer than the paper case's
    1e-4 kg; checked at 1e-5 m, where every centre of mass mirrored, a
    frame error, moves the legs by 2.7 cm); rps3's energy balance holds
    to rounding."""
    _, lib, sym = shims
    p = dict(oracle.ENTROPY, payload=dict(mass=0.0, com=(0.0, 0.0, 0.0),
                                          inertia=(0.0, 0.0, 0.0)))
    bodies, fric = general_plant()
    bvec, fvec = _body_vector(bodies), np.ascontiguousarray(fric.ravel())
    par = oracle.param_vector(p)
    dp = np.ctypeslib.ndpointer(np.float64, flags="C_CONTIGUOUS")
    lib.rps3_shim_general_forces.argtypes = [dp, dp, dp, ctypes.c_int,
                                             ctypes.c_int, dp, dp, dp, dp,
                                             ctypes.c_char_p, ctypes.c_int]
    lib.rps3_shim_sim_general.argtypes = [
        dp, dp, dp, ctypes.c_int, ctypes.c_int, ctypes.c_double,
        ctypes.c_double, dp, dp, ctypes.c_int, ctypes.c_double, dp, dp, dp,
        dp, dp, ctypes.c_char_p, ctypes.c_int]
    _, _, states, t0, _ = PATHS["entropy-fast-sine"]
    n = int(round(WINDOW / DT))
    st = [np.ascontiguousarray(s, float)
          for s in states(t0 + (np.arange(n) + 0.5) * DT)]
    F = np.zeros((n, 3))
    err = ctypes.create_string_buffer(256)
    rc = lib.rps3_shim_general_forces(par, bvec, fvec, EFF_ALL7, n, *st, F,
                                      err, 256)
    assert rc == 0, err.value.decode()
    s0 = [s[0] for s in states(np.array([t0]))]
    l_rps3 = np.zeros((n + 1, 3))
    T, P, W = (np.zeros(n + 1) for _ in range(3))
    rc = lib.rps3_shim_sim_general(
        par, bvec, fvec, EFF_ALL7, RK8PD, 1e-3, 1e-12,
        np.ascontiguousarray(s0[0], float),
        np.ascontiguousarray(s0[1], float), n, DT, F, l_rps3, T, P, W, err,
        256)
    assert rc == 0, err.value.decode()
    e_res = T + P - (T[0] + P[0]) - W
    # MuJoCo: the same forces, the Coulomb parts as known torques and forces
    model = mujoco.MjModel.from_xml_string(general_xml(p, bodies, fric))
    data = mujoco.MjData(model)
    qpos, qvel, _ = mujoco_model.state(model, sym.kinematics(p, *s0))
    data.qpos[:] = qpos
    data.qvel[:] = qvel
    mujoco.mj_forward(model, data)
    legs = [model.joint(f"leg_{i}").qposadr[0] for i in range(3)]
    pins = [model.joint(f"pin_{i}").dofadr[0] for i in range(3)]
    slides = [model.joint(f"leg_{i}").dofadr[0] for i in range(3)]
    l_mj = [data.qpos[legs].copy()]
    for k in range(n):
        data.ctrl[:] = F[k]
        data.qfrc_applied[:] = 0.0
        for i in range(3):
            data.qfrc_applied[pins[i]] = -fric[i, 1] * np.sign(
                data.qvel[pins[i]])
            data.qfrc_applied[slides[i]] = -fric[i, 3] * np.sign(
                data.qvel[slides[i]])
        mujoco.mj_step(model, data)
        l_mj.append(data.qpos[legs].copy())
    diff = np.max(np.abs(l_rps3 - np.array(l_mj)))
    moved = np.max(np.abs(l_rps3 - l_rps3[0]))
    print(f"general bodies: |l_rps3 - l_mujoco| <= {diff:.3g} m over a "
          f"motion of {moved:.3g} m, energy residual "
          f"{np.max(np.abs(e_res)):.3g} J")
    assert diff <= 1e-5
    assert np.max(np.abs(e_res)) <= 1e-9
