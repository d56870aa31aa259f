"""The identification's results file (docs/identification.md, "Data in,
parameters out"): ``write_results`` writes a :class:`rps3.ident_io.Fit`
as HDF5 (CF-1.10).  rps3.ident_io re-exports its public names."""

from __future__ import annotations

import os
from typing import Any

import numpy as np

from rps3 import ident as _id
from rps3 import ident_paper as _ip
from rps3.ident_io import Data, Fit


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
