"""Measured data in, identified parameters out (docs/identification.md,
"Data in, parameters out"): ``load`` reads a table of link lengths and
forces, ``fit`` identifies the paper model's parameters or a general
layout's; ``write_results`` (rps3.ident_write) and ``manipulator_yaml``
(rps3.ident_scene), re-exported here, write them.
"""

from __future__ import annotations

import hashlib
import os
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rps3 import ident as _id
from rps3 import ident_consistent as _ic
from rps3 import ident_estimate as _ie
from rps3 import ident_filter as _if
from rps3 import ident_paper as _ip

#: the columns of a data table: name -> (units it must be in, the spellings
#: a units attribute may use for them, as the runner's tables)
COLUMNS: dict[str, tuple[str, ...]] = {
    "t": ("s", "second", "seconds"),
    **{f"l{i}": ("m", "meter", "metre", "meters", "metres") for i in (1, 2, 3)},
    **{f"l{i}_dot": ("m/s", "m s-1") for i in (1, 2, 3)},
    **{f"l{i}_ddot": ("m/s^2", "m/s2", "m s-2") for i in (1, 2, 3)},
    **{f"F{i}": ("N", "newton", "newtons") for i in (1, 2, 3)},
}
#: a link length above this in a table is taken for millimetres [m]
LENGTH_MAX = 10.0


class DataError(ValueError):
    """A data table refused: the message names the file, the row and the
    column."""


@dataclass
class Data:
    """A measured motion: times t (n,) [s], link lengths l (n, 3) [m],
    rates dl [m/s] and accelerations ddl [m/s^2] (None when not in the
    file), forces F (n, 3) [N] (None when not in the file), and where the
    rates and accelerations came from."""

    path: str
    t: np.ndarray
    l: np.ndarray
    dl: np.ndarray | None
    ddl: np.ndarray | None
    F: np.ndarray | None
    sha256: str
    source: dict[str, str] = field(default_factory=dict)


def _sha256(path: str) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def _read_csv(path: str) -> tuple[dict[str, np.ndarray], dict[int, int]]:
    """Columns and each row's line number (1-based)."""
    header: list[str] | None = None
    rows: list[list[float]] = []
    lines: list[int] = []
    with open(path, encoding="utf-8-sig") as fh:
        for ln, raw in enumerate(fh, 1):
            s = raw.strip()
            if not s or s.startswith("#"):
                continue
            fields = [x.strip() for x in s.split(",")]
            if header is None:
                header = []
                for x in fields:
                    name, _, unit = x.partition("[")
                    name = name.strip()
                    if name not in COLUMNS:
                        raise DataError(f"{path}:{ln}: column {name!r}: unknown; "
                                        f"known: {', '.join(COLUMNS)}")
                    if name in header:
                        raise DataError(f"{path}:{ln}: column {name}: given twice")
                    u = unit.rstrip("]").strip()
                    if unit and u not in COLUMNS[name]:
                        raise DataError(f"{path}:{ln}: column {name}: units '{u}', but "
                                        f"the table is in {COLUMNS[name][0]}")
                    header.append(name)
                continue
            if len(fields) != len(header):
                raise DataError(f"{path}:{ln}: {len(fields)} fields for "
                                f"{len(header)} columns")
            row = []
            for k, x in enumerate(fields):
                try:
                    row.append(float(x))
                except ValueError:
                    raise DataError(f"{path}:{ln}: column {header[k]}: expected a "
                                    f"number, got {x!r}") from None
            rows.append(row)
            lines.append(ln)
    if header is None:
        raise DataError(f"{path}: no header line naming the columns")
    arr = np.array(rows, float).reshape(len(rows), len(header))
    return {h: arr[:, k] for k, h in enumerate(header)}, {k: ln for k, ln in enumerate(lines)}


def _read_h5(path: str) -> dict[str, np.ndarray]:
    import h5py

    out: dict[str, np.ndarray] = {}
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise DataError(f"{path}: not an HDF5 file ({exc})") from None
    with f:
        for name in f:
            if name not in COLUMNS:
                continue
            ds = f[name]
            if not isinstance(ds, h5py.Dataset) or ds.ndim != 1:
                raise DataError(f"{path}: dataset /{name}: expected a 1-D dataset")
            u = ds.attrs.get("units")
            if u is not None:
                u = u.decode() if isinstance(u, bytes) else str(u)
                if u not in COLUMNS[name]:
                    raise DataError(f"{path}: dataset /{name}: units '{u}', but the "
                                    f"table is in {COLUMNS[name][0]}")
            out[name] = np.asarray(ds[()], float)
    return out


def load(path: str | os.PathLike[str]) -> Data:
    """A measured motion from a CSV or HDF5 (``.h5``, ``.hdf5``) table:
    columns ``t`` [s], ``l1 l2 l3`` [m]; optionally ``l1_dot ...`` [m/s]
    (all three), ``l1_ddot ...`` [m/s^2] (all three, with the rates) and
    ``F1 F2 F3`` [N].  A CSV header may give units in brackets
    (``l1 [m]``), an HDF5 dataset a ``units`` attribute: either must name
    the column's SI unit.

    Raises:
        DataError: naming the file, the row (a CSV line number, or an HDF5
            dataset's index) and the column: an unknown, repeated or
            missing column, a column in other units, a field that is not
            a number, NaN or infinity, times that do not increase
            strictly, columns of different lengths, a length above
            LENGTH_MAX (millimetres?) or not positive, fewer than 4 rows.
    """
    p = os.fspath(path)
    if not os.path.isfile(p):
        raise DataError(f"{p}: no such regular file")
    h5 = p.endswith((".h5", ".hdf5"))
    if h5:
        cols = _read_h5(p)
        lines: dict[int, int] = {}
    else:
        cols, lines = _read_csv(p)

    def where(k: int, col: str) -> str:
        if h5:
            return f"{p}: dataset /{col}, row {k}"
        return f"{p}:{lines.get(k, k)}: column {col}"

    for need in ("t", "l1", "l2", "l3"):
        if need not in cols:
            raise DataError(f"{p}: column {need}: missing (the table needs t, l1, l2, l3)")
    for grp in (("l1_dot", "l2_dot", "l3_dot"), ("l1_ddot", "l2_ddot", "l3_ddot"),
                ("F1", "F2", "F3")):
        have = [c for c in grp if c in cols]
        if have and len(have) != 3:
            miss = [c for c in grp if c not in cols]
            raise DataError(f"{p}: column {miss[0]}: missing ({', '.join(grp)}: "
                            "all three or none)")
    if "l1_ddot" in cols and "l1_dot" not in cols:
        raise DataError(f"{p}: column l1_ddot: accelerations need the rates l1_dot ...")
    n = len(cols["t"])
    for c, v in cols.items():
        if len(v) != n:
            raise DataError(f"{p}: dataset /{c}: {len(v)} rows, /t has {n}")
        bad = np.flatnonzero(~np.isfinite(v))
        if len(bad):
            raise DataError(f"{where(int(bad[0]), c)}: {v[bad[0]]}: not a finite number")
    if n < 4:
        raise DataError(f"{p}: {n} rows; at least 4 are needed")
    t = cols["t"]
    dt = np.diff(t)
    bad = np.flatnonzero(dt <= 0)
    if len(bad):
        k = int(bad[0]) + 1
        raise DataError(f"{where(k, 't')}: {t[k]:g} after {t[k - 1]:g}: times must "
                        "increase strictly")
    for c in ("l1", "l2", "l3"):
        v = cols[c]
        big = np.flatnonzero((v > LENGTH_MAX) | (v <= 0))
        if len(big):
            k = int(big[0])
            raise DataError(f"{where(k, c)}: {v[k]:g} m: a link length must be in "
                            f"(0, {LENGTH_MAX:g}] m (millimetres?)")

    def three(stem: str) -> np.ndarray | None:
        if stem.format(1) not in cols:
            return None
        return np.column_stack([cols[stem.format(i)] for i in (1, 2, 3)])

    lengths = three("l{}")
    assert lengths is not None
    d = Data(p, t, lengths, three("l{}_dot"), three("l{}_ddot"), three("F{}"), _sha256(p))
    d.source = {"rates": "measured" if d.dl is not None else "none",
                "accelerations": "measured" if d.ddl is not None else "none"}
    return d


def save_data(path: str, t: np.ndarray, l: np.ndarray, F: np.ndarray | None = None,
              dl: np.ndarray | None = None, ddl: np.ndarray | None = None) -> None:
    """A data table :func:`load` reads (CSV, or HDF5 by the suffix)."""
    cols: dict[str, np.ndarray] = {"t": np.asarray(t, float)}
    for stem, v in (("l{}", l), ("l{}_dot", dl), ("l{}_ddot", ddl), ("F{}", F)):
        if v is not None:
            for i in (1, 2, 3):
                cols[stem.format(i)] = np.asarray(v, float)[:, i - 1]
    if path.endswith((".h5", ".hdf5")):
        import h5py

        with h5py.File(path, "w") as f:
            f.attrs["Conventions"] = "CF-1.10"
            for c, v in cols.items():
                f.create_dataset(c, data=v).attrs["units"] = COLUMNS[c][0]
        return
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(", ".join(f"{c} [{COLUMNS[c][0]}]" for c in cols) + "\n")
        np.savetxt(fh, np.column_stack(list(cols.values())), delimiter=", ", fmt="%.17g")


# ------------------------------------------------------------------- fit

#: zero-phase filter cut-off used when rates are differentiated [Hz]
CUTOFF = 5.0
#: time dropped at each end of filtered data (the filter's transients),
#: in periods of the cut-off
EDGE_PERIODS = 3.0


@dataclass
class Fit:
    """An identification: the estimate of the base parameters, the set's
    parameters, the consistency and where the states came from.  A fit of
    a general layout (``layout`` given) has no paper set (``pset`` None,
    ``theta`` and ``model_arguments`` None) and holds the consistent fit
    of all the layout's parameters instead."""

    estimate: _ie.Estimate
    pset: _ip.PaperSet | None
    geometry: _ip.Geometry
    base: _id.Base
    theta: np.ndarray | None         #: the set's parameters (base = set: full rank)
    model_arguments: dict[str, Any] | None
    mapping: str                     #: why the fit does not map onto Model's arguments
    consistency: str                 #: the consistency report (text)
    consistent: bool
    source: dict[str, str]
    t: np.ndarray                    #: the times used [s]
    F: np.ndarray                    #: forces used (n, 3) [N]
    Y: np.ndarray                    #: base regressor used (n, 3, r)
    #: the general layout fitted, or None (the paper model)
    layout: _id.Layout | None = None
    #: the consistent fit of the layout's parameters (rps3.ident.consistent_c),
    #: None when it failed (``consistency`` says why) or was not asked for
    consistent_fit: Any = None
    #: the 82 standard parameters of the consistent fit, layout.matrix @ pi
    standard: np.ndarray | None = None
    #: the consistent fit's report per body (rps3.ident.consistency_report)
    report: Any = None


def states(data: Data, geometry: _ip.Geometry, cutoff: float = CUTOFF
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, str]]:
    """(t, pose, dpose, ddpose, source) of the data: missing rates or
    accelerations differentiated from the lengths filtered with the
    cut-off [Hz] (:func:`rps3.ident.differentiate`); the pose by the
    forward kinematics, its rates and accelerations by the Jacobian of
    the lengths: ddpose = J^-1 (ddl - J' dpose)."""
    from rps3 import velocity

    t, l, dl, ddl = data.t, data.l, data.dl, data.ddl
    src = dict(data.source)
    if dl is None or ddl is None:
        h = np.diff(t)
        off = np.flatnonzero(np.abs(h - np.median(h)) > UNIFORM_TOL * np.median(h))
        if len(off):
            k = int(off[0]) + 1
            raise DataError(f"{data.path}: row {k}: column t: step {h[k - 1]:g} s where "
                            f"the table's is {np.median(h):g} s: differentiating the "
                            "lengths needs uniform times (give the rates and "
                            "accelerations, or resample)")
        try:
            lf, dlf, ddlf = _if.differentiate(t, l, cutoff)
        except ValueError as exc:      # too few rows for the filter, a cut-off
            raise DataError(f"{data.path}: differentiating the lengths: {exc}") from None
        how = (f"differentiated: zero-phase Butterworth order {_if.FILTER_ORDER}, "
               f"cut-off {cutoff:g} Hz, central differences")
        if dl is None:
            dl, src["rates"] = dlf, how
        if ddl is None:
            ddl, src["accelerations"] = ddlf, how
        l = lf
    from rps3.errors import Rps3Error

    mdl = geometry.model()
    try:
        mot = velocity.joint_rates(mdl, l, dl)
    except Rps3Error as exc:           # "point I: ...": the row's lengths
        raise DataError(f"{data.path}: row {str(exc).removeprefix('point ')}") from None
    pose, dpose = np.asarray(mot.pose), np.asarray(mot.dpose)
    J = np.asarray(velocity.jacobian(mdl, pose).l)
    bias = np.asarray(velocity.pose_rates(mdl, pose, dpose, np.zeros_like(pose)).ddl)
    ddpose = np.linalg.solve(J, (ddl - bias)[..., None])[..., 0]
    return t, pose, dpose, ddpose, src


#: relative deviation of a time step from the median step beyond which
#: the times are not uniform (differentiation needs uniform samples)
UNIFORM_TOL = 1e-6
#: filtered data are decimated to about DECIMATE_RATIO times the cut-off
#: [Hz], so that the remaining noise is about white
DECIMATE_RATIO = 2.5


def _filtered_noise_corr(keep: np.ndarray, fs: float, cutoff: float) -> np.ndarray:
    """The correlation over the kept samples (indices keep) of unit white
    noise through the zero-phase filter: C[p, q] = (g * g)(keep[p] -
    keep[q]), the autocorrelation of the filter's impulse response g,
    which dies out within a few periods of the cut-off (taken here over
    eight times the ends dropped, EDGE_PERIODS).  Exact away from the
    ends, which fit drops; the memory is that of C alone."""
    m = int(np.ceil(8 * EDGE_PERIODS * fs / cutoff))
    impulse = np.zeros(2 * m + 1)
    impulse[m] = 1.0
    g = _if.zero_phase_filter(impulse, fs, cutoff)
    a = np.correlate(g, g, mode="full")          # lags -2m .. 2m
    lag = keep[:, None] - keep[None, :]
    C = np.zeros(lag.shape)
    inside = np.abs(lag) <= 2 * m
    C[inside] = a[2 * m + lag[inside]]
    return C


def _filtered(t: np.ndarray, F: np.ndarray, Y: np.ndarray, src: dict[str, str],
              cutoff: float) -> tuple[np.ndarray, np.ndarray, np.ndarray,
                                      np.ndarray | None]:
    """(t, F, Y, noise correlation) the estimate uses: as they are for
    measured states; for differentiated ones the forces and the
    regressor's columns filtered alike, the ends dropped, decimated, and
    the filtered noise's correlation over the kept samples (src says so)."""
    if "differentiated" not in src.get("rates", "") + src.get("accelerations", ""):
        return t, F, Y, None
    # parallel filtering: the forces and the regressor's columns with
    # the same filter (Coulomb's steps smoothed alike), the ends'
    # transients dropped, then decimated so the noise is about white
    fs = 1.0 / float(np.mean(np.diff(t)))
    F = _if.zero_phase_filter(F, fs, cutoff)
    Y = _if.zero_phase_filter(Y, fs, cutoff)
    edge = EDGE_PERIODS / cutoff
    step = max(1, int(fs / (DECIMATE_RATIO * cutoff)))
    keep = np.flatnonzero((t >= t[0] + edge) & (t <= t[-1] - edge))[::step]
    # white noise comes out of the filter correlated over its impulse
    # response: the kept samples' correlation enters the estimate's
    # covariance
    corr = _filtered_noise_corr(keep, fs, cutoff)
    src["forces"] = (f"filtered alike, {edge:g} s dropped at each end, "
                     f"every {step}th sample kept")
    src["covariance"] = "the filtered noise's correlation over the kept samples"
    return t[keep], F[keep], Y[keep], corr


def fit(data: Data, *, geometry: _ip.Geometry | None = None,
        pset: _ip.PaperSet | None = None, layout: _id.Layout | None = None,
        M: float = 0.18, method: str = "ols", cutoff: float = CUTOFF,
        cond_max: float = _id.COND_MAX, consistent: bool = True,
        reg: float | None = None) -> Fit:
    """The paper model's parameters (``pset``) or a general layout's
    (``layout``, rps3.ident.Layout; not both) from measured data: states
    (:func:`states`), the regressor from the library
    (rps3.ident_paper.paper_regressor, or the layout's
    rps3.ident_excite.layout_regressor), its structural base parameters,
    ``method`` "ols" or "wls".  The paper set's result is mapped onto
    Model's arguments when it can be (M the given one when a payload is
    identified); a layout's is followed, with ``consistent``, by the
    physically consistent fit of all its parameters
    (rps3.ident.consistent_c, weighted as the estimate: each actuator by
    its inverse WLS variance, or equally for OLS; ``reg`` its
    regularisation, default the library's) and its consistency report.

    Raises:
        DataError: the data have no forces.
        NotExcitingError: the data do not determine the parameters.
        ValueError: both pset and layout, or an unknown method.
    """
    if pset is not None and layout is not None:
        raise ValueError("pset, layout: give one (the paper model's set or a general "
                         "layout), not both")
    if method not in _ESTIMATORS:
        raise ValueError(f"method: expected 'ols' or 'wls', got {method!r}")
    if data.F is None:
        raise DataError(f"{data.path}: column F1: missing (forces are needed to fit)")
    geo = geometry or _ip.Geometry()
    t, q, dq, ddq, src = states(data, geo, cutoff)
    if layout is not None:
        from rps3 import ident_excite as _ix

        Y = _ix.layout_regressor(q, dq, ddq, geo, layout)
        base = _ix.layout_base(geo, layout)
    else:
        ps = pset or _ip.PaperSet()
        Y = _ip.paper_regressor(q, dq, ddq, geo, ps)
        base = _ip.structural_base(geo, ps)
    t, F, Y, corr = _filtered(t, data.F, Y, src, cutoff)
    est = _ESTIMATORS[method](Y, F, base=base, cond_max=cond_max, noise_corr=corr)
    if layout is not None:
        return _general(est, geo, base, layout, src, t, F, Y, consistent, reg)
    theta = None
    args, why, rep, ok = None, "", "", False
    if base.rank == len(ps.names):
        theta = base.K.T @ np.linalg.solve(base.K @ base.K.T, est.theta)
        args, why = _ip.to_model_arguments(theta, ps, d=geo.d, M=M, R=geo.R, rho=geo.rho)
        if args is not None:
            std = _ip.standard_of(theta, ps, d=geo.d, M=M, R=geo.R, rho=geo.rho)
            assert std is not None
            r = _ic.consistency_report(std[0], std[1])
            rep, ok = str(r), r.ok
        else:
            rep = "not physically consistent: " + why
    else:
        why = (f"the data determine {base.rank} combinations of the "
               f"{len(ps.names)} parameters: {', '.join(base.base_names)}")
        rep = "not checked: " + why
    return Fit(est, ps, geo, base, theta, args, why, rep, ok, src, t, F, base.reduce(Y))


_ESTIMATORS = {"ols": _ie.ols, "wls": _ie.wls}


def _general(est: _ie.Estimate, geo: _ip.Geometry, base: _id.Base, layout: _id.Layout,
             src: dict[str, str], t: np.ndarray, F: np.ndarray, Y: np.ndarray,
             consistent: bool, reg: float | None) -> Fit:
    """A general layout's fit: the estimate, then the consistent fit of
    all the layout's parameters with the estimate's weights."""
    from rps3 import ident_c as _c

    if not consistent:
        return Fit(est, None, geo, base, None, None, "", "not checked: no consistent fit "
                   "asked for", False, src, t, F, base.reduce(Y), layout)
    try:
        cf = _consistent(Y, F, est, _c.layout_of(layout), layout.names, reg)
    except _id.InconsistentFitError as exc:
        rep = f"not physically consistent: {exc}"
        return Fit(est, None, geo, base, None, None, str(exc), rep, False, src, t, F,
                   base.reduce(Y), layout)
    report = _ic.consistency_report(cf.pi, layout)
    ok = bool(cf.consistent and report.ok)
    solver = (f"consistent fit: converged in {cf.niter} iterations" if cf.converged
              else f"consistent fit: {cf.message}")
    return Fit(est, None, geo, base, None, None, "" if ok else "not physically consistent",
               f"{report}\n{solver}", ok, src, t, F, base.reduce(Y), layout, cf,
               layout.matrix @ cf.pi, report)


def _consistent(Y: np.ndarray, F: np.ndarray, est: _ie.Estimate, layout: Any,
                names: tuple[str, ...], reg: float | None) -> Any:
    """The physically consistent fit (rps3.ident.consistent_c) of the
    regressor Y's parameters (C layout ``layout``), weighted as the
    estimate: each actuator by its inverse WLS variance, or equally for
    OLS.  A fit short of its optimality test is returned (converged False,
    its message), not warned about per call.

    Raises:
        InconsistentFitError: the fit's eigenvalue check failed.
    """
    import warnings

    from rps3 import ident_c as _c

    weights = 1.0 / est.sigma**2 if est.method == "wls" else None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return _c.consistent_c(Y, F, layout, weights=weights, names=names, reg=reg)


def paper_consistent(result: Fit, reg: float | None = None) -> Any:
    """The physically consistent fit of a paper fit's set (a CFit over
    ``result.pset.names``): rps3.ident.consistent_c with
    rps3.ident.paper_layout of the set's columns (a link about its pin,
    the payload about the platform centre, M and the friction >= 0),
    weighted as the estimate, on the forces and regressor the estimate
    used.  ``fit`` does not run it: the paper set's estimate is its
    parameters, checked by ``consistency``.

    Raises:
        ValueError: a general layout's fit, or a set the data do not
            determine (its base parameters are not the set's).
        InconsistentFitError: the fit's eigenvalue check failed.
    """
    from rps3 import ident_c as _c

    if result.layout is not None or result.pset is None:
        raise ValueError("result: a general layout's fit (its consistent fit is "
                         "result.consistent_fit)")
    names = result.pset.names
    if result.theta is None:
        raise ValueError(f"result: {result.mapping}")
    # base = set: the base regressor is the set's, in its order
    assert np.array_equal(result.base.independent, np.arange(len(names)))
    cols = [_c.C_PAPER_NAMES.index(n) for n in names]
    return _consistent(result.Y, result.F, result.estimate, _c.paper_layout(cols), names, reg)


def predict(result: Fit, data: Data, *, which: str = "consistent",
            cutoff: float = CUTOFF) -> tuple[np.ndarray, np.ndarray]:
    """(t, F) [s], [N] (n, 3): the forces the fit predicts along the
    motion of ``data`` (its forces, if any, unused: a held-out check), at
    every row, from the states of :func:`states` (rates and accelerations
    differentiated with the cut-off [Hz] when the table has none).
    ``which`` "consistent" (a general layout's consistent fit; the paper
    set's estimate, which is its parameters) or "estimate" (the base
    parameters' estimate).

    Raises:
        ValueError: "consistent" for a fit without a consistent fit.
    """
    if which not in ("consistent", "estimate"):
        raise ValueError(f"which: expected 'consistent' or 'estimate', got {which!r}")
    t, q, dq, ddq, _ = states(data, result.geometry, cutoff)
    if result.layout is None:
        Y = _ip.paper_regressor(q, dq, ddq, result.geometry, result.pset)
        return t, result.base.reduce(Y) @ result.estimate.theta
    from rps3 import ident_excite as _ix

    Y = _ix.layout_regressor(q, dq, ddq, result.geometry, result.layout)
    if which == "estimate":
        return t, result.base.reduce(Y) @ result.estimate.theta
    if result.consistent_fit is None:
        raise ValueError("which: the fit has no consistent fit ("
                         f"{result.consistency.splitlines()[0]})")
    return t, Y @ result.consistent_fit.pi


# ------------------------------------------------------- output, forwarded

#: the results file (rps3.ident_write) and the scene's section
#: (rps3.ident_scene), on first use: both import this module
_WRITE = ("layout_units", "parameter_units", "write_results")
_SCENE = ("MASS_REL", "SceneBody", "fitted_model", "manipulator_yaml", "scene_bodies",
          "scene_body")


def __getattr__(name: str) -> Any:
    if name in _WRITE:
        from rps3 import ident_write
        return getattr(ident_write, name)
    if name in _SCENE:
        from rps3 import ident_scene
        return getattr(ident_scene, name)
    raise AttributeError(f"module 'rps3.ident_io' has no attribute {name!r}")
