"""The library's C identification (include/rps3.h, "identification";
docs/identification.md, "The C library's regressor and fits"): the paper
model's regressor of a Model, the general model's regressor of its 82
standard parameters, weighted least squares and the physically
consistent fit (Cholesky factors, then a barrier stage), numpy in and
out.  rps3.ident re-exports every public name.

    Y = rps3.ident.regressor(model, pose, dpose, ddpose)   # (n, 3, 12)
    Ys = rps3.ident.regressor_std(model, pose, dpose, ddpose)  # (n, 3, 82)
    est = rps3.ident.wls_c(Y[..., cols], F)                # an Estimate
    fit = rps3.ident.consistent_c(Y[..., cols], F, rps3.ident.paper_layout(cols))
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from rps3._core import buf, motion_points, text
from rps3._rps3 import ffi, lib
from rps3.ident import Base, InconsistentFitError, Layout, NotExcitingError, _stacked
from rps3.ident_estimate import Estimate
from rps3.model import Model

#: the C regressor's columns, in its order (rps3_paper_name; the names of
#: rps3.ident_paper.PAPER_NAMES)
C_PAPER_NAMES: tuple[str, ...] = tuple(text(lib.rps3_paper_name(k))
                                       for k in range(lib.RPS3_NPAPER))


def paper_params(model: Model) -> np.ndarray:
    """The model's paper parameters pi (12,), F = Y pi (rps3_paper_params).

    Raises:
        ValueError: the model's payload has its centre of mass off the
            platform axes (products of inertia the parameters do not hold).
    """
    pi = np.empty(lib.RPS3_NPAPER)
    err = ffi.new("rps3_check *")
    status = lib.rps3_paper_params(model._c, buf(pi), err)
    if status != lib.RPS3_OK:
        raise ValueError(f"model: {text(err.msg)}")
    return pi


#: the general model's standard parameters, in the C regressor's order
#: (rps3_std_name; the names of rps3.ident.STANDARD_NAMES)
C_STD_NAMES: tuple[str, ...] = tuple(text(lib.rps3_std_name(k))
                                     for k in range(lib.RPS3_NSTD))
#: their units (rps3_std_unit, UDUNITS)
C_STD_UNITS: tuple[str, ...] = tuple(text(lib.rps3_std_unit(k))
                                     for k in range(lib.RPS3_NSTD))


def std_params(model: Model) -> np.ndarray:
    """The model's 82 standard parameters pi, F = Y pi for Y of
    :func:`regressor_std` (rps3_std_params): its general bodies', or the
    paper's bodies as general ones (the disc, point-mass links, massless
    pistons), a selected payload added to the platform's, the prismatic
    and pin friction coefficients."""
    pi = np.empty(lib.RPS3_NSTD)
    status = lib.rps3_std_params(model._c, buf(pi))
    if status != lib.RPS3_OK:          # an initialised Model never fails
        raise ValueError(f"model: rps3_std_params failed with status {status}")
    return pi


def regressor(model: Model, pose: ArrayLike, dpose: ArrayLike | None = None,
              ddpose: ArrayLike | None = None) -> np.ndarray:
    """The C regressor (rps3_regressor_batch) of the model at the poses,
    rates and accelerations (n, 3) or (3,): Y (n, 3, 12) [N per unit
    parameter] with F = Y pi for F of ``model.inverse`` and pi of
    :func:`paper_params`; columns of effects the model does not select are
    zero.

    Raises:
        ValueError: a shape is wrong, rates are needed and missing, or a
            point fails (its index and the library's message).
    """
    return _batch(lib.rps3_regressor_batch, lib.RPS3_NPAPER, model, pose, dpose, ddpose)


def regressor_std(model: Model, pose: ArrayLike, dpose: ArrayLike | None = None,
                  ddpose: ArrayLike | None = None) -> np.ndarray:
    """The C regressor of the general model's standard parameters
    (rps3_regressor_std_batch) at the poses, rates and accelerations
    (n, 3) or (3,): Y (n, 3, 82) [N per unit parameter, the order of
    :data:`rps3.ident.STANDARD_NAMES`] with F = Y pi for F of
    ``model.inverse`` and pi of :func:`std_params`, whatever the model's
    bodies; the model's geometry, method (Lagrange or Newton-Euler), theta
    route and friction laws' vreg; columns of effects the model does not
    select are zero.  ``Layout.regressor(Y)`` gives a layout's columns.

    Raises:
        ValueError: a shape is wrong, rates are needed and missing, or a
            point fails (its index and the library's message).
    """
    return _batch(lib.rps3_regressor_std_batch, lib.RPS3_NSTD, model, pose, dpose, ddpose)


def _batch(fn: Any, ncol: int, model: Model, pose: ArrayLike, dpose: ArrayLike | None,
           ddpose: ArrayLike | None) -> np.ndarray:
    p, single, given = motion_points(pose, dpose, ddpose)
    n = p.shape[1]
    keep: list[Any] = []
    cin = ffi.new("rps3_batch_in *")
    cin.n = n
    keep.append(buf(p))
    cin.pose = keep[-1]
    for name, v in given.items():
        keep.append(buf(v))
        setattr(cin, name, keep[-1])
    needs = model._c.opt.effects & lib.RPS3_EFF_DYNAMIC
    if needs and n > 0 and (dpose is None or ddpose is None):
        raise ValueError(f"{'dpose' if dpose is None else 'ddpose'}: needed by the "
                         f"effects {list(model.effects)}, and not given")
    Y = np.empty((3 * ncol, n))
    status = np.empty(n, np.int32)
    cout = ffi.new("rps3_batch_out *")
    cout.status = ffi.from_buffer("int[]", status)
    d = model._workspace()
    rc = fn(model._c, d, cin, buf(Y), cout)
    if rc != lib.RPS3_OK:
        raise ValueError(text(d.err.msg))
    if cout.nfail:
        raise ValueError(f"pose: {text(d.err.msg)} (status {int(status[cout.first_fail])})")
    out = np.moveaxis(Y.reshape(3, ncol, n), -1, 0)
    return out[0] if single else out


def _opts(rank_tol: float | None = None, level: float | None = None, **kw: Any) -> Any:
    o = ffi.new("rps3_ident_opts *")
    lib.rps3_ident_opts_default(o)
    if rank_tol is not None:
        o.rank_tol = rank_tol
    if level is not None:
        o.level = level
    for k, v in kw.items():
        if v is not None:
            setattr(o, k, v)
    return o


def _data(Y: ArrayLike, F: ArrayLike, weights: ArrayLike | None,
          names: tuple[str, ...] | None) -> tuple[Any, list[Any], np.ndarray,
                                                 np.ndarray, np.ndarray, tuple[str, ...]]:
    Ya, Fa, act = _stacked(Y, F)
    assert Fa is not None
    Ya = np.ascontiguousarray(Ya)
    Fa = np.ascontiguousarray(Fa)
    nm = tuple(names) if names is not None else tuple(f"p{k}" for k in range(Ya.shape[1]))
    if len(nm) != Ya.shape[1]:
        raise ValueError(f"names: {len(nm)} names for {Ya.shape[1]} columns")
    dt = ffi.new("rps3_ident_data *")
    dt.n, dt.p = Ya.shape
    acta = np.ascontiguousarray(act, np.int32)
    keep: list[Any] = [buf(Ya), buf(Fa), ffi.from_buffer("int[]", acta)]
    dt.Y, dt.F, dt.actuator = keep
    if weights is not None:
        wa = np.asarray(weights, float).reshape(-1)
        if wa.size == 3:
            wa = wa[act]
        if wa.size != Ya.shape[0]:
            raise ValueError(f"weights: expected 3 (per actuator) or {Ya.shape[0]} "
                             "(per row) values")
        wa = np.ascontiguousarray(wa)
        keep.append(buf(wa))
        dt.weight = keep[-1]
    cnames = [ffi.new("char[]", s.encode()) for s in nm]
    arr = ffi.new("char *[]", cnames)
    keep += [cnames, arr]
    dt.names = arr
    return dt, keep, Ya, Fa, act, nm


def base_c(Y: ArrayLike, names: tuple[str, ...] | list[str] | None = None,
           tol: float = 1e-7) -> Base:
    """The base parameters of a stacked regressor by the library
    (rps3_ident_base): Y (n, 3, p) or (N, p); names default to the
    standard ones for 82 columns.  The same choice as
    ``rps3.ident.base_parameters`` (columns kept greedily in their order,
    grouping by least squares); ``rdiag`` is empty (the library checks the
    rank by the singular values instead).

    Raises:
        NotExcitingError: the rank is ambiguous at tol or Y is all zero.
        ValueError: bad arguments (Y not finite, named).
    """
    Ya = np.ascontiguousarray(_stacked(Y)[0], float)
    n, p = Ya.shape
    if names is None:
        if p != len(C_STD_NAMES):
            raise ValueError(f"names: needed for {p} columns")
        names = C_STD_NAMES
    if len(names) != p:
        raise ValueError(f"names: {len(names)} names for {p} columns")
    ind = np.zeros(p, np.intc)
    K = np.zeros((p, p))
    nb = ffi.new("int *")
    chk = ffi.new("rps3_check *")
    st = lib.rps3_ident_base(buf(Ya), n, p, tol, buf(ind, "int[]"), buf(K), nb, chk)
    msg = text(chk.msg)
    if st == lib.RPS3_ESING:
        raise NotExcitingError(msg, float("inf"), [])
    if st != lib.RPS3_OK:
        raise ValueError(msg)
    r = int(nb[0])
    Kr = K.reshape(-1)[:r * p].reshape(r, p).copy()
    unid = tuple(names[j] for j in range(p) if np.all(np.abs(Kr[:, j]) < 1e-12))
    return Base(tuple(names), ind[:r].astype(int), Kr, np.zeros(0), tol, unid)


def wls_c(Y: ArrayLike, F: ArrayLike, *, weights: ArrayLike | None = None,
          names: tuple[str, ...] | None = None, rank_tol: float | None = None,
          level: float = 0.95) -> Estimate:
    """Weighted least squares in C (rps3_ident_wls): with ``weights`` None,
    two passes weighting each actuator by its residual variance (as
    :func:`rps3.ident.wls`); weights are inverse variances [1/N^2], per row
    or per actuator (3,).  Y (n, 3, p) with F (n, 3), or (N, p) with F
    (N,).  Returns an :class:`Estimate` (method "wls_c", ci95 at ``level``).

    Raises:
        NotExcitingError: the column-scaled regressor is rank deficient
            (rank_tol, default 1e-10); ``unidentifiable`` names the columns.
        ValueError: bad arguments (the library's message).
    """
    dt, keep, Ya, Fa, act, nm = _data(Y, F, weights, names)
    p = Ya.shape[1]
    theta, cov, ci = np.empty(p), np.empty((p, p)), np.empty((p, 2))
    flags = np.zeros(p, np.int32)
    res = ffi.new("rps3_ident_result *")
    res.theta, res.cov, res.ci = buf(theta), buf(cov), buf(ci)
    res.unident = ffi.from_buffer("int[]", flags)
    err = ffi.new("rps3_check *")
    status = lib.rps3_ident_wls(dt, _opts(rank_tol, level), res, err)
    del keep
    if status == lib.RPS3_ESING:
        raise NotExcitingError(text(err.msg), float(res.cond),
                               [nm[j] for j in np.flatnonzero(flags)])
    if status != lib.RPS3_OK:
        raise ValueError(text(err.msg))
    return Estimate(theta, nm, cov, ci, np.array(list(res.sigma)), Fa - Ya @ theta,
                    float(res.cond), int(res.dof), "wls_c")


@dataclass(frozen=True)
class CLayout:
    """rps3_ident_layout: col (nbody, 10), the column of each body's
    standard parameter (m, mcx, mcy, mcz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz) or
    -1; kind (p,), 0 free or 1 >= 0 for the columns of no body."""

    col: np.ndarray
    kind: np.ndarray


def layout_of(layout: Layout) -> CLayout:
    """The C layout of an rps3.ident Layout: its bodies' 10 columns each in
    order, its friction coefficients >= 0."""
    nb = len(layout.bodies)
    col = np.arange(10 * nb, dtype=np.int32).reshape(nb, 10)
    kind = np.zeros(layout.n, np.int32)
    kind[layout.friction_indices] = 1
    return CLayout(col, kind)


def paper_layout(columns: ArrayLike | None = None) -> CLayout:
    """rps3_ident_paper_layout (a link about its pin, the payload about the
    platform centre; M and the friction >= 0), restricted to the paper
    parameters ``columns`` (indices into C_PAPER_NAMES, default all) and
    renumbered to them."""
    pl = lib.rps3_ident_paper_layout()
    cols = np.arange(lib.RPS3_NPAPER) if columns is None else np.asarray(columns, int)
    where = {int(c): k for k, c in enumerate(cols)}
    col = np.array([[where.get(int(pl.col[b][k]), -1) if pl.col[b][k] >= 0 else -1
                     for k in range(10)] for b in range(pl.nbody)], np.int32)
    kind = np.array([pl.kind[int(c)] for c in cols], np.int32)
    return CLayout(col, kind)


@dataclass(frozen=True)
class CFit:
    """The result of :func:`consistent_c`."""

    pi: np.ndarray            #: fitted parameters, (p,)
    names: tuple[str, ...]
    body: np.ndarray          #: each body's 10 standard parameters, (nbody, 10)
    eig: np.ndarray           #: each body's pseudo-inertia eigenvalues, (nbody, 4)
    converged: bool           #: the optimality test met (gap <= opt_tol cost)
    consistent: bool          #: the eigenvalues (and >= 0 columns) checked
    niter: int
    rss: float                #: weighted residual sum of squares [N^2]
    cost: float               #: the objective minimised
    message: str              #: the library's message when not converged
    residual: np.ndarray      #: F - Y pi [N]
    gap: float = float("nan")  #: optimality measure: how far cost may be above the optimum


def consistent_c(Y: ArrayLike, F: ArrayLike, layout: CLayout | Layout, *,
                 weights: ArrayLike | None = None, names: tuple[str, ...] | None = None,
                 reg: float | None = None, max_iter: int | None = None,
                 xtol: float | None = None, gtol: float | None = None,
                 opt_tol: float | None = None) -> CFit:
    """The physically consistent fit in C (rps3_ident_consistent): the
    objective of :func:`rps3.ident.consistent` (reg its LMI_REG), every
    body's pseudo-inertia by its Cholesky factor (log-Cholesky, then
    plain) solved by GSL's trust-region least squares, then where needed
    the convex problem by the barrier method (Newton, exact Hessian), to
    the optimality test (gap <= opt_tol cost).  weights: inverse variances [1/N^2] per
    row or per actuator (3,) (rps3.ident.consistent's are their square
    roots).  A fit that stops short of convergence is returned with
    converged False (and a RuntimeWarning); its parameters are checked.

    Raises:
        InconsistentFitError: the eigenvalue check failed.
        ValueError: bad arguments or layout (the library's message).
    """
    lay = layout_of(layout) if isinstance(layout, Layout) else layout
    dt, keep, Ya, Fa, act, nm = _data(Y, F, weights, names)
    p = Ya.shape[1]
    col = np.ascontiguousarray(lay.col, np.int32)
    kind = np.ascontiguousarray(lay.kind, np.int32)
    if col.ndim != 2 or col.shape[1] != 10 or kind.shape != (p,):
        raise ValueError(f"layout: col must be (nbody, 10) and kind ({p},)")
    cl = ffi.new("rps3_ident_layout *")
    cl.nbody = col.shape[0]
    keep += [ffi.from_buffer("int[]", col), ffi.from_buffer("int[]", kind)]
    cl.col = ffi.cast("const int (*)[10]", keep[-2])
    cl.kind = keep[-1]
    nb = col.shape[0]
    theta, body, eig = np.empty(p), np.empty((max(nb, 1), 10)), np.empty((max(nb, 1), 4))
    fit = ffi.new("rps3_ident_fit *")
    fit.theta, fit.body, fit.eig = buf(theta), buf(body), buf(eig)
    err = ffi.new("rps3_check *")
    o = _opts(reg=reg, max_iter=max_iter, xtol=xtol, gtol=gtol, opt_tol=opt_tol)
    status = lib.rps3_ident_consistent(dt, cl, o, fit, err)
    del keep
    msg = text(err.msg)
    if status == lib.RPS3_ENOCONV and not fit.consistent:
        raise InconsistentFitError(f"consistent_c: {msg}")
    if status not in (lib.RPS3_OK, lib.RPS3_ENOCONV):
        raise ValueError(msg)
    if status != lib.RPS3_OK:
        import warnings

        warnings.warn(f"consistent_c: {msg}", RuntimeWarning, stacklevel=2)
    return CFit(theta, nm, body[:nb], eig[:nb], status == lib.RPS3_OK, bool(fit.consistent),
                int(fit.niter), float(fit.rss), float(fit.cost), msg, Fa - Ya @ theta,
                float(fit.gap))
