"""The C library's identification (rps3.ident_c over include/rps3.h,
docs/identification.md): its regressor against the Python regressor of
the paper model and the library's forces, its WLS against rps3.ident.wls,
and its log-Cholesky consistent fit against the LMI fit of
rps3.ident.consistent (cvxpy with Clarabel) on the independent oracle's
regressor (tests/ident_oracle.py)."""

import time
import warnings

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
# its ~1e-8 feasibility and the C trust region to gtol; their base
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


# the tie-break weight of both fits in the comparison: at the default 1e-9
# its curvature is so small that the C trust-region solver stops at
# max_iter on this 76-parameter layout short of the optimum
# (docs/identification.md, limits); 1e-7 is one objective both solve
REG_COMPARE = 1e-7


def test_consistent_c_agrees_with_the_lmi_fit(oracle_data, monkeypatch):
    """The same objective, two solvers: the C fit's base parameters (the
    combinations the data determine) within TOL_LMI of the noise's
    standard deviation of the LMI fit's, its residual no larger, and every
    pseudo-inertia positive semidefinite."""
    from rps3 import ident_consistent
    from test_ident import rich_base

    d = oracle_data
    base = rich_base(d["g"].R, d["g"].rho, LAYOUT)
    monkeypatch.setattr(ident_consistent, "LMI_REG", REG_COMPARE)
    t0 = time.perf_counter()
    lmi = ident.consistent(d["Y"], d["F"], LAYOUT)
    t1 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        c = ident.consistent_c(d["Y"], d["F"], LAYOUT, names=LAYOUT.names,
                               reg=REG_COMPARE)
    t2 = time.perf_counter()
    print(f"\nLMI (cvxpy, Clarabel) {t1 - t0:.3f} s; C log-Cholesky {t2 - t1:.3f} s, "
          f"{c.niter} iterations, converged {c.converged}")
    assert c.consistent
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
    Coulomb friction in truth): every fit checked consistent; the times of
    WLS on 30,000 rows and of the consistent fit reported (not asserted:
    targets 0.5 s and 1 s)."""
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
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            fit = ident.consistent_c(Y, F, lay, names=pset.names)
        t2 = time.perf_counter()
        times.append((t1 - t0, t2 - t1))
        assert fit.consistent
        assert fit.pi[-1] >= 0 and fit.pi[-2] >= 0
        nconv += fit.converged
        assert est.dof == 30000 - len(cols)
    w, c = np.median(times, axis=0)
    print(f"\nWLS of 30,000 rows: median {w:.3f} s (target 0.5 s); consistent fit "
          f"{c:.3f} s (target 1 s); converged {nconv} of 10, consistent 10 of 10")
