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
MuJoCo's own energy is not used.
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
