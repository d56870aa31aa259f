"""Physically consistent identification for rps3.ident
(docs/identification.md): every body's pseudo-inertia positive
semidefinite and friction >= 0, fitted on the standard parameters by a
linear-matrix-inequality problem (cvxpy with Clarabel), certified by the
eigenvalues afterwards, and the per-body consistency report.  rps3.ident
re-exports every public name.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from rps3.ident import (
    COND_MAX,
    Base,
    InconsistentFitError,
    Layout,
    _column_scale,
    _need,
    _r_factor,
    _stacked,
    check_excitation,
    inertia_matrix,
    pseudo_inertia,
)

# ------------------------------------------------- physical consistency

#: a pseudo-inertia eigenvalue down to -EIG_TOL times the body's largest
#: counts as zero (the interior-point solver's feasibility tolerance is
#: ~1e-8 relative)
EIG_TOL = 1e-6


@dataclass(frozen=True)
class BodyReport:
    name: str
    eig: np.ndarray                  #: pseudo-inertia eigenvalues
    mass: float
    com: np.ndarray | None           #: centre of mass (body axes) [m], None if m <= 0
    principal: np.ndarray | None     #: principal moments about the com [kg m^2]
    triangle: bool                   #: I1 + I2 >= I3 for every permutation
    ok: bool


def _fmt(v: np.ndarray) -> str:
    return "[" + " ".join(f"{x:.3g}" for x in v) + "]"


@dataclass(frozen=True)
class ConsistencyReport:
    bodies: list[BodyReport]
    friction: dict[str, float] = field(default_factory=dict)
    ok: bool = True

    def __str__(self) -> str:
        lines = []
        for b in self.bodies:
            lines.append(f"{b.name}: {'consistent' if b.ok else 'NOT consistent'}; "
                         f"pseudo-inertia eigenvalues "
                         f"{_fmt(b.eig)}; mass {b.mass:.4g} kg"
                         + ("" if b.principal is None else
                            f"; principal moments {_fmt(b.principal)}"
                            f" kg m^2, triangle inequalities "
                            f"{'hold' if b.triangle else 'FAIL'}"))
        bad = [k for k, v in self.friction.items() if v < 0]
        lines.append("friction: " + ("all >= 0" if not bad else
                                     "NEGATIVE " + ", ".join(bad)))
        return "\n".join(lines)


def consistency_report(pi: ArrayLike, layout: Layout,
                       eig_tol: float = EIG_TOL) -> ConsistencyReport:
    """Per body: its pseudo-inertia's eigenvalues (>= -eig_tol times the
    largest: consistent), mass, centre of mass, principal moments about
    the centre of mass and the triangle inequalities; the friction
    coefficients' signs."""
    p = np.asarray(pi, float)
    if p.shape != (layout.n,):
        raise ValueError(f"pi: expected {layout.n} parameters, got shape {p.shape}")
    reps = []
    for k, name in enumerate(layout.bodies):
        q = p[10 * k:10 * k + 10]
        eig = np.linalg.eigvalsh(pseudo_inertia(q))
        scale = max(np.abs(eig).max(), 1e-300)
        ok = bool(eig.min() >= -eig_tol * scale)
        com = principal = None
        tri = True
        if q[0] > 0:
            com = q[1:4] / q[0]
            Ic = inertia_matrix(q) - q[0] * (com @ com * np.eye(3) - np.outer(com, com))
            principal = np.linalg.eigvalsh(Ic)
            # the principal moments are sums of two eigenvalues of the
            # centroidal second moment: the pseudo-inertia's tolerance, twice
            tol = 2 * eig_tol * scale
            tri = bool(principal.min() >= -tol and
                       principal[0] + principal[1] >= principal[2] - tol)
        reps.append(BodyReport(name, eig, float(q[0]), com, principal, tri,
                               ok and tri))
    fr = {layout.names[j]: float(p[j]) for j in layout.friction_indices}
    tol = eig_tol * max([abs(v) for v in fr.values()] + [1e-300])
    ok = all(b.ok for b in reps) and all(v >= -tol for v in fr.values())
    return ConsistencyReport(reps, fr, ok)


@dataclass(frozen=True)
class ConsistentFit:
    pi: np.ndarray               #: standard parameters of the layout, (p,)
    names: tuple[str, ...]
    status: str                  #: the solver's status
    residual: np.ndarray         #: F - Y pi [N]
    report: ConsistencyReport


def _lmi_problem(layout: Layout) -> Any:
    cp = _need("cvxpy")

    pi = cp.Variable(layout.n)
    cons = []
    Js = []
    for k in range(len(layout.bodies)):
        q = pi[10 * k:10 * k + 10]
        J = cp.Variable((4, 4), PSD=True)
        tr = (q[4] + q[7] + q[9]) / 2
        cons += [J[0, 0] == tr - q[4], J[1, 1] == tr - q[7], J[2, 2] == tr - q[9],
                 J[0, 1] == -q[5], J[0, 2] == -q[6], J[1, 2] == -q[8],
                 J[0, 3] == q[1], J[1, 3] == q[2], J[2, 3] == q[3], J[3, 3] == q[0]]
        Js.append(J)
    fi = layout.friction_indices
    if len(fi):
        cons.append(pi[fi] >= 0)
    return cp, pi, cons, Js


#: weight of the total pseudo-inertia trace sum_b (m_b + tr Sigma_b) [1/kg]
#: against the squared residual over |F|^2 in :func:`consistent`: it picks
#: the lightest, most compact bodies among the fits the data cannot tell
#: apart, and moves the fit by about LMI_REG / (|F|^2 curvature): far below
#: the noise (tests/test_ident.py measures the bias on exact data)
LMI_REG = 1e-9


def consistent(Y: ArrayLike, F: ArrayLike, layout: Layout, *,
               base: Base | None = None, cond_max: float = COND_MAX,
               weights: ArrayLike | None = None, eig_tol: float = EIG_TOL,
               solver: str = "CLARABEL") -> ConsistentFit:
    """Physically consistent least squares on the layout's standard
    parameters: minimise |W (F - Y pi)|^2 subject to every body's 4x4
    pseudo-inertia positive semidefinite and every friction coefficient
    >= 0 (a semidefinite program, cvxpy with Clarabel).  Y is the layout's
    regressor (Layout.regressor); weights (per row, or per actuator (3,))
    e.g. 1 / sigma from :func:`wls`.  The standard parameters the data do
    not determine are fixed by a small penalty on the total pseudo-inertia
    trace, LMI_REG sum_b (m_b + tr Sigma_b), added to the normalised
    squared residual: the lightest, most compact bodies among the fits
    the data cannot tell apart.  With ``base`` (the layout's structural
    base parameters) the data must excite every base parameter, as for
    :func:`ols`; without it, directions the data leave unexcited are set
    by that penalty alone.

    Raises:
        NotExcitingError: with ``base``, the data do not determine the
            base parameters (:func:`check_excitation`).
        InconsistentFitError: the solver's status is not optimal, or a
            pseudo-inertia eigenvalue or a friction coefficient of the
            result is below -eig_tol (relative).
    """
    Ya, Fa_, act = _stacked(Y, F)
    assert Fa_ is not None
    Fa = Fa_
    if Ya.shape[1] != layout.n:
        raise ValueError(f"Y: {Ya.shape[1]} columns, the layout has {layout.n} parameters")
    if base is not None:
        if base.K.shape[1] != layout.n:
            raise ValueError("base: computed for another layout")
        check_excitation(base.reduce(Ya), base.base_names, cond_max)
    w = np.ones(len(Fa))
    if weights is not None:
        wa = np.asarray(weights, float).reshape(-1)
        if wa.size not in (3, len(Fa)) or not np.all(wa > 0):
            raise ValueError(f"weights: expected 3 (per actuator) or {len(Fa)} "
                             "(per row) positive numbers")
        w = wa[act] if wa.size == 3 else wa
    Yw, Fw = Ya * w[:, None], Fa * w
    scale = np.linalg.norm(Fw) or 1.0
    cs = _column_scale(Yw)
    p = layout.n
    # |Yw pi - Fw|^2 = |R (cs pi) - z|^2 + rho^2 from the R factor of the
    # scaled [Yw, Fw]: a p-row objective, and numbers near 1 for the solver
    Ra = _r_factor(np.column_stack([Yw / cs, Fw])) / scale
    cp, pi, cons, Js = _lmi_problem(layout)
    fit = cp.sum_squares(Ra[:p, :p] @ cp.multiply(cs, pi) - Ra[:p, p])
    # the parameters the data do not determine: a tie-break of weight
    # LMI_REG per kg (or kg m^2) of total pseudo-inertia trace
    size = sum(cp.trace(J) for J in Js)
    prob = cp.Problem(cp.Minimize(fit + LMI_REG * size), cons)
    prob.solve(solver=solver)
    if prob.status != "optimal" or pi.value is None:
        raise InconsistentFitError(f"consistent: the solver {solver} ended with "
                                   f"status {prob.status!r}")
    est = np.asarray(pi.value, float)
    rep = consistency_report(est, layout, eig_tol)
    if not rep.ok:
        raise InconsistentFitError("consistent: the solution is not physically "
                                   "consistent within the tolerance:\n" + str(rep))
    return ConsistentFit(est, layout.names, prob.status, Fa - Ya @ est, rep)


def base_consistent(theta: ArrayLike, base: Base, layout: Layout,
                    solver: str = "CLARABEL") -> bool:
    """Whether base parameters theta (e.g. an OLS estimate) are those of
    some physically consistent standard parameters: the feasibility of
    K pi = theta with every pseudo-inertia PSD and friction >= 0 (an SDP)."""
    if base.K.shape[1] != layout.n:
        raise ValueError("base: computed for another layout")
    cp, pi, cons, _ = _lmi_problem(layout)
    th = np.asarray(theta, float)
    sc = np.where(np.abs(th) > 0, np.abs(th), 1.0)
    cons.append(cp.multiply(1.0 / sc, base.K @ pi) == th / sc)
    prob = cp.Problem(cp.Minimize(0), cons)
    prob.solve(solver=solver)
    return prob.status == "optimal"
