"""The C library's identification (rps3.ident_c over include/rps3.h,
docs/identification.md): its regressor against the Python regressor of
the paper model and the library's forces, its WLS against rps3.ident.wls,
and its consistent fit against the LMI fit of rps3.ident.consistent
(cvxpy with Clarabel) on the independent oracle's regressor
(tests/ident_oracle.py), also where the optimum lies on the boundary of
the cone."""

import time

import ident_oracle as O
import numpy as np
import pytest
import rps3
from rps3 import ident
from rps3 import ident_paper as P

# the C regressor and the Python one push the same loads through the same
# solve (the Python one a column per inverse-dynamics call, and payload
# first moments by a central difference): rounding, measured ~3e-16 of
# the columns' scale; 1e-10 is the required agreement
TOL_REGRESSOR = 1e-10
# WLS in C (gsl_multifit_wlinear on unit-norm columns) and in Python (QR
# of the column-scaled regressor): the same estimator, rounding times the
# condition number (~1e3 here): 1e-9 of each quantity's scale
TOL_WLS = 1e-9
# the consistent fits: two solvers of one convex objective, Clarabel to
# its ~1e-8 feasibility and the C fit to its optimality test; their base
# parameters must agree far inside the statistical uncertainty: within
# 5 % of the 1 %-noise standard deviation (the criterion the LMI fit's own
# bias test uses)
TOL_LMI = 0.05

ENTROPY = dict(M=0.2381, m=0.0917, link_Ic=3.17e-4,
               payload=dict(mass=0.0713, com=[0.0, 0.0, 0.0411],
                            inertia=[1.13e-4, 1.71e-4, 0.97e-4]),
               friction=dict(viscous=0.0137, coulomb=0.0029))


def states(n, seed):
    rng = np.random.default_rng(seed)
    q = np.column_stack([rng.uniform(-np.pi, np.pi, n), rng.uniform(0.05, 0.45, n),
                         rng.uniform(0.27, 0.36, n)])
    return q, rng.normal(size=(n, 3)) * [1.0, 0.5, 0.05], rng.normal(size=(n, 3)) * [5.0, 2.0, 0.3]


@pytest.mark.parametrize("vreg", [0.0, 0.02])
@pytest.mark.parametrize("pset", [P.PaperSet(), P.PaperSet(payload=True)])
def test_regressor_matches_python(vreg, pset):
    geo = P.Geometry(R=0.2385, rho=0.4387, d=0.1383, vreg=vreg)
    m = geo.model(effects=list(rps3.EFFECTS), **{**ENTROPY, "friction": {
        **ENTROPY["friction"], "vreg": vreg}})
    q, dq, ddq = states(300, 4)
    Yc = ident.regressor(m, q, dq, ddq)
    Yp = P.paper_regressor(q, dq, ddq, geo, pset)
    cols = [ident.C_PAPER_NAMES.index(n) for n in pset.names]
    scale = np.abs(Yp).max(axis=(0, 1))
    assert np.all(np.abs(Yc[..., cols] - Yp) <= TOL_REGRESSOR * scale)
    assert ident.C_PAPER_NAMES == P.PAPER_NAMES


@pytest.mark.parametrize("method", ["lagrange", "newton_euler"])
def test_regressor_times_parameters_is_the_force(method):
    m = rps3.Model(R=0.2385, rho=0.4387, d=0.1383, effects=list(rps3.EFFECTS),
                   method=method, **ENTROPY)
    q, dq, ddq = states(2000, 9)
    Y = ident.regressor(m, q, dq, ddq)
    F = m.inverse(q, dq, ddq).force
    scale = np.abs(Y * ident.paper_params(m)).sum(axis=-1)
    assert np.all(np.abs(Y @ ident.paper_params(m) - F) <= TOL_REGRESSOR * scale)
    # one point in, one point out
    assert ident.regressor(m, q[0], dq[0], ddq[0]).shape == (3, 12)


def test_regressor_refuses():
    m = rps3.Model(effects=list(rps3.EFFECTS), **ENTROPY)
    q, dq, ddq = states(5, 2)
    q[3, 2] = -0.2
    with pytest.raises(ValueError, match="point 3: "):
        ident.regressor(m, q, dq, ddq)
    with pytest.raises(ValueError, match="dpose"):
        ident.regressor(m, q)
    off = rps3.Model(payload=dict(mass=0.1, com=[0.01, 0.02, 0.0]), effects=["payload"])
    with pytest.raises(ValueError, match="payload.com"):
        ident.paper_params(off)


@pytest.fixture(scope="module")
def paper_data():
    """An exciting trajectory of the paper model with every effect, its C
    regressor of the set without the payload, the truth and the forces."""
    rng = np.random.default_rng(5)
    t = np.arange(0, 20, 0.02)
    q, dq, ddq = O.exciting(t, rng)
    m = rps3.Model(effects=list(rps3.EFFECTS), **ENTROPY)
    names = P.PaperSet().names
    cols = [ident.C_PAPER_NAMES.index(n) for n in names]
    Y = ident.regressor(m, q, dq, ddq)[..., cols]
    pi = ident.paper_params(m)[cols]
    return dict(Y=Y, pi=pi, F=Y @ pi, names=names, cols=cols, rng=rng)


def test_wls_c_matches_python(paper_data):
    d = paper_data
    noise = d["rng"].normal(size=d["F"].shape) * [0.02, 0.05, 0.01]
    F = d["F"] + noise
    c = ident.wls_c(d["Y"], F, names=d["names"])
    py = ident.wls(d["Y"], F, names=d["names"])
    assert c.names == py.names and c.dof == py.dof
    assert np.all(np.abs(c.theta - py.theta) <= TOL_WLS * np.abs(py.theta).max()
                  + 1e-3 * py.std)
    assert np.allclose(c.sigma, py.sigma, rtol=1e-9)
    assert np.allclose(c.std, py.std, rtol=1e-6)
    assert np.allclose(c.ci95, py.ci95, rtol=1e-6, atol=1e-3 * py.std.max())
    # the C cond is that of the weighted regressor (the one fitted)
    Ya = d["Y"].reshape(-1, d["Y"].shape[-1]) / np.tile(c.sigma, len(d["Y"]))[:, None]
    cond = ident.check_excitation(Ya, d["names"])
    assert abs(c.cond - cond) <= 1e-6 * cond


def test_wls_c_names_what_is_not_identifiable(paper_data):
    d = paper_data
    m = rps3.Model(effects=list(rps3.EFFECTS), **ENTROPY)
    q, dq, ddq = states(400, 3)
    Y = ident.regressor(m, q, dq, ddq)
    F = Y @ ident.paper_params(m)
    with pytest.raises(ident.NotExcitingError) as e:
        ident.wls_c(Y, F, names=ident.C_PAPER_NAMES)
    assert "rank 11 < 12" in str(e.value)
    assert {"M", "payload.m"} <= set(e.value.unidentifiable)
    with pytest.raises(ValueError, match="weight"):
        ident.wls_c(d["Y"], d["F"], weights=[1.0, -1.0, 1.0])


def test_wls_c_message_counts_what_it_cannot_name():
    """Many undetermined columns with long names: the message names as
    many as it holds and counts the rest; unidentifiable lists them all."""
    rng = np.random.default_rng(5)
    p = 60
    Y = np.zeros((400, p))
    Y[:, :4] = rng.normal(size=(400, 4))
    F = Y[:, :4] @ np.ones(4)
    names = tuple(f"a_rather_long_parameter_name_{k:02d}" for k in range(p))
    with pytest.raises(ident.NotExcitingError) as e:
        ident.wls_c(Y, F, names=names)
    msg = str(e.value)
    named = [n for n in names[4:] if n in msg]
    assert 0 < len(named) < p - 4
    assert msg.endswith(f" and {p - 4 - len(named)} more")
    assert len(e.value.unidentifiable) == p - 4


LAYOUT = ident.Layout("each", ("prismatic",))


@pytest.fixture(scope="module")
def oracle_data():
    """The oracle's standard regressor of seven general bodies on an
    exciting trajectory (as tests/test_ident.py's), 1 % noise."""
    rng = np.random.default_rng(3)
    g = O.Geometry()
    t = np.arange(0, 20, 0.02)
    p, dp, ddp = O.exciting(t, rng)
    Y = LAYOUT.regressor(O.regressor(g, p, dp, ddp))
    pi = O.random_parameters(rng, LAYOUT)
    F0 = Y @ pi
    F = F0 + rng.normal(size=F0.shape) * 0.01 * np.sqrt(np.mean(F0**2))
    return dict(Y=Y, F=F, pi=pi, g=g)


def test_consistent_c_agrees_with_the_lmi_fit(oracle_data):
    """The same objective at the default reg, two solvers: the C fit
    converged, its base parameters (the combinations the data determine)
    within TOL_LMI of the noise's standard deviation of the LMI fit's, its
    residual no larger, and every pseudo-inertia positive semidefinite."""
    from test_ident import rich_base

    d = oracle_data
    base = rich_base(d["g"].R, d["g"].rho, LAYOUT)
    t0 = time.perf_counter()
    lmi = ident.consistent(d["Y"], d["F"], LAYOUT)
    t1 = time.perf_counter()
    c = ident.consistent_c(d["Y"], d["F"], LAYOUT, names=LAYOUT.names)
    t2 = time.perf_counter()
    print(f"\nLMI (cvxpy, Clarabel) {t1 - t0:.3f} s; C {t2 - t1:.3f} s, "
          f"{c.niter} iterations, converged {c.converged}")
    assert c.consistent and c.converged
    for e in c.eig:
        assert e.min() >= -1e-10 * np.abs(e).max()
    assert np.all(c.pi[LAYOUT.friction_indices] >= 0)
    ols = ident.ols(d["Y"], d["F"], base=base)
    diff = np.abs(base.of(c.pi) - base.of(lmi.pi)) / ols.std
    print(f"base parameters: largest |C - LMI| / std {diff.max():.3g}")
    assert diff.max() <= TOL_LMI
    # the LMI's interior-point solution is feasible to ~1e-8: the C fit's
    # residual may exceed it by no more than that
    assert np.linalg.norm(c.residual) <= (1 + 1e-6) * np.linalg.norm(lmi.residual)


def test_consistent_c_monte_carlo_and_timing():
    """A small Monte Carlo on the paper model (payload identified, no
    Coulomb friction in truth): every fit converged and checked consistent;
    the times of WLS on 30,000 rows and of the consistent fit reported, the
    fit's median under its 1 s target (measured ~0.01 s)."""
    rng = np.random.default_rng(8)
    t = np.arange(0, 50, 0.005)
    q, dq, ddq = O.exciting(t, rng)
    kw = {**ENTROPY, "friction": dict(viscous=0.0137, coulomb=0.0, vreg=0.01)}
    m = rps3.Model(effects=list(rps3.EFFECTS), **kw)
    pset = P.PaperSet(payload=True)
    cols = [ident.C_PAPER_NAMES.index(n) for n in pset.names]
    Y = ident.regressor(m, q, dq, ddq)[..., cols]
    assert Y.shape[0] * 3 == 30000
    F0 = Y @ ident.paper_params(m)[cols]
    lay = ident.paper_layout(cols)
    times, nconv = [], 0
    for _ in range(10):
        F = F0 + rng.normal(size=F0.shape) * 0.01 * np.sqrt(np.mean(F0**2))
        t0 = time.perf_counter()
        est = ident.wls_c(Y, F, names=pset.names)
        t1 = time.perf_counter()
        fit = ident.consistent_c(Y, F, lay, names=pset.names)
        t2 = time.perf_counter()
        times.append((t1 - t0, t2 - t1))
        assert fit.consistent and fit.converged
        assert fit.pi[-1] >= 0 and fit.pi[-2] >= 0
        nconv += fit.converged
        assert est.dof == 30000 - len(cols)
    w, c = np.median(times, axis=0)
    print(f"\nWLS of 30,000 rows: median {w:.3f} s (target 0.5 s); consistent fit "
          f"{c:.3f} s (target 1 s); converged {nconv} of 10, consistent 10 of 10")
    assert c < 1.0


# ---------------------------------------------------------------- boundary
# The consistent fit where the optimum lies on the boundary of the cone (a
# singular pseudo-inertia, a >= 0 column at 0), against an independent
# solve of the same objective by cvxpy with Clarabel at tight tolerances.

# the objectives of the two solvers, relative: Clarabel at 1e-12 gap and
# feasibility reaches the optimum to ~1e-9 (measured 4e-10), the C fit
# converges to opt_tol = 1e-6 of its cost (its barrier stage aims at 1e-8:
# measured 2e-9 to 2e-8)
TOL_OBJ = 1e-6
# the C fit's pseudo-inertias: U U^T rounded, rps3_ident_opts.eig_tol
TOL_EIG = 1e-10
# an optimum on the boundary: a pseudo-inertia eigenvalue below 1e-6 of
# its body's largest, or a >= 0 column below 1e-6 of the largest friction
# coefficient (interior points are many orders above: 1e-3 and up)
TOL_BOUNDARY = 1e-6
# the fit's iterations on these cases: the log-Cholesky stage's 30, the
# plain Cholesky stage's first 20, then the barrier stage's Newton steps
# (measured 86 to 110 in all; the plain stage alone took 185 to 1,300):
# a bound that a slower last stage fails
MAX_ITER_BOUNDARY = 150
CLARABEL_TIGHT = dict(tol_gap_abs=1e-12, tol_gap_rel=1e-12, tol_feas=1e-12,
                      max_iter=500)


def objective(Y, F, pi, layout, reg):
    """|F - Y pi|^2 / |F|^2 + reg sum_b tr J_b (docs/identification.md),
    from the full rows: the number both fits minimise."""
    Ya, Fa = Y.reshape(-1, Y.shape[-1]), F.reshape(-1)
    r = Fa - Ya @ pi
    tr = sum(pi[10 * k] + 0.5 * (pi[10 * k + 4] + pi[10 * k + 7] + pi[10 * k + 9])
             for k in range(len(layout.bodies)))
    return r @ r / (Fa @ Fa) + reg * tr


def lmi_reference(Y, F, layout, reg):
    """The LMI problem of rps3.ident.consistent, its objective written out
    here and solved by Clarabel at tight tolerances."""
    from rps3 import ident_consistent

    cp, pi, cons, Js = ident_consistent._lmi_problem(layout)
    Ya, Fa = Y.reshape(-1, Y.shape[-1]), F.reshape(-1)
    cs = np.linalg.norm(Ya, axis=0)
    cs[cs == 0] = 1.0
    Ra = np.linalg.qr(np.column_stack([Ya / cs, Fa]), mode="r") / np.linalg.norm(Fa)
    p = Ya.shape[1]
    fit = cp.sum_squares(Ra[:p, :p] @ cp.multiply(cs, pi) - Ra[:p, p])
    prob = cp.Problem(cp.Minimize(fit + reg * sum(cp.trace(J) for J in Js)), cons)
    prob.solve(solver="CLARABEL", **CLARABEL_TIGHT)
    assert prob.status == "optimal"
    return np.asarray(pi.value, float)


def on_boundary(pi, layout):
    """Whether pi has a singular pseudo-inertia or a >= 0 column at 0."""
    eig = [np.linalg.eigvalsh(ident.pseudo_inertia(pi[10 * k:10 * k + 10]))
           for k in range(len(layout.bodies))]
    fr = pi[layout.friction_indices]
    return (min(e[0] / e[-1] for e in eig) < TOL_BOUNDARY
            or (len(fr) > 0 and fr.min() < TOL_BOUNDARY * fr.max()))


def boundary_data(layout, seed, scale=1.0, T=20.0, noise=0.01, rods=(),
                  no_coulomb=False):
    """The oracle's regressor of a layout on an exciting trajectory (scale
    < 1, short T: weakly exciting), a random consistent truth with bodies
    made rods (a singular pseudo-inertia: all mass on a line) and the
    Coulomb coefficients 0 if asked, forces with noise of that fraction of
    their RMS."""
    rng = np.random.default_rng(seed)
    t = np.arange(0, T, 0.02)
    p, dp, ddp = O.exciting(t, rng, scale)
    Y = layout.regressor(O.regressor(O.Geometry(), p, dp, ddp))
    pi = O.random_parameters(rng, layout)
    for k in rods:
        m = pi[10 * k]
        pi[10 * k:10 * k + 10] = ident.body_parameters(
            m, pi[10 * k + 1:10 * k + 4] / m, m * 0.08**2 / 12 * np.diag([0.0, 1.0, 1.0]))
    if no_coulomb:
        pi[layout.friction_indices[1::2]] = 0.0
    F0 = Y @ pi
    return Y, F0 + rng.normal(size=F0.shape) * noise * np.sqrt(np.mean(F0**2))


EACH = ident.Layout("each", ("prismatic",))
IDENTICAL = ident.Layout("identical", ("prismatic", "pin"))
BOUNDARY_CASES = {
    "weak_each": (EACH, dict(seed=3, scale=0.1, T=5.0)),
    "weak_identical": (IDENTICAL, dict(seed=5, scale=0.2, T=5.0)),
    "rods": (EACH, dict(seed=3, rods=(0, 2, 5), noise=1e-3)),
    "no_coulomb": (EACH, dict(seed=4, no_coulomb=True)),
    "rods_no_friction_identical": (IDENTICAL, dict(seed=6, rods=(1,), no_coulomb=True,
                                                  noise=1e-3)),
}


@pytest.mark.parametrize("case", list(BOUNDARY_CASES))
def test_consistent_c_reaches_the_boundary_optimum(case):
    """Weakly exciting data, general-body layouts, rods in truth, Coulomb
    friction 0 in truth: the optimum is on the boundary of the cone (checked
    on the reference), where a log-Cholesky iterate alone stalls (its
    diagonal heads for minus infinity).  The C fit's objective within TOL_OBJ of the
    reference's, its fitted forces the reference's (the objective is
    strictly convex in Y pi: |Y (pi - pi*)|^2 / |F|^2 is at most the
    objective's excess), every pseudo-inertia positive semidefinite, the
    >= 0 columns >= 0, converged with its optimality measure small, in at
    most MAX_ITER_BOUNDARY iterations."""
    layout, kw = BOUNDARY_CASES[case]
    Y, F = boundary_data(layout, **kw)
    reg = 1e-9
    ref = lmi_reference(Y, F, layout, reg)
    assert on_boundary(ref, layout)
    t0 = time.perf_counter()
    c = ident.consistent_c(Y, F, layout, names=layout.names)
    dt = time.perf_counter() - t0
    o_ref, o_c = objective(Y, F, ref, layout, reg), objective(Y, F, c.pi, layout, reg)
    print(f"\n{case}: {layout.n} parameters, C {dt:.2f} s, {c.niter} iterations; "
          f"objective C / reference - 1 = {o_c / o_ref - 1:.2e}; gap {c.gap / c.cost:.1e}")
    assert c.converged and c.consistent
    assert c.niter <= MAX_ITER_BOUNDARY
    assert abs(o_c - o_ref) <= TOL_OBJ * o_ref
    assert c.gap <= TOL_OBJ * c.cost
    Ya, Fa = Y.reshape(-1, layout.n), F.reshape(-1)
    dev = np.linalg.norm(Ya @ (c.pi - ref)) ** 2 / (Fa @ Fa)
    assert dev <= 4 * TOL_OBJ * o_ref
    for e in c.eig:
        assert e.min() >= -TOL_EIG * np.abs(e).max()
    assert np.all(c.pi[layout.friction_indices] >= 0)


@pytest.mark.parametrize("case", list(BOUNDARY_CASES))
def test_consistent_c_without_tie_break(case):
    """reg 0: no tie-break, the bodies the data see only in part anywhere
    in a face of the cone at no cost (the barrier stage keeps a minimiser
    by its far trace terms).  Converged in at most MAX_ITER_BOUNDARY
    iterations, consistent, its objective no worse than the reference's
    (Clarabel, without the trace term to bound those directions, stops up
    to ~1e-6 above the C fit: measured 1e-10 to 1.4e-6), within its own
    measure of the optimum."""
    layout, kw = BOUNDARY_CASES[case]
    Y, F = boundary_data(layout, **kw)
    ref = lmi_reference(Y, F, layout, 0.0)
    c = ident.consistent_c(Y, F, layout, names=layout.names, reg=0.0)
    o_ref, o_c = objective(Y, F, ref, layout, 0.0), objective(Y, F, c.pi, layout, 0.0)
    print(f"\n{case}, reg 0: {c.niter} iterations; objective C / reference - 1 = "
          f"{o_c / o_ref - 1:.2e}; gap {c.gap / c.cost:.1e}")
    assert c.converged and c.consistent
    assert c.niter <= MAX_ITER_BOUNDARY
    assert o_c <= (1 + TOL_OBJ) * o_ref
    assert c.gap <= TOL_OBJ * c.cost
    for e in c.eig:
        assert e.min() >= -TOL_EIG * np.abs(e).max()
    assert np.all(c.pi[layout.friction_indices] >= 0)


def test_consistent_c_says_when_not_optimal():
    """An iteration budget too small for a boundary case: not converged,
    the message names the optimality measure, the iterate is consistent
    and its objective above the optimum's."""
    layout, kw = BOUNDARY_CASES["weak_identical"]
    Y, F = boundary_data(layout, **kw)
    with pytest.warns(RuntimeWarning, match="optimality measure"):
        c = ident.consistent_c(Y, F, layout, names=layout.names, max_iter=40)
    assert not c.converged and c.consistent
    assert c.gap > TOL_OBJ * c.cost
