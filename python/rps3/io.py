"""rps3-run's HDF5 files as xarray Datasets (docs/hdf5.md)."""

from __future__ import annotations

import itertools
import os
from typing import Any

import numpy as np
import xarray as xr


def _short_names(keys: list[str]) -> dict[str, str]:
    """Swept dotted keys -> their last component (``manipulator.m_over_M``
    -> ``m_over_M``), keeping the dotted name where two would collide."""
    short = [k.rsplit(".", 1)[-1] for k in keys]
    return {k: s if short.count(s) == 1 else k for k, s in zip(keys, short)}


def _is_product(values: list[np.ndarray]) -> bool:
    """Whether the cases are each combination of the keys' values once."""
    uniques = [np.unique(v) for v in values]
    if int(np.prod([u.size for u in uniques])) != values[0].size:
        return False
    seen = set(zip(*(v.tolist() for v in values)))
    return seen == set(itertools.product(*(u.tolist() for u in uniques)))


def open_dataset(path: str | os.PathLike[str], **kwargs: Any) -> xr.Dataset:
    """Open an rps3-run output file as an ``xarray.Dataset``.

    Swept keys become coordinates named by their last component
    (``m_over_M``, ``rho``, ``amp[2]``; the dotted key where two would
    collide).  When the sweep is a Cartesian product of its keys (as
    rps3-run's sweeps are), the ``case`` dimension is replaced by one
    dimension per swept key, so that
    ``ds.force.sel(m_over_M=0.5, rho=0.3)`` picks one case by value
    (values are those of the file: use ``method="nearest"`` for values
    from ranges), and ``case_index`` keeps each case's number.  Units are
    the ``units`` attributes of the file (SI); ``time`` is in seconds since
    the start of the trajectory (``decode_times=False`` by default: its
    CF units name a nominal reference date).

    Args:
        path: an HDF5 file written by rps3-run.
        **kwargs: passed to ``xarray.open_dataset`` (engine h5netcdf).

    Returns:
        The dataset; variables as in docs/hdf5.md (``force`` [N],
        ``force_by_effect`` [N], ``length`` [m], ``lambda`` [N/m], ...).
    """
    kwargs.setdefault("engine", "h5netcdf")
    # time stays in seconds: its units name a nominal reference date (CF,
    # docs/hdf5.md) that xarray would otherwise decode into dates
    kwargs.setdefault("decode_times", False)
    ds = xr.open_dataset(path, **kwargs)
    coords = str(ds["force"].attrs.get("coordinates", "")) if "force" in ds else ""
    if not coords and "force" in ds:
        coords = str(ds["force"].encoding.get("coordinates", ""))
    keys = [k for k in coords.split() if k != "case_time" and k in ds.variables]
    if not keys:
        return ds
    # the variables have CF names (trajectory__amp_2), scene_key the key
    dotted = {k: str(ds[k].attrs.get("scene_key", k)) for k in keys}
    short = _short_names(list(dotted.values()))
    names = {k: short[dotted[k]] for k in keys}
    ds = ds.rename({k: v for k, v in names.items() if k != v})
    dims = [names[k] for k in keys]
    ds = ds.assign_coords(case_index=("case", np.arange(ds.sizes["case"])))
    values = [np.asarray(ds[d].values) for d in dims]
    if not _is_product(values):
        return ds
    if len(dims) == 1:
        # one key: its values index the cases (set_index would make a
        # plain index, which unstack refuses)
        return ds.drop_vars("case", errors="ignore").swap_dims({"case": dims[0]})
    ds = ds.drop_vars("case", errors="ignore").set_index(case=dims)
    # the swept dimensions where case was: first, in the file's key order
    return ds.unstack("case").transpose(*dims, ...)
