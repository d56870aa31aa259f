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
    parameters, the consistency and where the states came from."""

    estimate: _ie.Estimate
    pset: _ip.PaperSet
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


def fit(data: Data, *, geometry: _ip.Geometry | None = None,
        pset: _ip.PaperSet | None = None, M: float = 0.18, method: str = "ols",
        cutoff: float = CUTOFF, cond_max: float = _id.COND_MAX) -> Fit:
    """The paper model's parameters (``pset``) from measured data: states
    (:func:`states`), the regressor from the library
    (rps3.ident_paper.paper_regressor), its structural base parameters,
    ``method`` "ols" or "wls"; the result mapped onto Model's arguments
    when it can be (M the given one when a payload is identified).

    Raises:
        DataError: the data have no forces.
        NotExcitingError: the data do not determine the parameters.
    """
    if data.F is None:
        raise DataError(f"{data.path}: column F1: missing (forces are needed to fit)")
    geo = geometry or _ip.Geometry()
    ps = pset or _ip.PaperSet()
    t, q, dq, ddq, src = states(data, geo, cutoff)
    F = data.F
    Y = _ip.paper_regressor(q, dq, ddq, geo, ps)
    if "differentiated" in src.get("rates", "") + src.get("accelerations", ""):
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
        t, F, Y = t[keep], F[keep], Y[keep]
        src["forces"] = (f"filtered alike, {edge:g} s dropped at each end, "
                         f"every {step}th sample kept")
        src["covariance"] = "the filtered noise's correlation over the kept samples"
    else:
        corr = None
    base = _ip.structural_base(geo, ps)
    est = {"ols": _ie.ols, "wls": _ie.wls}[method](Y, F, base=base, cond_max=cond_max,
                                                   noise_corr=corr)
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


# ----------------------------------------------------------------- output

def _version() -> str:
    try:
        from importlib.metadata import version

        return version("rps3")
    except Exception:  # noqa: BLE001 - an uninstalled tree
        return "unknown"


def write_results(path: str, result: Fit, data: Data) -> None:
    """The fit as HDF5 (CF-1.10): ``theta``, ``std``, ``ci95``, ``cov``
    over the ``parameter`` dimension (names in ``parameter``, units per
    parameter in ``parameter_units``), ``sigma`` per actuator, the
    residuals over ``time``; attributes: the consistency report, the
    mapping onto Model's arguments (or why not), where the rates came
    from, the rps3 version and the input file's SHA-256.  Written to a
    temporary name and renamed, so no partial file looks complete."""

    est = result.estimate
    units = [_ip.PAPER_UNITS.get(n, "1") for n in est.names]
    tmp = path + ".part"
    try:
        _write(tmp, result, data, units)
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
        f.attrs["mapping"] = result.mapping or "maps onto the manipulator section"
        for k, v in result.source.items():
            f.attrs[f"{k}_source"] = v
        for gk, gv in (("R", result.geometry.R), ("rho", result.geometry.rho),
                       ("d", result.geometry.d), ("g", result.geometry.g)):
            f.attrs[f"geometry_{gk}"] = gv
        pdim = f.create_dataset("parameter", data=np.array(est.names, dtype=h5py.string_dtype()))
        pdim.make_scale("parameter")
        pdim.attrs["units"] = "1"
        pdim.attrs["long_name"] = "base parameter"
        f.create_dataset("parameter_units", data=np.array(units, dtype=h5py.string_dtype()),
                         ).attrs["units"] = "1"
        bnd = f.create_dataset("bound", data=np.array([0, 1]))
        bnd.attrs["units"] = "1"
        bnd.make_scale("bound")
        act = f.create_dataset("actuator", data=np.array([1, 2, 3]))
        act.attrs["units"] = "1"
        act.make_scale("actuator")
        tt = f.create_dataset("time", data=result.t)
        tt.attrs["units"] = "s"
        tt.make_scale("time")

        def put(name: str, v: Any, unit: str, axes: tuple[Any, ...], long: str) -> None:
            ds = f.create_dataset(name, data=np.asarray(v))
            ds.attrs["units"] = unit
            ds.attrs["long_name"] = long
            for k, ax in enumerate(axes):
                ds.dims[k].attach_scale(ax)

        put("theta", est.theta, "various: see parameter_units", (pdim,), "estimate")
        put("std", est.std, "various: see parameter_units", (pdim,), "standard deviation")
        put("ci95", est.ci95, "various: see parameter_units", (pdim, bnd), "95 % interval")
        put("cov", est.cov, "various: products of parameter_units", (pdim, pdim), "covariance")
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


def manipulator_yaml(result: Fit) -> str:
    """A ``manipulator:`` section with the fitted M, m, d, link_Ic,
    payload, friction (and the geometry's R, rho, g) that a scene can use
    as it is; or, when the fit does not map onto them, a YAML comment
    saying why and no section."""
    a = result.model_arguments
    if a is None:
        return f"# the fit does not map onto the manipulator section: {result.mapping}\n"
    g = result.geometry

    def num(x: float) -> str:
        return repr(float(x))

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
