"""The Python package's bindings of the library beyond the kinematics and
the inverse dynamics (python/rps3: dynamics, velocity, sim, control,
scene, errors, the trajectory kinds waypoints and path): against the
library's own outputs (the runner's files, the library's controllers),
against physics (forward dynamics inverts inverse dynamics, energy is
conserved without forces), a Python controller against the library's, the
callback's exceptions, and bad arguments raising exceptions that name
them."""

import math
import os
import time

import h5py
import numpy as np
import pytest
import rps3
from conftest import CONFIGS, write_scene
from rps3 import control, dynamics, errors, scene, sim, velocity

EPS = np.finfo(float).eps

# forward dynamics against inverse dynamics: the accelerations come back
# through the theta solve of rps3_fwddyn (tolerance opt.tol = 1e-12 on the
# dimensionless constraints, so theta to ~cond x 1e-12) and a 3x3 solve
# with Mq; relative to the acceleration the forces would give with the
# smallest eigenvalue of Mq, 1e-9 leaves three digits over what the solve
# leaves (measured ~1e-11), while a wrong term (a share missing, a sign)
# is off by 1e-3 or more
TOL_FWD = 1e-9
# a quantity the library computes twice by the same formula: rounding only
TOL_EXACT = 64 * EPS
# Python PD against the library's PD: the same law on the same numbers
# (the desired lengths by the same closed form), so the same trajectory to
# rounding; the brief of the binding asks 1e-12 of the lengths' scale
TOL_SAME_LAW = 1e-12


def helix(model=None, samples=201):
    return rps3.trajectory.helix(samples=samples, model=model)


# --------------------------------------------------------- forward dynamics

MODELS = {
    "paper": dict(m_over_M=0.5),
    "newton_euler": dict(m_over_M=0.5, method="newton_euler"),
    "payload_friction": dict(
        m_over_M=0.3, link_Ic=2e-4,
        payload={"mass": 0.05, "com": [0.01, -0.02, -0.03],
                 "inertia": [1e-5, 2e-5, 2.5e-5]},
        friction={"viscous": 0.002, "coulomb": 0.0},
        effects=list(rps3.EFFECTS)),
}


@pytest.mark.parametrize("name", sorted(MODELS))
@pytest.mark.parametrize("kind", ["helix", "sine"])
def test_forward_inverts_inverse(name, kind):
    """F = rps3_inverse(pose, dpose, ddpose); rps3_fwddyn(l, dl, F) gives
    back the link accelerations of the pose's motion (rps3_acceleration),
    and the pose itself (its theta solve), for each formulation and the
    payload and friction effects."""
    model = rps3.Model(**MODELS[name])
    if kind == "helix":
        tr = helix(model)
    else:
        tr = rps3.trajectory.sine(mean=[0.2, 0.1, 0.3], amp=[0.4, 0.05, 0.03],
                                  freq=[0.7, 1.3, 2.1], phase=[0, 1, 2],
                                  duration=2.0, samples=201, model=model)
    inv = model.inverse(tr.pose, tr.dpose, tr.ddpose)
    assert (inv.status == 0).all()
    mot = velocity.pose_rates(model, tr.pose, tr.dpose, tr.ddpose)
    fd = dynamics.forward(model, mot.l, mot.dl, inv.force)
    assert (fd.status == 0).all() and fd.message == ""
    lam_min = np.linalg.eigvalsh(fd.Mq)[:, 0]
    scale = (np.abs(inv.force).max(1) + np.abs(fd.hq).max(1)) / lam_min
    err = np.abs(fd.ddl - mot.ddl).max(1)
    assert (err <= TOL_FWD * scale).all(), (err / scale).max()
    assert np.abs(fd.pose - tr.pose).max() <= 1e-9
    # F = Mq ddl + hq, the equation the result solves
    resid = np.einsum("nij,nj->ni", fd.Mq, fd.ddl) + fd.hq - inv.force
    assert np.abs(resid).max() <= 1e3 * EPS * scale.max() * lam_min.max()


def test_forward_mass_matrix_and_energy():
    """Mq is symmetric positive definite; T = 1/2 dl . Mq dl (the kinetic
    energy from the bodies' motion, independently of Mq); a wrong Mq or T
    fails both."""
    model = rps3.Model()
    tr = helix(model, 51)
    mot = velocity.pose_rates(model, tr.pose, 50 * tr.dpose)
    fd = dynamics.forward(model, mot.l, mot.dl, np.zeros_like(mot.l))
    assert np.allclose(fd.Mq, np.transpose(fd.Mq, (0, 2, 1)), rtol=0, atol=1e-15)
    assert (np.linalg.eigvalsh(fd.Mq) > 0).all()
    T = 0.5 * np.einsum("ni,nij,nj->n", mot.dl, fd.Mq, mot.dl)
    assert np.abs(T - fd.T).max() <= TOL_EXACT * fd.T.max() * 10
    # one state: per-point shapes
    one = dynamics.forward(model, mot.l[3], mot.dl[3], [0.5, 0.6, 0.7])
    assert one.ddl.shape == (3,) and one.Mq.shape == (3, 3) and one.status == 0


def test_forward_errors():
    """A library status becomes its exception with the library's message;
    with check_status=False the status and NaN come back per point."""
    static = rps3.Model(effects=["platform_gravity"])
    with pytest.raises(errors.InvalidError, match="point 0: .*inertia") as exc:
        dynamics.forward(static, [0.3] * 3, [0.0] * 3, [1.0] * 3)
    assert exc.value.status == rps3._lib.RPS3_EINVAL
    assert isinstance(exc.value, ValueError)
    model = rps3.Model()
    l = [[0.3, 0.3, 0.3], [0.3, 0.3, 5.0], [0.31, 0.3, 0.3]]
    with pytest.raises(errors.Rps3Error, match="point 1: "):
        dynamics.forward(model, l, np.zeros((3, 3)), np.ones((3, 3)))
    fd = dynamics.forward(model, l, np.zeros((3, 3)), np.ones((3, 3)),
                          check_status=False)
    assert fd.status[0] == 0 and fd.status[2] == 0 and fd.status[1] != 0
    assert np.isnan(fd.ddl[1]).all() and fd.message.startswith("point 1: ")


@pytest.mark.parametrize("bad, exc, match", [
    ([0.3, 0.3], ValueError, r"l: expected shape \(n, 3\)"),
    ([0.3, 0.3, np.nan], ValueError, "l: non-finite"),
    ([0.3, 0.3, 0.3 + 1e-3j], TypeError, r"l: .*complex"),
    (["a", "b", "c"], TypeError, "l: expected real numbers"),
])
def test_forward_bad_arguments(bad, exc, match):
    with pytest.raises(exc, match=match):
        dynamics.forward(rps3.Model(), bad, [0.0] * 3, [0.0] * 3)


def test_forward_shape_mismatch_names_argument():
    with pytest.raises(ValueError, match="F: shape"):
        dynamics.forward(rps3.Model(), np.full((4, 3), 0.3), np.zeros((4, 3)),
                         np.zeros((3, 3)))


# ------------------------------------------------------------ velocities

def test_velocity_against_differences_of_ik():
    """dl/dt of the inverse kinematics along the trajectory, by central
    differences of Model.ik (truncation ~h^2 |l'''|, rounding ~eps/h):
    1e-7 of the rate scale; J dpose = dl (the Jacobian's columns)."""
    model = rps3.Model()
    tr = rps3.trajectory.sine(mean=[0.2, 0.1, 0.3], amp=[0.4, 0.05, 0.03],
                              freq=[0.7, 1.3, 2.1], duration=2.0, samples=101)
    h = 1e-5
    mot = velocity.pose_rates(model, tr.pose, tr.dpose, tr.ddpose)
    lp = model.ik(tr.pose + h * tr.dpose).l
    lm = model.ik(tr.pose - h * tr.dpose).l
    fd = (lp - lm) / (2 * h)
    assert np.abs(fd - mot.dl).max() <= 1e-7 * np.abs(mot.dl).max()
    J = velocity.jacobian(model, tr.pose)
    assert np.abs(np.einsum("nij,nj->ni", J.l, tr.dpose) - mot.dl).max() \
        <= TOL_EXACT * np.abs(mot.dl).max()
    assert np.abs(np.einsum("nij,nj->ni", J.omega, tr.dpose) - mot.omega).max() \
        <= TOL_EXACT * np.abs(mot.omega).max()
    # the joint route (25)-(30) inverts the pose route
    back = velocity.joint_rates(model, mot.l, mot.dl, mot.ddl)
    assert np.abs(back.pose - tr.pose).max() <= 1e-9
    assert np.abs(back.dpose - tr.dpose).max() <= 1e-8 * np.abs(tr.dpose).max()
    assert np.abs(back.ac - mot.ac).max() <= 1e-8 * np.abs(mot.ac).max()


def test_velocity_transform_and_paper_omega():
    """The transform (1) is a rotation with the centre as translation; the
    paper's body-frame angular velocity (31)-(33) with the errata is
    rot^T omega (the library's second formulation, computed apart)."""
    model = rps3.Model()
    tr = rps3.trajectory.sine(mean=[0.2, 0.1, 0.3], amp=[0.4, 0.05, 0.03],
                              freq=[0.7, 1.3, 2.1], duration=2.0, samples=51)
    v = velocity.pose_rates(model, tr.pose, tr.dpose)
    R = v.transform[:, :3, :3]
    assert np.abs(np.einsum("nji,njk->nik", R, R) - np.eye(3)).max() <= TOL_EXACT
    assert np.array_equal(v.transform[:, :3, 3], v.c)
    assert np.array_equal(v.transform[:, 3], np.tile([0.0, 0, 0, 1], (51, 1)))
    body = np.einsum("nji,nj->ni", R, v.omega)
    assert np.abs(body - v.omega_body).max() <= 1e-12 * np.abs(v.omega).max()


def test_velocity_errors():
    model = rps3.Model()
    with pytest.raises(errors.ReachError, match="point 1: "):
        velocity.pose_rates(model, [[0, 0, 0.3], [0, 0, -0.3]])
    v = velocity.pose_rates(model, [[0, 0, 0.3], [0, 0, -0.3]],
                            check_status=False)
    assert list(v.status) == [0, rps3._lib.RPS3_EREACH]
    with pytest.raises(ValueError, match="ddpose: accelerations need"):
        velocity.pose_rates(model, [0, 0, 0.3], ddpose=[0, 0, 0])
    with pytest.raises(TypeError, match=r"dpose: .*complex"):
        velocity.pose_rates(model, [0, 0, 0.3], [1j, 0, 0])


# ------------------------------------------------------------ simulation

@pytest.mark.parametrize("integrator, options", [
    ("rk4", dict(h=1e-3)), ("rkf45", {}), ("rk8pd", {}), ("msbdf", {}),
    ("rk4imp", dict(h=1e-3))])
def test_energy_conserved_without_forces(integrator, options):
    """Zero forces, no friction: T + P stays E0.  Adaptive integrators keep
    each step's error within epsabs + epsrel |y| on (l, dl, work), so the
    energy drifts by at most about that per step times the energy's
    sensitivity to the state (forces of ~1 N, momenta of ~0.1 kg m/s, here
    below 10 per unit): bound nsteps (epsabs + epsrel) 10 E0; rk4imp too,
    whose implicit stages GSL solves to that tolerance.  rk4 is fourth
    order: doubling h multiplies the drift by ~16 (measured 15.5)."""
    model = rps3.Model()
    t = np.linspace(0.0, 0.2, 21)
    res = sim.simulate(model, control.constant(), t, (0.3, 0.1, 0.3),
                       (0.5, 0.2, 0.1), integrator=integrator, **options)
    assert res.ok and (res.work == 0).all() and (res.work_friction == 0).all()
    drift = np.abs(res.T + res.P - (res.T[0] + res.P[0]))
    assert np.allclose(drift, np.abs(res.energy_residual), rtol=0, atol=1e-15)
    E0 = res.T[0] + res.P[0]
    if integrator == "rk4":
        double = sim.simulate(model, control.constant(), t, (0.3, 0.1, 0.3),
                              (0.5, 0.2, 0.1), integrator=integrator, h=2e-3)
        big = np.abs(double.energy_residual).max()
        assert 8 * drift.max() < big < 32 * drift.max(), (big, drift.max())
        assert drift.max() <= 1e-9 * E0
    else:
        assert drift.max() <= res.nsteps * (1e-9 + 1e-9) * 10 * E0
    # the platform moved: the test is not of a plant at rest
    assert np.abs(res.pose[-1] - res.pose[0]).max() > 0.05


def paper_pd(model, traj):
    """A PD law in Python, as the library's: e = l_d - l with l_d, dl_d
    of the trajectory's pose by the closed form (after the span: its final
    pose at rest), kp 2000 N/m, kd 40 N s/m; looked up per tick."""
    ticks = np.arange(int(round(traj.spec.duration * 1000)) + 1) / 1000.0
    ref = traj.spec.eval(ticks, model)
    mot = velocity.pose_rates(model, ref.pose, ref.dpose)
    L, DL = mot.l, mot.dl

    def law(t, l, dl):
        k = int(round(t * 1000.0))
        if k < len(L):
            return 2000.0 * (L[k] - l) + 40.0 * (DL[k] - dl)
        return 2000.0 * (L[-1] - l) + 40.0 * (0.0 - dl)
    return law


def test_python_pd_is_the_library_pd():
    """The same PD law in Python (a cffi callback each tick) and in the
    library (rps3_ctrl_update) give the same run: lengths, forces, energy
    to TOL_SAME_LAW of their scale.  The trajectory ends before the run
    does (the rest after the span is followed too)."""
    model = rps3.Model(m_over_M=0.5)
    traj = rps3.trajectory.helix(period=1.0, blend=0.1, samples=11, model=model)
    plant = rps3.Model(m_over_M=0.3)           # the controller's model differs
    t = np.linspace(0.0, 1.2, 121)
    lib_run = sim.simulate(plant, control.pd(model, traj), t, traj.pose[0])
    law = control.python(paper_pd(model, traj), rate=1000.0)
    py_run = sim.simulate(plant, law, t, traj.pose[0])
    assert lib_run.ok and py_run.ok
    assert law.calls == py_run.nticks == lib_run.nticks == 1200
    assert np.abs(py_run.l - lib_run.l).max() <= TOL_SAME_LAW * np.abs(lib_run.l).max()
    assert np.isnan(py_run.force[0]).all() and np.isnan(lib_run.force[0]).all()
    assert np.abs(py_run.force[1:] - lib_run.force[1:]).max() \
        <= TOL_SAME_LAW * np.abs(lib_run.force[1:]).max()
    assert np.abs(py_run.T + py_run.P - lib_run.T - lib_run.P).max() <= 1e-12
    # the library's PD logged its desired lengths: the Python law's own
    assert np.isnan(py_run.l_des).all() and np.isfinite(lib_run.l_des[1:]).all()


def test_library_controllers_as_the_runner(runner):
    """configs/closed_loop.yaml simulated by the runner and the same runs
    from Python (rps3.sim with rps3.control's library controllers): the
    same forces and lengths, bit for bit (the same calls in the same
    order), for every controller and controller model of the sweep."""
    path = os.path.join(CONFIGS, "closed_loop.yaml")
    ds = scene.run(path, runner=runner)
    t = ds.time.values
    plant = rps3.Model(m_over_M=0.5)
    traj = rps3.trajectory.helix(t=t[t <= 10.0], model=plant)
    gains = {"pd": (2000.0, 40.0), "pd_gravity": (2000.0, 40.0),
             "computed_torque": (400.0, 40.0)}
    for kind, (kp, kd) in gains.items():
        for ratio in (0.5, 0.0):
            # the runner's controller model computes F alone (rps3.h,
            # RPS3_OUT_FORCES), and the plant starts at the trajectory's rates
            cmodel = rps3.Model(m_over_M=ratio, outputs=["forces"])
            ctl = control.Library(kind, cmodel, traj, kp=kp, kd=kd, rate=1000.0)
            res = sim.simulate(plant, ctl, t, traj.pose[0], traj.dpose[0])
            case = ds.sel(controller=kind, m_over_M=ratio)
            assert res.ok and int(case.status) == 0
            assert np.array_equal(res.l, case.length.values), (kind, ratio)
            assert np.array_equal(res.force, case.force.values, equal_nan=True)
            assert np.array_equal(res.force_cmd, case.force_cmd.values, equal_nan=True)
            assert np.array_equal(res.energy_residual, case.energy_residual.values)
            assert res.nticks == int(case.nticks) and res.nsteps == int(case.nsteps)


def test_friction_work_balances_energy():
    """Viscous and regularised Coulomb friction at the pins, zero forces:
    the energy falls, by the friction's work (work_friction < 0), and
    T + P - E0 - work_friction stays at the integrator's tolerance (as in
    test_energy_conserved_without_forces); a wrong friction power (sign,
    factor) leaves a residual of the size of the lost energy."""
    model = rps3.Model(effects=list(rps3.DEFAULT_EFFECTS) + ["pin_friction"],
                       friction={"viscous": 0.05, "coulomb": 0.02, "vreg": 0.5})
    t = np.linspace(0.0, 0.2, 21)
    res = sim.simulate(model, control.constant(), t, (0.3, 0.1, 0.3),
                       (0.5, 0.2, 0.1), integrator="rk8pd", epsabs=1e-12,
                       epsrel=1e-12)
    lost = res.T[0] + res.P[0] - res.T - res.P
    assert lost[-1] > 1e-4 and res.work_friction[-1] < -1e-4
    assert np.abs(res.energy_residual).max() <= 1e-6 * lost[-1]
    assert np.allclose(lost, -res.work_friction, rtol=1e-6, atol=1e-12)


def test_continuous_python_law_is_the_constant_force():
    """rate 0: the law is called at every evaluation of the plant (nevals
    of them, four an RK4 step) and gives the library's constant force's
    run bit for bit."""
    model = rps3.Model()
    t = np.linspace(0.0, 0.05, 6)
    F = [0.9, 1.1, 1.0]
    law = control.python(lambda t, l, dl: F, rate=0.0)
    a = sim.simulate(model, law, t, (0.3, 0.1, 0.3))
    b = sim.simulate(model, control.constant(F), t, (0.3, 0.1, 0.3))
    assert np.array_equal(a.l, b.l) and np.array_equal(a.work, b.work)
    assert law.calls >= 4 * a.nsteps and a.nticks == 0


def test_python_law_sees_the_measurement():
    """With noise and quantisation on, a Python law receives the measured
    lengths and rates the simulation records (l_meas, dl_meas: those of the
    last tick before each output time), not the true ones."""
    model = rps3.Model()
    traj = helix(model, 3)
    seen = []

    def law(t, l, dl):
        seen.append((t, l, dl))
        return [1.0, 1.0, 1.0]
    t = np.arange(11) / 1000.0
    res = sim.simulate(model, control.python(law), t, traj.pose[0],
                       noise_l=1e-5, noise_dl=1e-4, quant_l=1e-6, seed=3)
    times = np.array([x[0] for x in seen])
    assert np.allclose(times, t[:-1], rtol=0, atol=1e-15)
    assert np.array_equal(np.array([x[1] for x in seen]), res.l_meas[1:])
    assert np.array_equal(np.array([x[2] for x in seen]), res.dl_meas[1:])
    assert np.abs(res.l_meas[1:] - res.l[:-1]).max() > 1e-7   # noisy


class Stop(Exception):
    pass


def test_callback_exception_propagates():
    """An exception in a Python law stops the run at that tick and is
    raised by run() (the same object); the partial result holds the
    states before it; the simulation then reports the stopped status."""
    model = rps3.Model()
    traj = helix(model, 11)

    def law(t, l, dl):
        if t >= 0.05:
            raise Stop(f"at {t}")
        return [1.0, 1.0, 1.0]
    s = sim.Simulation(model)
    s.start(traj.pose[0])
    with pytest.raises(Stop, match="at 0.05"):
        s.run(np.linspace(0, 0.1, 11), control.python(law))
    res = s.last_result
    assert res.status == rps3._lib.RPS3_EINVAL
    assert res.failed_at == pytest.approx(0.05)
    assert (res.status_t[:6] == 0).all() and (res.status_t[6:] != 0).all()
    assert np.isfinite(res.l[:6]).all() and np.isnan(res.l[6:]).all()
    assert "controller returned" in res.message
    with pytest.raises(errors.InvalidError):       # stopped: the status again
        s.run([0.2], control.constant())


@pytest.mark.parametrize("value, exc, match", [
    ([1.0, 2.0], ValueError, "return value: expected 3 forces"),
    ([1.0, 2.0, 3j], TypeError, "return value"),
    (None, TypeError, "return value"),
    ([1.0, np.inf, 0.0], ValueError, "non-finite"),
])
def test_callback_bad_return_value(value, exc, match):
    model = rps3.Model()
    with pytest.raises(exc, match=match):
        sim.simulate(model, control.python(lambda t, l, dl: value), [0.0, 0.01],
                     helix(model, 3).pose[0])


def test_callback_cost_per_tick():
    """The measured cost of a Python law per tick, over the library's PD
    (docs/python.md quotes it): the difference of two runs of 2000 ticks
    divided by the ticks.  Printed; bounded loosely (a shared machine)."""
    model = rps3.Model()
    traj = rps3.trajectory.helix(period=2.0, blend=0.2, samples=3, model=model)
    t = np.array([0.0, 2.0])
    law = control.python(paper_pd(model, traj))
    best = math.inf
    for _ in range(3):
        t0 = time.perf_counter()
        sim.simulate(model, control.pd(model, traj), t, traj.pose[0])
        t1 = time.perf_counter()
        sim.simulate(model, law, t, traj.pose[0])
        t2 = time.perf_counter()
        best = min(best, ((t2 - t1) - (t1 - t0)) / 2000)
    print(f"Python controller: {best * 1e6:.1f} us per tick over the library's PD")
    assert 0 < best < 1e-3


def test_simulation_stops_with_library_status():
    """A link leaving its stroke stops the run: ReachError with the
    library's message, the partial result on the exception."""
    model = rps3.Model()
    with pytest.raises(errors.ReachError) as exc:
        sim.simulate(model, control.constant(), np.linspace(0, 0.3, 31),
                     (0.3, 0.1, 0.3), l_min=0.25)
    res = exc.value.result
    assert res.status == rps3._lib.RPS3_EREACH and 0 < res.failed_at < 0.3
    assert str(exc.value) == res.message and "l" in res.message
    res = sim.simulate(model, control.constant(), np.linspace(0, 0.3, 31),
                       (0.3, 0.1, 0.3), l_min=0.25, check_status=False)
    assert not res.ok and np.isnan(res.l[-1]).all()


def test_simulation_options():
    """Saturation, noise and quantisation act as the library says: forces
    within fmax; measured lengths on the quantum's grid; the same seed the
    same noise, another seed other noise."""
    model = rps3.Model()
    traj = helix(model, 11)
    t = np.linspace(0, 0.05, 6)
    res = sim.simulate(model, control.pd(model, traj, kp=1e5), t, traj.pose[0],
                       fmax=0.5, quant_l=1e-4)
    assert np.abs(res.force[1:]).max() <= 0.5 and res.nsat > 0
    assert np.array_equal(res.force[1:], np.clip(res.force_cmd[1:], -0.5, 0.5))
    assert np.abs(res.force_cmd[1:]).max() > 0.5
    q = res.l_meas[1:] / 1e-4
    assert np.abs(q - np.round(q)).max() <= 1e-6
    a, b, c = (sim.simulate(model, control.pd(model, traj), t, traj.pose[0],
                            noise_l=1e-4, seed=s) for s in (7, 7, 8))
    assert np.array_equal(a.l_meas, b.l_meas, equal_nan=True)
    assert not np.array_equal(a.l_meas, c.l_meas, equal_nan=True)


@pytest.mark.parametrize("kw, exc, match", [
    (dict(integrator="euler"), ValueError, "integrator: 'euler'"),
    (dict(h=-1.0), ValueError, "^h = "),
    (dict(h=1e-3 + 0j), TypeError, "h: expected a real number"),
    (dict(fmax=float("nan")), ValueError, "fmax: must be finite"),
    (dict(max_steps=1.5), TypeError, "max_steps"),
])
def test_simulation_bad_options(kw, exc, match):
    with pytest.raises(exc, match=match):
        sim.Simulation(rps3.Model(), **kw)


def test_simulation_bad_times_and_start():
    model = rps3.Model()
    s = sim.Simulation(model)
    with pytest.raises(errors.StateError):
        s.run([0.1], control.constant())
    with pytest.raises(errors.ReachError):
        s.start((0.0, 0.0, -0.1))
    s.start((0.0, 0.0, 0.3))
    with pytest.raises(ValueError, match="t: not strictly increasing at index 2"):
        s.run([0.0, 0.1, 0.1], control.constant())
    with pytest.raises(TypeError, match="controller"):
        s.run([0.1], lambda t, l, dl: [0, 0, 0])
    with pytest.raises(ValueError, match="kp: must be >= 0"):
        control.pd(model, helix(model, 3), kp=-1.0)


# ------------------------------------------------------- trajectory kinds

TABLE_T = np.arange(0.0, 2.0001, 0.05)


def table_rows():
    """Poses of a smooth motion every 50 ms (the table kind's rows)."""
    t = TABLE_T
    return np.stack([0.3 * np.sin(t), 0.1 + 0.02 * t, 0.3 + 0.01 * np.sin(2 * t)], 1)


def path_rows():
    """Centres of a path beside the Z axis every 50 ms."""
    t = TABLE_T
    return np.stack([0.02 + 0.005 * np.sin(t), 0.01 * np.cos(t), 0.3 + 0.01 * t], 1)


def write_csv(path, header, rows):
    with open(path, "w") as f:
        f.write(header + "\n")
        for t, r in zip(TABLE_T, rows):
            f.write(", ".join(repr(float(x)) for x in (t, *r)) + "\n")


KINDS = {
    "helix": ("kind: helix\n  radius: 0.000266\n  pitch: 0.03048\n  z0: 0.3048\n"
              "  period: 10\n  blend: 1\n  samples: 51",
              lambda t: rps3.trajectory.helix(t=t)),
    "sine": ("kind: sine\n  mean: [0.1, 0.1, 0.3]\n  amp: [0.2, 0.03, 0.02]\n"
             "  freq: [1, 2, 0.5]\n  phase: [0, 0.5, 1]\n  duration: 2\n  samples: 51",
             lambda t: rps3.trajectory.sine(mean=[0.1, 0.1, 0.3],
                                            amp=[0.2, 0.03, 0.02], freq=[1, 2, 0.5],
                                            phase=[0, 0.5, 1], duration=2, t=t)),
    "waypoints_lspb": (
        "kind: waypoints\n  waypoints:\n    times: [0, 1, 2.5]\n"
        "    poses: [[0.6, 0.1, 0.32], [0.6, 0.1, 0.26], [-0.6, 0.12, 0.3]]\n"
        "    law: lspb\n    blend_ratio: 0.25\n    vmax: [0.8, 0, 0]\n  samples: 51",
        lambda t: rps3.trajectory.waypoints(
            [0, 1, 2.5], [[0.6, 0.1, 0.32], [0.6, 0.1, 0.26], [-0.6, 0.12, 0.3]],
            law="lspb", blend=0.25, vmax=[0.8, 0, 0], t=t)),
    "waypoints_quintic": (
        "kind: waypoints\n  waypoints:\n    times: [0, 1, 2.5]\n"
        "    poses: [[0.6, 0.1, 0.32], [0.6, 0.1, 0.26], [-0.6, 0.12, 0.3]]\n"
        "    law: quintic\n  samples: 51",
        lambda t: rps3.trajectory.waypoints(
            [0, 1, 2.5], [[0.6, 0.1, 0.32], [0.6, 0.1, 0.26], [-0.6, 0.12, 0.3]],
            law="quintic", t=t)),
    "line": ("kind: path\n  path:\n    shape: line\n    start: [0.02, -0.03, 0.28]\n"
             "    end: [0.03, 0.035, 0.34]\n    duration: 2.0\n    law: lspb\n"
             "    blend_ratio: 0.2\n  samples: 51",
             lambda t: rps3.trajectory.line([0.02, -0.03, 0.28], [0.03, 0.035, 0.34],
                                            2.0, law="lspb", blend=0.2, t=t)),
    "circle": ("kind: path\n  path:\n    shape: circle\n    centre: [0.01, 0, 0.30]\n"
               "    radius: 0.03\n    angle0: 0.4\n    turns: -1.5\n    duration: 4.0\n"
               "    law: minimum_jerk\n  samples: 51",
               lambda t: rps3.trajectory.circle([0.01, 0, 0.30], 0.03, 4.0, angle0=0.4,
                                                turns=-1.5, law="minimum_jerk", t=t)),
    "path_helix": ("kind: path\n  path:\n    shape: helix\n    centre: [0, 0, 0.3048]\n"
                   "    radius: 0.000266\n    turns: 1\n    pitch: 0.03048\n"
                   "    duration: 10\n    law: lspb\n    blend_ratio: 0.1\n  samples: 51",
                   lambda t: rps3.trajectory.circle([0, 0, 0.3048], 0.000266, 10.0,
                                                    pitch=0.03048, blend=0.1, t=t)),
    "table": ("kind: table\n  table:\n    file: rows.csv\n  samples: 51",
              lambda t: rps3.trajectory.table(TABLE_T, table_rows(), t=t)),
    "path_table": ("kind: path\n  path:\n    shape: table\n    file: rows.csv\n"
                   "  samples: 51",
                   lambda t: rps3.trajectory.path_table(TABLE_T, path_rows(), t=t)),
}


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_trajectory_kind_as_the_runner(tmp_path, runner, kind):
    """Every trajectory kind of the library, built from Python, gives the
    poses the runner writes for the same scene (the library's
    rps3_traj_eval on both sides, the runner's parser on one): the same
    bits."""
    text, build = KINDS[kind]
    if kind == "table":
        write_csv(tmp_path / "rows.csv", "t, alpha, beta, z_c", table_rows())
    if kind == "path_table":
        write_csv(tmp_path / "rows.csv", "t, x, y, z", path_rows())
    path = write_scene(tmp_path / "s.yaml",
                       "manipulator: {R: 0.2286, rho: 0.5, M: 0.18, m_over_M: 0.5,"
                       " d: 0.1524}\ntrajectory:\n  " + text + "\n")
    ds = scene.run(path, runner=runner).isel(case=0)
    tr = build(ds.time.values)
    want = np.stack([ds.alpha.values, ds.beta.values, ds.z_c.values], 1)
    assert np.array_equal(tr.pose, want), np.abs(tr.pose - want).max()
    # and the Model's forces along it are the file's (the same path)
    out = rps3.Model(m_over_M=0.5).inverse(tr.pose, tr.dpose, tr.ddpose)
    assert np.allclose(out.force, ds.force.values, rtol=0,
                       atol=1e-12 * np.abs(ds.force.values).max())


def test_trajectory_bad_arguments():
    with pytest.raises(ValueError, match="law: 'cubic'"):
        rps3.trajectory.waypoints([0, 1], [[0, 0.1, 0.3]] * 2, law="cubic")
    with pytest.raises(ValueError, match="poses: 1 rows for 2 times"):
        rps3.trajectory.waypoints([0, 1], [[0, 0.1, 0.3]])
    with pytest.raises(TypeError, match=r"poses: .*complex"):
        rps3.trajectory.waypoints([0, 1], [[0, 0.1, 0.3j]] * 2)
    with pytest.raises(ValueError, match="radius"):
        rps3.trajectory.circle([0.01, 0, 0.3], 0.2, 1.0)
    with pytest.raises(ValueError, match="start"):
        rps3.trajectory.line([0.0, 0.0, 0.3], [0.02, 0.0, 0.3], 1.0)
    with pytest.raises(TypeError, match="t: expected real numbers"):
        rps3.trajectory.helix(t=np.array([0.0, 1.0 + 1j]))


# ----------------------------------------------------------------- scenes

def test_scene_run_matches_runner_file(paper_h5):
    """configs/paper.yaml run from Python (the runner found as a user's
    call finds it: the build's), against the file conftest's runner wrote:
    the forces and lengths, per case."""
    ds = scene.run(os.path.join(CONFIGS, "paper.yaml"))
    with h5py.File(paper_h5, "r") as f:
        force = f["force"][()]
        length = f["length"][()]
        ratio = f["m_over_M"][()] if "m_over_M" in f else None
    got = ds.force.transpose("m_over_M", "time", "link").values
    assert ratio is None or np.array_equal(np.sort(ratio), ds.m_over_M.values)
    assert np.array_equal(got, force[np.argsort(ratio)] if ratio is not None else force)
    assert np.array_equal(ds.length.transpose("m_over_M", "time", "link").values,
                          length[np.argsort(ratio)] if ratio is not None else length)
    assert ds.force.attrs["units"] == "N"


def test_scene_errors(tmp_path, monkeypatch, runner):
    bad = write_scene(tmp_path / "bad.yaml",
                      "manipulator: {R: -1}\ntrajectory: {kind: helix}\n")
    with pytest.raises(scene.SceneError, match=r"bad.yaml:1:\d+: .*R") as exc:
        scene.run(bad, runner=runner)
    assert exc.value.returncode == 2
    with pytest.raises(FileNotFoundError, match="scene"):
        scene.run(tmp_path / "missing.yaml", runner=runner)
    monkeypatch.setenv("RPS3_RUN", str(tmp_path / "no-runner"))
    with pytest.raises(FileNotFoundError, match="RPS3_RUN"):
        scene.find_runner()
    monkeypatch.setenv("RPS3_RUN", runner)
    assert scene.find_runner() == runner
    monkeypatch.delenv("RPS3_RUN")
    assert os.access(scene.find_runner(), os.X_OK)
    # another version's runner is refused, whoever names it
    fake = tmp_path / "rps3-run"
    fake.write_text("#!/bin/sh\necho rps3-run 9.9.9\n")
    fake.chmod(0o755)
    with pytest.raises(RuntimeError, match="version rps3-run 9.9.9"):
        scene.find_runner(fake)


# ------------------------------------------------------------- exceptions

@pytest.mark.parametrize("call", ["ik", "fk", "inverse"])
def test_model_stages_refuse_complex_and_strings(call):
    """Model's stages name the argument of a complex or string array
    (numpy alone would drop the imaginary part with a warning)."""
    model = rps3.Model()
    name = "lengths" if call == "fk" else "pose"
    for bad in (np.array([0.0, 0.0, 0.3 + 1e-3j]), np.array(["0", "0", "0.3"])):
        with pytest.raises(TypeError, match=f"^{name}: expected real numbers"):
            getattr(model, call)(bad)


def test_every_status_has_its_exception():
    """Each status code of the library maps to its own class, carrying the
    code and the message; success raises nothing."""
    codes = [c for c in range(-5, 10) if rps3.strerror(c) != "unknown status"]
    assert len(codes) >= 10
    seen = set()
    for c in codes:
        if c == 0:
            errors.check(0, "nothing")
            continue
        e = errors.error(c, "msg")
        if c == rps3._lib.RPS3_ENOMEM:
            assert isinstance(e, MemoryError)
            continue
        assert isinstance(e, errors.Rps3Error) and e.status == c and str(e) == "msg"
        seen.add(type(e))
    assert len(seen) == len(codes) - 2  # all distinct, but OK and ENOMEM


# ------------------------------------------------------------------- docs

def test_docs_example_runs(capsys):
    """The example of docs/python.md (shown in the README) runs and tracks
    the helix: the PD law's error of the paper's scene (0.36 mm with the
    library's PD, tests above) and an integration error at rounding."""
    from conftest import ROOT
    with open(os.path.join(ROOT, "docs", "python.md")) as f:
        doc = f.read()
    block = doc.split("<!-- example:", 1)[1].split("```python\n", 1)[1]
    code = block.split("```", 1)[0]
    exec(compile(code, "docs/python.md", "exec"), {})
    err, resid = (float(x) for x in capsys.readouterr().out.split())
    assert 1e-4 < err < 1e-3 and resid < 1e-9
