"""Identification of the manipulator's inertia and friction parameters from
a regressor, F = Y(q, qd, qdd) pi (docs/identification.md).

    lay = rps3.ident.Layout(legs="each", friction=("prismatic",))
    base = rps3.ident.base_parameters(Y_rich, lay.names)  # structural, (3N, p) Y
    est = rps3.ident.ols(Y, F, base=base)                 # base parameters, 95 % intervals
    fit = rps3.ident.consistent(Y, F, lay)                # standard parameters, LMI
    print(rps3.ident.consistency_report(fit.pi, lay))

The standard parameters are those of seven rigid bodies (the platform, and
per leg the cylinder turning about its pin and the piston sliding in it),
10 each, in the order of :data:`STANDARD_NAMES`, then the friction
coefficients.  Every function works on any stacked regressor (Y, F): rows
are force equations (one per actuator and sample), columns parameters.
Y may be given as (n, 3, p) with F (n, 3) (three actuators per sample) or
as (N, p) with F (N,).

The estimators need scipy (QR, the Butterworth filter, Student's t) and,
for :func:`consistent`, cvxpy with the Clarabel solver: the package's
``ident`` extra.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

#: the seven bodies, in the order of the standard parameters
BODIES: tuple[str, ...] = ("platform", "cylinder1", "piston1", "cylinder2",
                           "piston2", "cylinder3", "piston3")
#: a body's 10 standard parameters: mass [kg], first moment m c [kg m] in the
#: body's axes from its origin, inertia about the origin [kg m^2]
INERTIAL: tuple[str, ...] = ("m", "mcx", "mcy", "mcz", "Ixx", "Ixy", "Ixz",
                             "Iyy", "Iyz", "Izz")
#: friction kinds: viscous fv [N s/m | N m s/rad] and Coulomb fc [N | N m]
FRICTION_KINDS: tuple[str, ...] = ("prismatic", "pin")
N_BODY_PARAMETERS = 70
N_STANDARD = 82
#: names of the 82 standard parameters: body.parameter, then
#: prismatic1.fv, prismatic1.fc, ..., pin3.fc
STANDARD_NAMES: tuple[str, ...] = tuple(
    [f"{b}.{p}" for b in BODIES for p in INERTIAL]
    + [f"{k}{i}.{c}" for k in FRICTION_KINDS for i in (1, 2, 3)
       for c in ("fv", "fc")])


class NotExcitingError(ValueError):
    """The data do not determine every parameter: the message names the
    parameter combinations left undetermined and the condition number."""

    def __init__(self, message: str, cond: float, unidentifiable: list[str]):
        super().__init__(message)
        self.cond = cond
        self.unidentifiable = unidentifiable


class InconsistentFitError(RuntimeError):
    """The constrained fit did not reach a certified physically consistent
    optimum (solver status, or a pseudo-inertia eigenvalue below the
    tolerance)."""


# ------------------------------------------------------------------ layout

@dataclass(frozen=True)
class Layout:
    """Which parameters a model has: every leg its own bodies
    (``legs="each"``) or three identical legs (``"identical"``: one
    cylinder and one piston, each leg's in its own axes); which friction
    kinds; and friction coefficients per leg or one pair per kind shared
    by the three legs (``friction_per_leg``, by default as the legs: per
    leg for "each", shared for "identical").

    ``matrix`` maps the layout's parameters to the 82 standard ones
    (pi_standard = matrix @ pi), so a standard regressor Y gives the
    layout's as Y @ matrix (:meth:`regressor`)."""

    legs: str = "each"
    friction: tuple[str, ...] = ("prismatic", "pin")
    friction_per_leg: bool | None = None

    def __post_init__(self) -> None:
        if self.legs not in ("each", "identical"):
            raise ValueError(f"legs: expected 'each' or 'identical', got {self.legs!r}")
        if isinstance(self.friction, str):
            raise ValueError(f"friction: expected a tuple of kinds, got {self.friction!r}")
        for k in self.friction:
            if k not in FRICTION_KINDS:
                raise ValueError(f"friction: unknown kind {k!r}; known: "
                                 f"{', '.join(FRICTION_KINDS)}")

    @property
    def per_leg(self) -> bool:
        """Whether each leg has its own friction coefficients."""
        return (self.legs == "each" if self.friction_per_leg is None
                else bool(self.friction_per_leg))

    @property
    def bodies(self) -> tuple[str, ...]:
        """The layout's bodies (each 10 parameters, first in the vector)."""
        return BODIES if self.legs == "each" else ("platform", "cylinder", "piston")

    @property
    def names(self) -> tuple[str, ...]:
        out = [f"{b}.{p}" for b in self.bodies for p in INERTIAL]
        legs: tuple[Any, ...] = (1, 2, 3) if self.per_leg else ("",)
        for k in FRICTION_KINDS:
            if k in self.friction:
                out += [f"{k}{i}.{c}" for i in legs for c in ("fv", "fc")]
        return tuple(out)

    @property
    def n(self) -> int:
        return len(self.names)

    @property
    def friction_indices(self) -> np.ndarray:
        return np.arange(10 * len(self.bodies), self.n)

    @property
    def matrix(self) -> np.ndarray:
        S = np.zeros((N_STANDARD, self.n))
        std = {name: k for k, name in enumerate(STANDARD_NAMES)}
        for j, name in enumerate(self.names):
            head, par = name.split(".")
            if name in std:
                S[std[name], j] = 1.0
            else:                      # shared by the three legs
                for i in (1, 2, 3):
                    S[std[f"{head}{i}.{par}"], j] = 1.0
        return S

    def regressor(self, Y: ArrayLike) -> np.ndarray:
        """The layout's regressor from a standard one (..., 82)."""
        return np.asarray(Y, float) @ self.matrix


# ------------------------------------------------------- body parameters

def body_parameters(mass: float, com: ArrayLike = (0.0, 0.0, 0.0),
                    inertia: ArrayLike | None = None) -> np.ndarray:
    """The 10 standard parameters of a body from its mass [kg], centre of
    mass [m] and inertia about the centre of mass [kg m^2] (3x3, or 3
    principal moments along the body's axes), in the body's axes."""
    c = np.asarray(com, float).reshape(3)
    Ic = np.zeros((3, 3)) if inertia is None else np.asarray(inertia, float)
    if Ic.shape == (3,):
        Ic = np.diag(Ic)
    I = Ic + mass * (c @ c * np.eye(3) - np.outer(c, c))   # parallel axes
    return np.array([mass, *(mass * c), I[0, 0], I[0, 1], I[0, 2], I[1, 1],
                     I[1, 2], I[2, 2]])


def inertia_matrix(p10: ArrayLike) -> np.ndarray:
    """The 3x3 inertia about the origin from a body's 10 parameters."""
    p = np.asarray(p10, float)
    return np.array([[p[4], p[5], p[6]], [p[5], p[7], p[8]], [p[6], p[8], p[9]]])


def pseudo_inertia(p10: ArrayLike) -> np.ndarray:
    """The 4x4 pseudo-inertia [[Sigma, h], [h^T, m]] of a body, Sigma =
    tr(I)/2 1 - I the second moment of its mass about the origin: positive
    semidefinite exactly when some mass distribution has these parameters."""
    p = np.asarray(p10, float)
    I = inertia_matrix(p)
    J = np.zeros((4, 4))
    J[:3, :3] = 0.5 * np.trace(I) * np.eye(3) - I
    J[:3, 3] = J[3, :3] = p[1:4]
    J[3, 3] = p[0]
    return J


def standard_parameters(*, R: float = 0.2286, rho: float = 0.5,
                        M: float = 0.18, m: float = 0.09, d: float = 0.1524,
                        link_Ic: float = 0.0,
                        payload: dict[str, Any] | None = None,
                        pin_friction: dict[str, float] | None = None,
                        prismatic_friction: dict[str, float] | None = None
                        ) -> np.ndarray:
    """The 82 standard parameters of the paper's model (rps3.Model's
    arguments of the same names): the platform a uniform disc of radius
    r = rho R (I = diag(1/4, 1/4, 1/2) M r^2) plus a rigid payload (mass,
    com, principal inertia about its centre of mass, platform axes), each
    cylinder a point mass m at d from the pin along the link plus link_Ic
    about the pin direction, massless pistons; pin friction (viscous,
    coulomb) per pin, prismatic friction (viscous, coulomb) per actuator."""
    r = rho * R
    pi = np.zeros(N_STANDARD)
    plat = body_parameters(M, inertia=[M * r**2 / 4, M * r**2 / 4, M * r**2 / 2])
    if payload:
        plat += body_parameters(payload.get("mass", 0.0), payload.get("com", (0, 0, 0)),
                                payload.get("inertia", (0, 0, 0)))
    pi[0:10] = plat
    cyl = body_parameters(m, com=(d, 0.0, 0.0), inertia=[0.0, link_Ic, link_Ic])
    for i in range(3):
        pi[10 + 20 * i:20 + 20 * i] = cyl
    for k, fr in ((0, prismatic_friction), (1, pin_friction)):
        if fr:
            for i in range(3):
                pi[N_BODY_PARAMETERS + 6 * k + 2 * i] = fr.get("viscous", 0.0)
                pi[N_BODY_PARAMETERS + 6 * k + 2 * i + 1] = fr.get("coulomb", 0.0)
    return pi


# -------------------------------------------------------------- utilities

def _stacked(Y: ArrayLike, F: ArrayLike | None = None,
             n_act: int = 3) -> tuple[np.ndarray, np.ndarray | None, np.ndarray]:
    """(N, p) Y, (N,) F and each row's actuator index."""
    Ya = np.asarray(Y, float)
    if Ya.ndim == 3:
        if Ya.shape[1] != n_act:
            raise ValueError(f"Y: expected (n, {n_act}, p), got shape {Ya.shape}")
        act = np.tile(np.arange(Ya.shape[1]), Ya.shape[0])
        Ya = Ya.reshape(-1, Ya.shape[2])
    elif Ya.ndim == 2:
        act = np.arange(Ya.shape[0]) % n_act
    else:
        raise ValueError(f"Y: expected (n, 3, p) or (N, p), got shape {Ya.shape}")
    Fa = None
    if F is not None:
        Fa = np.asarray(F, float).reshape(-1)
        if Fa.shape[0] != Ya.shape[0]:
            raise ValueError(f"F: {Fa.shape[0]} force values for {Ya.shape[0]} "
                             "regressor rows")
        if not np.all(np.isfinite(Fa)):
            raise ValueError("F: holds a non-finite value")
    if not np.all(np.isfinite(Ya)):
        raise ValueError("Y: holds a non-finite value")
    return Ya, Fa, act


def _need(module: str) -> Any:
    """Import an optional dependency, or say which extra brings it."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise ImportError(f"rps3.ident needs {module.split('.')[0]}: "
                          "pip install 'rps3[ident]' (scipy, cvxpy, clarabel)") from exc


def _column_scale(Y: np.ndarray) -> np.ndarray:
    s = np.linalg.norm(Y, axis=0)
    return np.where(s > 0, s, 1.0)


def _r_factor(A: np.ndarray, block: int = 128) -> np.ndarray:
    """The R factor of a tall A's QR (A^T A = R^T R), by a tree of QRs of
    row blocks: the same R as one QR, without the multi-threaded LAPACK
    call that a busy machine slows a hundredfold."""
    R = np.asarray(A, float)
    n = R.shape[1]
    while R.shape[0] > 2 * max(n, block):
        R = np.vstack([np.asarray(np.linalg.qr(R[i:i + block], mode="r"))
                       for i in range(0, R.shape[0], block)])
    return np.asarray(np.linalg.qr(R, mode="r"))


#: rank tolerance of :func:`base_parameters`: a column-scaled regressor's
#: R diagonal below RANK_TOL times its largest is taken as zero
RANK_TOL = 1e-7
#: condition number of the column-scaled base regressor above which data
#: are refused as not exciting (noise 1 % would move a parameter by ~1e4 %)
COND_MAX = 1e6


@dataclass(frozen=True)
class Base:
    """The base parameters of a regressor: the columns kept
    (``independent``, indices into the standard names) and the grouping
    ``K`` (r x p): base = K @ pi, Y @ pi = Y[:, independent] @ base."""

    names: tuple[str, ...]        #: names of Y's columns
    independent: np.ndarray       #: (r,) column indices, in the names' order
    K: np.ndarray                 #: (r, p) grouping matrix
    rdiag: np.ndarray             #: |R_kk| / |R_00| of the pivoted QR
    tol: float                    #: rank tolerance used
    unidentifiable: tuple[str, ...]  #: parameters absent from every base one

    @property
    def rank(self) -> int:
        return len(self.independent)

    @property
    def base_names(self) -> tuple[str, ...]:
        return tuple(self.names[k] for k in self.independent)

    def reduce(self, Y: ArrayLike) -> np.ndarray:
        """The base regressor: Y's independent columns."""
        return np.asarray(Y, float)[..., self.independent]

    def of(self, pi: ArrayLike) -> np.ndarray:
        """The base parameters of standard parameters pi."""
        return self.K @ np.asarray(pi, float)

    def relations(self, digits: int = 6) -> list[tuple[str, str]]:
        """(base name, 'name + c * name + ...') for each base parameter."""
        out = []
        for r, k in enumerate(self.independent):
            terms = [self.names[k]]
            for j in np.flatnonzero(np.abs(self.K[r]) > 1e-9):
                if j == k:
                    continue
                c = self.K[r, j]
                terms.append(f"{'+' if c > 0 else '-'} {abs(c):.{digits}g} "
                             f"{self.names[j]}")
            out.append((self.names[k], " ".join(terms)))
        return out


def base_parameters(Y: ArrayLike, names: tuple[str, ...] | list[str],
                    tol: float = RANK_TOL, order: ArrayLike | None = None) -> Base:
    """Base parameters of a regressor stacked over exciting states.

    The rank comes from a rank-revealing QR (column pivoting,
    scipy.linalg.qr) of Y with unit-norm columns: R_kk below tol * R_00 is
    zero.  The columns kept are then chosen greedily in ``order`` (default
    the names' order): a column is kept when it is not a combination of
    the columns kept before it (relative residual above tol), so a
    dependent parameter regroups into the earlier-listed ones.  The
    grouping coefficients are the least-squares solution
    Y_dep = Y_ind beta; K = [1 beta] in the columns' order.

    Raises:
        ValueError: the greedy selection disagrees with the QR's rank (the
            tolerance falls in no gap of the R diagonal).
    """
    qr = _need("scipy.linalg").qr
    Ya, _, _ = _stacked(Y)
    p = Ya.shape[1]
    if len(names) != p:
        raise ValueError(f"names: {len(names)} names for {p} columns")
    s = np.linalg.norm(Ya, axis=0)
    zero = s <= tol * s.max()
    Ys = Ya / np.where(zero, 1.0, s)
    Ys[:, zero] = 0.0
    Ys = _r_factor(Ys)          # same column geometry: Y^T Y = R^T R
    _, Rm, _ = qr(Ys, mode="economic", pivoting=True)
    rd = np.abs(np.diag(Rm))
    rd = rd / rd[0]
    rank = int(np.sum(rd > tol))
    sel: list[int] = []
    Qb = np.zeros((Ys.shape[0], 0))
    for j in (range(p) if order is None else np.asarray(order, int)):
        if zero[j]:
            continue
        v = Ys[:, j] - Qb @ (Qb.T @ Ys[:, j])
        v = v - Qb @ (Qb.T @ v)                # re-orthogonalised
        nv = np.linalg.norm(v)
        if nv > tol:
            sel.append(int(j))
            Qb = np.column_stack([Qb, v / nv])
    if len(sel) != rank:
        raise ValueError(f"base_parameters: the greedy selection keeps {len(sel)} "
                         f"columns where the pivoted QR finds rank {rank}; "
                         f"tol = {tol:g} is in no gap of the R diagonal")
    ind = np.array(sorted(sel))
    dep = np.setdiff1d(np.arange(p), ind)
    Rs = Ys * np.where(zero, 0.0, s)       # R of the unscaled Y
    beta = np.linalg.lstsq(Rs[:, ind], Rs[:, dep], rcond=None)[0]
    K = np.zeros((len(ind), p))
    K[np.arange(len(ind)), ind] = 1.0
    K[:, dep] = beta
    K[:, zero] = 0.0
    unid = tuple(names[j] for j in range(p) if np.all(np.abs(K[:, j]) < 1e-12))
    return Base(tuple(names), ind, K, rd, tol, unid)


# ------------------------------------------------------------ excitation

def check_excitation(Y: np.ndarray, names: tuple[str, ...],
                     cond_max: float = COND_MAX) -> float:
    """The condition number of Y with unit-norm columns.

    Raises:
        NotExcitingError: it exceeds cond_max.  The message names the
            parameters the data do not determine: the columns that are
            zero, and those with a component of 10 % or more in the span of
            the right singular vectors of the singular values below
            s_max / cond_max (the unexcited directions), and gives those
            directions' leading terms.  ``unidentifiable`` lists the names.
    """
    s = np.linalg.norm(Y, axis=0)
    dead = s <= 1e-300
    live = np.flatnonzero(~dead)
    Ys = Y[:, live] / s[live]
    # the singular values of Y's R factor are Y's (the SVD of the small R
    # costs little where that of the tall Y costs much)
    Rf = _r_factor(Ys) if Ys.shape[0] > Ys.shape[1] else Ys
    sv = np.zeros(0)
    if len(live):
        _, sv, Vt = np.linalg.svd(Rf, full_matrices=False)
    if len(live) and len(sv) < len(live):        # fewer rows than columns
        sv = np.concatenate([sv, np.zeros(len(live) - len(sv))])
    cond = (float(sv[0] / sv[-1]) if len(sv) and sv[-1] > 0 else float("inf"))
    if cond <= cond_max and not dead.any():
        return cond
    weak_k = (np.flatnonzero(sv < sv[0] / cond_max) if len(sv)
              else np.zeros(0, int))
    combos, involved = [], set()
    if len(weak_k):
        _, _, Vfull = np.linalg.svd(Rf, full_matrices=True)
        V = Vfull[weak_k]
        share = np.linalg.norm(V, axis=0)
        involved = {live[j] for j in np.flatnonzero(share >= 0.1)}
        for v in V[:4]:
            top = [j for j in np.argsort(-np.abs(v)) if abs(v[j]) > 0.1 * np.abs(v).max()][:5]
            combos.append(" ".join(f"{v[j] / np.abs(v).max():+.2f} {names[live[j]]}"
                                   for j in top))
    bad = [names[j] for j in range(len(names)) if dead[j] or j in involved]
    n_weak = int(dead.sum()) + len(weak_k)
    msg = (f"the data do not excite {n_weak} of {len(names)} parameter directions "
           f"(condition number {cond:.3g} of the column-scaled regressor, limit "
           f"{cond_max:.3g}); not determined: {', '.join(bad)}")
    if dead.any():
        msg += f" (absent from the data: {', '.join(names[j] for j in np.flatnonzero(dead))})"
    if combos:
        msg += "; unexcited directions: " + "; ".join(combos) + (
            f"; and {len(weak_k) - len(combos)} more" if len(weak_k) > len(combos) else "")
    raise NotExcitingError(msg, cond, bad)


# ------------------------------------------------- physical consistency

#: the consistent fit's names, defined in rps3.ident_consistent
_CONSISTENT = ("BodyReport", "ConsistencyReport", "consistency_report", "ConsistentFit",
               "consistent", "base_consistent", "EIG_TOL", "LMI_REG")


#: the C library's regressor and fits, defined in rps3.ident_c
_C = ("C_PAPER_NAMES", "C_STD_NAMES", "C_STD_UNITS", "paper_params", "std_params",
      "regressor", "regressor_std", "base_c", "wls_c", "CLayout", "layout_of",
      "paper_layout", "CFit", "consistent_c")


#: the estimators, defined in rps3.ident_estimate
_ESTIMATE = ("Estimate", "_corr_cov", "_finish", "_lsq", "_prepare", "_tquant", "iv", "ols", "wls")


#: the zero-phase filter and differentiation, defined in rps3.ident_filter
_FILTER = ("FILTER_ORDER", "zero_phase_filter", "differentiate")


def __getattr__(name: str) -> Any:
    # the consistent fit on first use: rps3.ident_consistent imports this module
    if name in _CONSISTENT:
        from rps3 import ident_consistent
        return getattr(ident_consistent, name)
    if name in _C:
        from rps3 import ident_c
        return getattr(ident_c, name)
    if name in _FILTER:
        from rps3 import ident_filter
        return getattr(ident_filter, name)
    if name in _ESTIMATE:
        from rps3 import ident_estimate
        return getattr(ident_estimate, name)
    raise AttributeError(f"module 'rps3.ident' has no attribute {name!r}")


# ------------------------------------------- data in, parameters out

def load(path: Any) -> Any:
    """A measured motion from a CSV or HDF5 table (rps3.ident_io.load)."""
    from rps3 import ident_io

    return ident_io.load(path)


if __name__ == "__main__":
    import sys

    from rps3 import ident_cli

    sys.exit(ident_cli.main())
