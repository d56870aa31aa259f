"""Measured data in, identified parameters out (docs/identification.md,
"Data in, parameters out"): ``load`` reads a table of link lengths and
forces, ``fit`` identifies the paper model's parameters, ``write_results``
and ``manipulator_yaml`` write them, ``main`` is the command line
``python -m rps3.ident``.
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


# ----------------------------------------------------------------- output

def _version() -> str:
    try:
        from importlib.metadata import version

        return version("rps3")
    except Exception:  # noqa: BLE001 - an uninstalled tree
        return "unknown"


def layout_units(layout: _id.Layout) -> list[str]:
    """Each layout parameter's units (UDUNITS): those of the standard
    parameters it stands for (rps3.ident.C_STD_UNITS)."""
    from rps3 import ident_c as _c

    S = layout.matrix
    return [_c.C_STD_UNITS[int(np.flatnonzero(S[:, j])[0])] for j in range(layout.n)]


def parameter_units(result: Fit) -> list[str]:
    """The units of each estimated (base) parameter of the fit."""
    if result.layout is None:
        return [_ip.PAPER_UNITS.get(n, "1") for n in result.estimate.names]
    u = layout_units(result.layout)
    return [u[int(j)] for j in result.base.independent]


def write_results(path: str, result: Fit, data: Data) -> None:
    """The fit as HDF5 (CF-1.10, root attribute ``content``
    "identification", which rps3.open_dataset reads over the parameter
    dimension): ``theta``, ``std``, ``ci95``, ``cov`` over the
    ``parameter`` dimension (names in ``parameter``, units per parameter
    in ``parameter_units``), ``sigma`` per actuator, the residuals over
    ``time``; attributes: the consistency report, the mapping onto Model's
    arguments (or why not), where the rates came from, the rps3 version
    and the input file's SHA-256.  A general layout's fit adds the
    grouping (``base_matrix``, ``relation``), the layout
    (``layout_matrix``) and the consistent fit (``consistent_theta`` over
    ``layout_parameter``, ``consistent_standard`` over
    ``standard_parameter``, ``consistent_eigenvalues`` per body,
    ``consistent``, ``consistent_status``).  Written to a temporary name
    and renamed, so no partial file looks complete."""

    tmp = path + ".part"
    try:
        _write(tmp, result, data, parameter_units(result))
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise
    os.replace(tmp, path)


def _write(tmp: str, result: Fit, data: Data, units: list[str]) -> None:
    import h5py

    est = result.estimate
    with h5py.File(tmp, "w") as f:
        f.attrs["Conventions"] = "CF-1.10"
        f.attrs["title"] = "rps3 identified parameters"
        f.attrs["content"] = "identification"
        f.attrs["source"] = f"rps3 {_version()} rps3.ident fit"
        f.attrs["input_file"] = os.path.basename(data.path)
        f.attrs["input_sha256"] = data.sha256
        f.attrs["rps3_version"] = _version()
        f.attrs["method"] = est.method
        f.attrs["covariance"] = est.cov_kind
        f.attrs["condition_number"] = est.cond
        f.attrs["dof"] = est.dof
        f.attrs["consistency_report"] = result.consistency
        f.attrs["consistent"] = int(result.consistent)
        f.attrs["maps_onto_model"] = int(result.model_arguments is not None)
        f.attrs["mapping"] = (result.mapping or "maps onto the manipulator section"
                              if result.layout is None else
                              "general bodies: manipulator_yaml writes them"
                              if result.consistent else
                              "general bodies: " + (result.mapping or "no consistent fit"))
        for k, v in result.source.items():
            f.attrs[f"{k}_source"] = v
        for gk, gv in (("R", result.geometry.R), ("rho", result.geometry.rho),
                       ("d", result.geometry.d), ("g", result.geometry.g),
                       ("vreg", result.geometry.vreg),
                       ("vreg_prismatic", result.geometry.vreg_of("prismatic"))):
            f.attrs[f"geometry_{gk}"] = gv

        def scale(name: str, values: Any, long: str) -> Any:
            data = np.asarray(values)
            if data.dtype.kind in "US":
                data = np.array([str(v) for v in values], dtype=h5py.string_dtype())
            ds = f.create_dataset(name, data=data)
            ds.make_scale(name)
            ds.attrs["units"] = "1"
            ds.attrs["long_name"] = long
            return ds

        def put(name: str, v: Any, unit: str, axes: tuple[Any, ...], long: str) -> Any:
            data = np.asarray(v)
            if data.dtype.kind in "US":
                data = np.array([str(x) for x in np.ravel(v)], dtype=h5py.string_dtype())
            ds = f.create_dataset(name, data=data)
            ds.attrs["units"] = unit
            ds.attrs["long_name"] = long
            for k, ax in enumerate(axes):
                ds.dims[k].attach_scale(ax)
            return ds

        pdim = scale("parameter", est.names, "base parameter")
        # CF: a variable's dimensions differ, so cov's columns have their own
        pcol = scale("parameter_column", est.names, "base parameter of the covariance's column")
        put("parameter_units", units, "1", (pdim,), "units of the base parameter")
        bnd = scale("bound", [0, 1], "bound of the interval (0 lower, 1 upper)")
        act = scale("actuator", [1, 2, 3], "actuator number")
        tt = f.create_dataset("time", data=result.t)
        # the table's t [s]; CF's time units name a reference date: a
        # nominal one, as rps3-run's files (docs/hdf5.md)
        tt.attrs["units"] = "s since 1970-01-01 00:00:00"
        tt.attrs["calendar"] = "proleptic_gregorian"
        tt.attrs["standard_name"] = "time"
        tt.attrs["axis"] = "T"
        tt.attrs["long_name"] = "the data table's t, in s (nominal reference date)"
        tt.make_scale("time")

        put("theta", est.theta, "various: see parameter_units", (pdim,), "estimate")
        put("std", est.std, "various: see parameter_units", (pdim,), "standard deviation")
        put("ci95", est.ci95, "various: see parameter_units", (pdim, bnd), "95 % interval")
        put("cov", est.cov, "various: products of parameter_units", (pdim, pcol), "covariance")
        put("sigma", est.sigma, "N", (act,), "noise standard deviation per actuator")
        put("residual", est.residual.reshape(-1, 3), "N", (tt, act), "F - Y theta")
        put("force", result.F, "N", (tt, act), "forces fitted")
        # each parameter also alone, in its own units (CF readers that
        # take one unit per variable)
        g = f.create_group("parameters")
        for j, (n, u) in enumerate(zip(est.names, units)):
            ds = g.create_dataset(n, data=est.theta[j])
            ds.attrs["units"] = u
            ds.attrs["std"] = est.std[j]
            ds.attrs["ci95"] = est.ci95[j]
        if result.layout is not None:
            _write_general(f, result, scale, put, pdim)


def _write_general(f: Any, result: Fit, scale: Any, put: Any, pdim: Any) -> None:
    """A general layout's grouping, layout and consistent fit."""
    from rps3 import ident_c as _c
    from rps3._rps3 import lib

    lay = result.layout
    assert lay is not None
    lunits = layout_units(lay)
    f.attrs["layout_legs"] = lay.legs
    f.attrs["layout_friction"] = ",".join(lay.friction) or "none"
    f.attrs["layout_friction_per_leg"] = int(lay.per_leg)
    ldim = scale("layout_parameter", lay.names, "the layout's parameter (rps3.ident.Layout)")
    sdim = scale("standard_parameter", _id.STANDARD_NAMES,
                 "standard parameter (rps3.ident.STANDARD_NAMES)")
    put("layout_parameter_units", lunits, "1", (ldim,), "units of the layout's parameter")
    put("standard_parameter_units", _c.C_STD_UNITS, "1", (sdim,),
        "units of the standard parameter")
    put("base_matrix", result.base.K, "various: parameter_units / layout_parameter_units",
        (pdim, ldim), "grouping K: base parameters = K layout parameters")
    put("relation", [f"{n} = {r}" for n, r in result.base.relations()], "1", (pdim,),
        "the base parameter's grouping of layout parameters")
    put("layout_matrix", lay.matrix, "1", (sdim, ldim),
        "standard parameters = layout_matrix layout parameters")
    cf = result.consistent_fit
    if cf is None:
        return
    put("consistent_theta", cf.pi, "various: see layout_parameter_units", (ldim,),
        "physically consistent estimate of the layout's parameters")
    put("consistent_standard", result.standard, "various: see standard_parameter_units",
        (sdim,), "the consistent fit's standard parameters")
    body = scale("body", lay.bodies, "body of the layout")
    eig = scale("eigenvalue", [1, 2, 3, 4], "pseudo-inertia eigenvalue number, ascending")
    e = put("consistent_eigenvalues", np.array([b.eig for b in result.report.bodies]),
            "kg m^2", (body, eig), "each body's pseudo-inertia eigenvalues, ascending "
            "(kg for its mass direction)")
    e.attrs["message"] = cf.message or "converged"
    put("consistent", np.int32(result.consistent), "1", (),
        "1: the consistent fit's eigenvalues and friction signs checked")
    st = put("consistent_status", np.int32(lib.RPS3_OK if cf.converged else lib.RPS3_ENOCONV),
             "1", (), "status of the consistent fit (rps3_status, 0: converged)")
    st.attrs["message"] = cf.message or f"converged in {cf.niter} iterations"
    put("consistent_residual_rms", float(np.sqrt(np.mean(cf.residual**2))), "N", (),
        "RMS of F - Y pi of the consistent fit")


def manipulator_yaml(result: Fit) -> str:
    """A ``manipulator:`` section with the fitted M, m, d, link_Ic,
    payload, friction (and the geometry's R, rho, g) that a scene can use
    as it is; or, when the fit does not map onto them, a YAML comment
    saying why and no section.  A general layout's fit: the general
    bodies of its consistent fit (:func:`scene_bodies`)."""
    if result.layout is not None:
        return _general_yaml(result)
    a = result.model_arguments
    if a is None:
        return f"# the fit does not map onto the manipulator section: {result.mapping}\n"
    g = result.geometry

    num = _num
    lines = ["# identified by rps3.ident (docs/identification.md)", "manipulator:",
             f"  R: {num(g.R)}", f"  rho: {num(g.rho)}", f"  M: {num(a['M'])}",
             f"  m: {num(a['m'])}", f"  d: {num(a['d'])}", f"  link_Ic: {num(a['link_Ic'])}",
             f"  g: {num(g.g)}"]
    if "payload" in a:
        p = a["payload"]
        lines += ["  payload:", f"    mass: {num(p['mass'])}",
                  f"    com: [{', '.join(num(x) for x in p['com'])}]",
                  f"    inertia: [{', '.join(num(x) for x in p['inertia'])}]"]
    if "friction" in a:
        fr = a["friction"]
        lines += ["  pin_friction:", f"    viscous: {num(fr['viscous'])}",
                  f"    coulomb: {num(fr['coulomb'])}"]
        if result.geometry.vreg > 0:
            lines.append(f"    vreg: {num(result.geometry.vreg)}")
    return "\n".join(lines) + "\n"


def _num(x: float) -> str:
    """A float as YAML reads it back exactly (repr), with a decimal point
    in the mantissa (YAML 1.1 readers take 1e-05 for a string)."""
    r = repr(float(x))
    if "e" in r and "." not in r:
        m, _, e = r.partition("e")
        r = f"{m}.0e{e}"
    return r


#: a body's mass at or below this fraction of its pseudo-inertia's largest
#: eigenvalue is written massless: its centre of mass, first moment over
#: mass, is then rounding over rounding
MASS_REL = 1e-12


@dataclass(frozen=True)
class SceneBody:
    """A body as a scene's ``manipulator:`` section gives it: mass [kg],
    com [m] (3,), inertia [Ixx, Ixy, Ixz, Iyy, Iyz, Izz] about the com
    [kg m^2] (6,); ``moved``: how far its standard parameters are from
    those it was made from, relative to its pseudo-inertia's largest
    eigenvalue (the projection onto a real body's, see
    :func:`scene_body`)."""

    mass: float
    com: np.ndarray
    inertia: np.ndarray
    moved: float


def scene_body(p10: Any) -> SceneBody:
    """The body of ten standard parameters (m, m c, inertia about the
    frame's origin) in a scene's terms, made acceptable to the library's
    check (rps3_model_init: the second moment about the centre of mass,
    Sigma_c = tr(I_c)/2 1 - I_c, positive semidefinite to 1e-12 of its
    trace).  A consistent fit's pseudo-inertia is positive semidefinite
    only to its eigenvalue tolerance, and its bodies often lie on the
    cone's boundary (a point mass or a rod: Sigma_c singular), where the
    parallel-axis theorem's cancellation, m |c|^2 against I_o, leaves
    Sigma_c's zero eigenvalues a rounding below zero: they are set to
    zero (Sigma_c's eigenvalues clipped at 0) and ``moved`` says by how
    much the standard parameters changed.  A mass <= 0, or at most
    MASS_REL of the pseudo-inertia's scale, is written as a massless body
    (com [0, 0, 0], the inertia about the origin)."""
    p = np.asarray(p10, float)
    J = _id.pseudo_inertia(p)
    big = max(float(np.abs(np.linalg.eigvalsh(J)).max()), 1e-300)
    Io = _id.inertia_matrix(p)
    if p[0] <= MASS_REL * big:
        mass, c, Ic = 0.0, np.zeros(3), Io
    else:
        mass = float(p[0])
        c = p[1:4] / mass
        Ic = Io - mass * (c @ c * np.eye(3) - np.outer(c, c))
    Sig = 0.5 * np.trace(Ic) * np.eye(3) - Ic
    w, V = np.linalg.eigh(0.5 * (Sig + Sig.T))
    Sig = (V * np.clip(w, 0.0, None)) @ V.T
    Ic = np.trace(Sig) * np.eye(3) - Sig
    six = np.array([Ic[0, 0], Ic[0, 1], Ic[0, 2], Ic[1, 1], Ic[1, 2], Ic[2, 2]])
    back = _id.body_parameters(mass, c, Ic)
    return SceneBody(mass, c, six, float(np.abs(back - p).max() / big))


def scene_bodies(result: Fit) -> dict[str, SceneBody]:
    """The layout's bodies (rps3.ident.Layout.bodies' names) of a general
    fit's consistent fit, as :func:`scene_body` writes them."""
    if result.layout is None or result.consistent_fit is None:
        raise ValueError("result: not a general layout's fit with a consistent fit")
    pi = result.consistent_fit.pi
    return {b: scene_body(pi[10 * k:10 * k + 10])
            for k, b in enumerate(result.layout.bodies)}


def _friction(result: Fit) -> dict[str, list[tuple[float, float]]]:
    """Per friction kind of the layout, (viscous, coulomb) per leg."""
    lay = result.layout
    assert lay is not None and result.standard is not None
    std = result.standard
    out = {}
    for k, kind in enumerate(_id.FRICTION_KINDS):
        if kind in lay.friction:
            j = _id.N_BODY_PARAMETERS + 6 * k
            # >= 0 columns of the fit: a square, exact; clipped anyway
            out[kind] = [(max(float(std[j + 2 * i]), 0.0), max(float(std[j + 2 * i + 1]), 0.0))
                         for i in range(3)]
    return out


def fitted_model(result: Fit, **kw: Any) -> Any:
    """An rps3.Model of the general fit's consistent bodies and friction
    as :func:`manipulator_yaml` writes them (the geometry's R, rho, g, the
    friction laws' vreg), the effects of the layout (the paper's four and
    its friction kinds) unless ``effects`` is given; kw passed on."""
    from rps3.body import Body
    from rps3.model import DEFAULT_EFFECTS, Model

    bodies = scene_bodies(result)
    lay = result.layout
    assert lay is not None
    B = {k: Body(b.mass, b.com, b.inertia) for k, b in bodies.items()}
    if lay.legs == "each":
        bd: dict[str, Any] = dict(platform=B["platform"], legs=[
            dict(cylinder=B[f"cylinder{i}"], piston=B[f"piston{i}"]) for i in (1, 2, 3)])
    else:
        bd = dict(platform=B["platform"], cylinder=B["cylinder"], piston=B["piston"])
    geo = result.geometry
    fr = {kind: [dict(viscous=v, coulomb=c, vreg=geo.vreg_of(kind)) for v, c in laws]
          for kind, laws in _friction(result).items()}
    effects = kw.pop("effects", [*DEFAULT_EFFECTS, *(f"{k}_friction" for k in fr)])
    return Model(R=geo.R, rho=geo.rho, g=geo.g, bodies=bd, friction=fr.get("pin"),
                 prismatic_friction=fr.get("prismatic"), effects=effects, **kw)


def _general_yaml(result: Fit) -> str:
    lay = result.layout
    assert lay is not None
    if result.consistent_fit is None or not result.consistent:
        why = result.consistency.splitlines()[0] if result.consistency else "no consistent fit"
        return f"# the fit has no physically consistent bodies to write: {why}\n"
    bodies = scene_bodies(result)
    geo = result.geometry
    fr = _friction(result)
    num = _num

    def vec(v: Any) -> str:
        return "[" + ", ".join(num(x) for x in v) + "]"

    def body(name: str, b: SceneBody, ind: str) -> list[str]:
        return [f"{ind}{name}: {{mass: {num(b.mass)}, com: {vec(b.com)}, "
                f"inertia: {vec(b.inertia)}}}"]

    def friction(kind: str, law: tuple[float, float], ind: str) -> list[str]:
        return [f"{ind}{kind}_friction: {{viscous: {num(law[0])}, coulomb: {num(law[1])}, "
                f"vreg: {num(geo.vreg_of(kind))}}}"]

    moved = max(b.moved for b in bodies.values())
    lines = ["# identified by rps3.ident (docs/identification.md): general bodies of the",
             f"# consistent fit of the layout legs={lay.legs}, friction="
             f"{','.join(lay.friction) or 'none'}; inertia about each body's centre of",
             "# mass; the bodies rounded onto real ones moved the standard parameters by",
             f"# at most {moved:.2g} of a body's pseudo-inertia scale"]
    if not result.consistent_fit.converged:
        lines.append("# warning: the consistent fit stopped short of its optimality test "
                     "(consistent, maybe not optimal): "
                     + " ".join(result.consistent_fit.message.split()))
    lines += ["manipulator:", f"  R: {num(geo.R)}", f"  rho: {num(geo.rho)}",
             f"  g: {num(geo.g)}", "  bodies: general"]
    lines += body("platform", bodies["platform"], "  ")
    shared = [k for k in fr if not lay.per_leg]
    if lay.legs == "identical" or shared:
        lines.append("  legs:")
        if lay.legs == "identical":
            lines += body("cylinder", bodies["cylinder"], "    ")
            lines += body("piston", bodies["piston"], "    ")
        for k in shared:
            lines += friction(k, fr[k][0], "    ")
    for i in (1, 2, 3):
        own = [k for k in fr if lay.per_leg]
        if lay.legs == "each" or own:
            lines.append(f"  leg{i}:")
        if lay.legs == "each":
            lines += body("cylinder", bodies[f"cylinder{i}"], "    ")
            lines += body("piston", bodies[f"piston{i}"], "    ")
        for k in own:
            lines += friction(k, fr[k][i - 1], "    ")
    text = "\n".join(lines) + "\n"
    # the library's own check, which the runner runs (rps3_model_init), on
    # the very numbers written (repr reads back exactly)
    try:
        fitted_model(result)
    except ValueError as exc:       # not expected: scene_body projects onto it
        return f"# the fitted bodies are refused by the library: {exc}\n"
    return text
