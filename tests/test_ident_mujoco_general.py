"""Identification of the general model on forces no part of rps3 produced:
MuJoCo's.

The truth: seven rigid bodies unlike the paper's in every parameter (a
platform with its centre of mass off every axis and products of inertia;
cylinders and pistons with mass, centres of mass off the link and full
inertia tensors), viscous and Coulomb (exact sign) friction in the pins
and in the prismatic joints, on a geometry unlike Table II.  Two cases:
every leg its own bodies and friction (layout "each"), and three identical
legs (layout "identical").  The MuJoCo model is the package's MJCF export
of those bodies (tests/mujoco_model.py); the test first checks, from the
oracle's kinematics alone, that MuJoCo holds each body's mass, centre of
mass and inertia in the frames of docs/identification.md ("The model").
Along an exciting trajectory (rps3.ident_excite.random_fourier, five
harmonics) the states come from the oracle's SymPy kinematics and the
actuator forces from MuJoCo's mass matrix, bias forces, joint damping and
site Jacobians (mujoco_model.actuator_forces, noise-free).  rps3's C
regressor of the 82 standard parameters (rps3.ident.regressor_std) at the
same states, from a model of the truth's geometry with every effect and
vreg = 0 (the identification assumes the geometry known), in the
layout's columns, reduced to the structural base parameters
(rps3.ident_excite.layout_base), gives the OLS, WLS and consistent fits.
The truth's base parameters are K pi of the standard parameters this
file computes from the bodies (mass, first moment, inertia about the
frame's origin by the parallel-axis theorem).

Targets: every base parameter carrying >= 1 % of the RMS force within 2 %
of the truth, a held-out trajectory's force NRMSE <= 3 %.  Both hold by
orders of magnitude on exact data; the force each base parameter's error
makes is bounded by ERR_FORCE, set by how closely the two dynamics agree
(measured below).  A wrong geometry (R 1 % off) must be seen.
"""

import warnings

import numpy as np
import oracle
import pytest
import rps3
from rps3 import ident, ident_excite

mujoco = pytest.importorskip("mujoco")
mujoco_model = pytest.importorskip("mujoco_model")   # imports mujoco

REL_TOL = 2e-2        # the target on base parameters
SHARE_MIN = 1e-2      # ... that carry at least this share of the RMS force
NRMSE_MAX = 3e-2      # the target on the held-out trajectory's forces
# the force of each base parameter's error, over the RMS force: MuJoCo and
# rps3 agree to rounding here (every body has mass: the exporter's
# EPS_MASS is not used), 1e-16 amplified by the column-scaled base
# regressor's condition number (3.2e3 legs each, 1.2e3 identical) to
# ~1e-13; measured <= 7e-14 (legs each), 5e-14 (identical); a hundredfold
# margin on 1e-12
ERR_FORCE = 1e-10
# MuJoCo's bodies against the truth's: it diagonalises each inertia
# (mju_eig3, iterated to rounding) and stores the principal axes as a
# quaternion; measured <= 4e-16 R (centres of mass, loop closure), 8e-15
# of the largest element (inertias)
FRAME_TOL = 1e-12
# the consistent fit's default regularisation reg = 1e-9 sum tr J_b pulls
# the base parameters by an amount proportional to reg: measured (force of
# the largest parameter error over the RMS force) 3.4e-4 legs each, 6.0e-5
# identical (3.9e-6 and 1.1e-6 at reg 1e-11); 3 times the larger
ERR_FORCE_REG = 1e-3
# a 1 % wrong R must raise the held-out NRMSE above WRONG_GAIN * ERR_FORCE
# (measured 4.7e-3 legs each, 3.5e-3 identical, from ~1e-15 with the right R)
WRONG_GAIN = 1e5
# the test's standard parameters against rps3_std_params' (the same
# parallel-axis sums: rounding; measured 2e-20 of the largest)
STD_TOL = 1e-15
N_FIT, N_HELD = 300, 150  # samples of the fit and held-out trajectories

# the truth's geometry (unlike Table II's R = 0.2286 m, rho = 0.5)
R, RHO, G = 0.2531, 0.4713, 9.80665
PSI = 2 * np.pi * np.arange(3) / 3
INERTIAL = ("m", "mcx", "mcy", "mcz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz")


def platform():
    """(mass [kg], centre of mass [m], inertia about it [kg m^2]), the
    platform's axes."""
    return (0.2417, np.array([0.0061, -0.0043, 0.0187]),
            np.array([[1.31e-3, 1.7e-5, -2.3e-5], [1.7e-5, 1.19e-3, 3.1e-5],
                      [-2.3e-5, 3.1e-5, 2.37e-3]]))


def cylinder(i):
    """Leg i's cylinder in its frame (pin, e1 along the link)."""
    s = 1 + 0.13 * i
    return (0.0871 + 0.0123 * i,
            np.array([0.1137 + 0.0071 * i, 0.0031 - 0.0023 * i, -0.0047 + 0.0013 * i]),
            s * np.array([[3.1e-5, 2.3e-6, -1.7e-6], [2.3e-6, 7.4e-4, 4.1e-6],
                          [-1.7e-6, 4.1e-6, 7.2e-4]]))


def piston(i):
    """Leg i's piston in its frame (ball joint, the cylinder's axes)."""
    s = 1 + 0.17 * i
    return (0.0337 + 0.0051 * i,
            np.array([-0.0613 + 0.0043 * i, 0.0017 * (i - 1), 0.0011 + 0.0007 * i]),
            s * np.array([[4.3e-6, -3.1e-7, 2.2e-7], [-3.1e-7, 8.7e-5, 1.3e-6],
                          [2.2e-7, 1.3e-6, 8.9e-5]]))


def truth(legs):
    """The truth as mujoco_model's parameters, and its bodies and friction
    laws per leg (dicts for the test's own standard parameters)."""
    plat = platform()
    if legs == "each":
        cyl, pis = [cylinder(i) for i in range(3)], [piston(i) for i in range(3)]
        pin = [dict(viscous=0.0113 + 0.0021 * i, coulomb=0.0027 + 0.0009 * i, vreg=0.0)
               for i in range(3)]
        pri = [dict(viscous=0.317 + 0.053 * i, coulomb=0.043 + 0.011 * i, vreg=0.0)
               for i in range(3)]
        bodies = dict(platform=rps3.Body(*plat),
                      legs=[dict(cylinder=rps3.Body(*cyl[i]), piston=rps3.Body(*pis[i]))
                            for i in range(3)])
        p = dict(R=R, rho=RHO, g=G, bodies=bodies, friction=pin, prismatic=pri)
    else:
        cyl, pis = [cylinder(1)] * 3, [piston(2)] * 3
        pin1 = dict(viscous=0.0131, coulomb=0.0033, vreg=0.0)
        pri1 = dict(viscous=0.347, coulomb=0.051, vreg=0.0)
        pin, pri = [pin1] * 3, [pri1] * 3
        bodies = dict(platform=rps3.Body(*plat), cylinder=rps3.Body(*cyl[0]),
                      piston=rps3.Body(*pis[0]))
        p = dict(R=R, rho=RHO, g=G, bodies=bodies, friction=pin1, prismatic=pri1)
    parts = {"platform": plat, "pin": pin, "prismatic": pri}
    for i in range(3):
        parts[f"cylinder{i + 1}"], parts[f"piston{i + 1}"] = cyl[i], pis[i]
    return p, parts


def ten(body):
    """A body's standard parameters: m, m c, inertia about the frame's
    origin (parallel axes), the tensor's Ixx, Ixy, Ixz, Iyy, Iyz, Izz."""
    m, c, Ic = body
    I0 = Ic + m * (c @ c * np.eye(3) - np.outer(c, c))
    return [m, *(m * c), I0[0, 0], I0[0, 1], I0[0, 2], I0[1, 1], I0[1, 2], I0[2, 2]]


def layout_truth(parts, layout):
    """The truth's parameters in the layout's columns, by name."""
    out = []
    for name in layout.names:
        head, par = name.split(".")
        kind = head.rstrip("123")
        leg = int(head[-1]) - 1 if head[-1].isdigit() else 0
        if kind in ("pin", "prismatic"):
            law = parts[kind][leg]
            out.append(law["viscous" if par == "fv" else "coulomb"])
        else:
            key = head if head == "platform" or head[-1].isdigit() else f"{head}1"
            out.append(ten(parts[key])[INERTIAL.index(par)])
    return np.array(out)


def regressor_model(R_=R):
    """What identification knows: the geometry and g, every effect, both
    friction laws' vreg (0: the exact sign, as MuJoCo's side)."""
    law = {"viscous": 0.0, "coulomb": 0.0, "vreg": 0.0}
    return rps3.Model(R=R_, rho=RHO, g=G, friction=law, prismatic_friction=law,
                      effects=list(rps3.EFFECTS))


def kinematics(sym, q, dq, ddq):
    """The oracle's kinematics of one state (it reads R and rho only)."""
    return sym.kinematics(dict(oracle.ENTROPY, R=R, rho=RHO, g=G), q, dq, ddq)


def mujoco_forces(p, kins):
    """MuJoCo's actuator forces at the oracle's states kins."""
    model = mujoco_model.build(p)
    data = mujoco.MjData(model)
    F = np.empty((len(kins), 3))
    for k, kin in enumerate(kins):
        qpos, qvel, qacc = mujoco_model.state(model, kin)
        F[k] = mujoco_model.actuator_forces(model, data, qpos, qvel, qacc, p)
    return F


def nrmse(F, Fhat):
    return float(np.sqrt(np.mean((Fhat - F) ** 2) / np.mean(F ** 2)))


@pytest.fixture(scope="module")
def states():
    """The fit's and the held-out trajectories (pose, rates,
    accelerations) and the oracle's kinematics at their samples."""
    sym = oracle.symbolic()
    fit = ident_excite.random_fourier((0.0, 0.25, 0.31), (1.5, 0.12, 0.03), 0.2, 5, seed=3)
    held = ident_excite.random_fourier((0.0, 0.26, 0.30), (1.2, 0.10, 0.025), 0.25, 4,
                                       seed=17)
    out = {}
    for key, fo, n in (("fit", fit, N_FIT), ("test", held, N_HELD)):
        qs = fo.eval(np.linspace(0.0, fo.period, n, endpoint=False))
        out[key] = qs
        out["kin_" + key] = [kinematics(sym, *(x[k] for x in qs)) for k in range(n)]
    return out


@pytest.fixture(scope="module", params=["each", "identical"])
def case(request, states):
    legs = request.param
    p, parts = truth(legs)
    layout = ident.Layout(legs)
    geo = ident_excite.Geometry(R=R, rho=RHO, g=G, vreg=0.0)
    base = ident_excite.layout_base(geo, layout)
    pi = layout_truth(parts, layout)
    return {"legs": legs, "p": p, "parts": parts, "layout": layout, "base": base,
            "fit": states["fit"], "test": states["test"], "kin": states["kin_fit"],
            "F": mujoco_forces(p, states["kin_fit"]),
            "F_test": mujoco_forces(p, states["kin_test"]),
            "pi": pi, "truth": base.of(pi)}


def identify(case, R_=R):
    """The layout's regressors (fit, held out) for a model of radius R_."""
    m = regressor_model(R_)
    lay = case["layout"]
    return (lay.regressor(ident.regressor_std(m, *case["fit"])),
            lay.regressor(ident.regressor_std(m, *case["test"])))


def errors(Yb, F, theta, truth):
    """Each base parameter's relative error, share of the RMS force, and the
    force its error makes over the RMS force."""
    rms = np.sqrt(np.mean(F ** 2))
    col = np.sqrt(np.mean(Yb ** 2, axis=(0, 1)))
    share = col * np.abs(truth) / rms
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(truth != 0, theta / truth - 1.0, np.inf)
    return rel, share, col * np.abs(theta - truth) / rms


def test_mujoco_bodies_are_the_truths(case):
    """MuJoCo's bodies, at states of the oracle's kinematics, in the frames
    of docs/identification.md built from the oracle's positions alone: each
    body's mass, centre of mass and inertia are the truth's (the exporter's
    frames of the cylinders and pistons and the piston's centre of mass
    from its ball joint)."""
    p, parts = case["p"], case["parts"]
    model = mujoco_model.build(p)
    data = mujoco.MjData(model)
    for k in (0, N_FIT // 3, 2 * N_FIT // 3):
        kin = case["kin"][k]
        data.qpos[:] = mujoco_model.state(model, kin)[0]
        mujoco.mj_kinematics(model, data)
        assert mujoco_model.closure_residual(model, data) <= FRAME_TOL * R
        frames = {"platform": (kin["c"], kin["rot"])}
        for i in range(3):
            u = np.array([np.cos(PSI[i]), np.sin(PSI[i]), 0.0])
            axis = np.array([-np.sin(PSI[i]), np.cos(PSI[i]), 0.0])
            pin, ball = R * u, kin["c"] + kin["rot"] @ (RHO * R * u)
            e1 = (ball - pin) / np.linalg.norm(ball - pin)
            E = np.column_stack([e1, axis, np.cross(e1, axis)])
            frames[f"cylinder{i + 1}"] = (pin, E)
            frames[f"piston{i + 1}"] = (ball, E)
        mj_name = {"platform": "platform"}
        mj_name.update({f"{b}{i + 1}": f"{'link' if b == 'cylinder' else b}_{i}"
                        for b in ("cylinder", "piston") for i in range(3)})
        for key, (origin, E) in frames.items():
            m, c, Ic = parts[key]
            b = model.body(mj_name[key])
            xi = data.body(mj_name[key])
            rot = xi.ximat.reshape(3, 3)
            I_mj = rot @ np.diag(b.inertia) @ rot.T
            assert b.mass[0] == pytest.approx(m, rel=FRAME_TOL), key
            assert np.abs(xi.xipos - (origin + E @ c)).max() <= FRAME_TOL * R, key
            assert np.abs(I_mj - E @ Ic @ E.T).max() <= FRAME_TOL * np.abs(Ic).max(), key


def test_truth_and_base(case):
    """The test's standard parameters of the truth are the library's
    (rps3_std_params of the same bodies); the structural base has the
    counts of docs/identification.md (legs each: 37, identical: 19, with
    both frictions) and the fit's trajectory excites every one of them."""
    lay, base = case["layout"], case["base"]
    model = mujoco_model.model_of(case["p"])
    pi_lib = ident.std_params(model)
    assert np.abs(lay.matrix @ case["pi"] - pi_lib).max() <= STD_TOL * np.abs(pi_lib).max()
    assert base.rank == {"each": 37, "identical": 19}[case["legs"]]
    Yb = base.reduce(identify(case)[0])
    assert np.linalg.matrix_rank(Yb.reshape(-1, base.rank) /
                                 np.sqrt(np.mean(Yb ** 2, axis=(0, 1)))) == base.rank


@pytest.mark.parametrize("method", ["ols", "wls", "wls_c"])
def test_least_squares_recovers_mujoco_truth(case, method):
    Y, Yt = identify(case)
    base = case["base"]
    Yb = base.reduce(Y)
    F, truth, names = case["F"], case["truth"], base.base_names
    est = getattr(ident, method)(Yb, F, names=names)
    rel, share, err = errors(Yb, F, est.theta, truth)
    big = share >= SHARE_MIN
    assert big.sum() >= 10, dict(zip(names, share))   # 13 legs each, 10 identical
    for k in np.flatnonzero(big):
        assert abs(rel[k]) <= REL_TOL, (names[k], truth[k], est.theta[k])
    assert err.max() <= ERR_FORCE, dict(zip(names, err))
    assert nrmse(case["F_test"], base.reduce(Yt) @ est.theta) <= NRMSE_MAX


@pytest.mark.parametrize("reg", [None, 0.0])
def test_consistent_fit_recovers_mujoco_truth(case, reg):
    """The consistent fit on the layout's columns (layout_of): at reg 0 it
    converges to the truth's base parameters to rounding; at the default
    reg its bias is the regularisation's, bounded by ERR_FORCE_REG."""
    Y, Yt = identify(case)
    F, truth, base, lay = case["F"], case["truth"], case["base"], case["layout"]
    with warnings.catch_warnings():
        # a fit stopped short of the optimality test warns: an error here
        warnings.simplefilter("error", RuntimeWarning)
        fit = ident.consistent_c(Y, F, ident.layout_of(lay), names=lay.names, reg=reg)
    assert fit.consistent, fit.message
    # every pseudo-inertia (the library's eig_tol) and friction coefficient
    assert np.all(fit.eig >= -1e-10 * np.abs(fit.eig).max(axis=1, keepdims=True))
    assert np.all(fit.pi[lay.friction_indices] >= 0)
    assert fit.converged, fit.message
    theta = base.of(fit.pi)
    Yb = base.reduce(Y)
    rel, share, err = errors(Yb, F, theta, truth)
    for k in np.flatnonzero(share >= SHARE_MIN):
        assert abs(rel[k]) <= REL_TOL, (base.base_names[k], truth[k], theta[k])
    bound = ERR_FORCE if reg == 0.0 else ERR_FORCE_REG
    assert err.max() <= bound, dict(zip(base.base_names, err))
    assert nrmse(case["F_test"], Yt @ fit.pi) <= NRMSE_MAX


def test_wrong_geometry_is_seen(case):
    """The same pipeline with R 1 % off: the held-out NRMSE grows by orders
    of magnitude and the large base parameters miss the target."""
    base, names = case["base"], case["base"].base_names
    Y, Yt = identify(case)
    right = ident.ols(base.reduce(Y), case["F"], names=names)
    Yw, Ytw = identify(case, R_=1.01 * R)
    wrong = ident.ols(base.reduce(Yw), case["F"], names=names)
    e_right = nrmse(case["F_test"], base.reduce(Yt) @ right.theta)
    e_wrong = nrmse(case["F_test"], base.reduce(Ytw) @ wrong.theta)
    assert e_right <= ERR_FORCE and e_wrong >= WRONG_GAIN * ERR_FORCE, (e_right, e_wrong)
    rel, share, _ = errors(base.reduce(Yw), case["F"], wrong.theta, case["truth"])
    assert np.max(np.abs(rel[share >= SHARE_MIN])) > REL_TOL
