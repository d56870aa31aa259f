"""rps3-run's HDF5 files as xarray Datasets (docs/hdf5.md)."""

from __future__ import annotations

import itertools
import os
import warnings
from typing import TYPE_CHECKING, Any

import h5py
import numpy as np

from rps3 import h5io

if TYPE_CHECKING:  # xarray is imported by open_dataset alone
    import xarray as xr


def _short_names(keys: list[str], taken: set[str]) -> dict[str, str]:
    """Swept dotted keys -> their last component (``manipulator.m_over_M``
    -> ``m_over_M``), keeping the dotted name where two would collide or
    where the short name is already a variable or dimension of the file
    (``solver.theta`` and the dataset ``theta``)."""
    short = [k.rsplit(".", 1)[-1] for k in keys]
    return {k: s if short.count(s) == 1 and s not in taken else k
            for k, s in zip(keys, short)}


def _is_product(values: list[np.ndarray]) -> bool:
    """Whether the cases are each combination of the keys' values once."""
    uniques = [np.unique(v) for v in values]
    if int(np.prod([u.size for u in uniques])) != values[0].size:
        return False
    seen = set(zip(*(v.tolist() for v in values)))
    return seen == set(itertools.product(*(u.tolist() for u in uniques)))


def _check(path: str) -> list[str]:
    """The swept keys of an rps3-run file, after checking that it is one
    and that every part a joined file reads is there."""
    try:
        f = h5py.File(path, "r")
    except FileNotFoundError:
        raise
    except OSError as e:
        if os.path.isfile(path) and not h5py.is_hdf5(path):
            raise ValueError(f"{path}: not an HDF5 file (rps3-run writes "
                             "HDF5: docs/hdf5.md)") from None
        raise OSError(f"{path}: cannot be opened: {e}") from e
    with f:
        h5io.check_file(f, path)
        h5io.check_sources(f, path)
        if "shard" in f.attrs:
            warnings.warn(
                f"{path}: part {h5io.text(f.attrs['shard'])} of a sharded run: "
                "the other shards' cases are not computed (status -1000); "
                "join the parts with rps3-run merge", stacklevel=3)
        return h5io.sweep_keys(f)


def open_dataset(path: str | os.PathLike[str], **kwargs: Any) -> xr.Dataset:
    """Open an rps3-run output file as an ``xarray.Dataset``.

    Swept keys become coordinates named by their last component
    (``m_over_M``, ``rho``, ``amp[2]``; the dotted key where two would
    collide or where a variable of the file has that name, as
    ``solver.theta`` and ``theta``).  When the sweep is a Cartesian
    product of its keys (as rps3-run's sweeps are), the ``case``
    dimension is replaced by one dimension per swept key, in the file's
    key order, each sorted by value, so that
    ``ds.force.sel(m_over_M=0.5, rho=0.3)`` picks one case by value
    (values are those of the file: use ``method="nearest"`` for values
    from ranges), and ``case_index`` keeps each case's number.  A file
    without a sweep keeps ``case``.  Files of simulated scenes open the
    same way; an identification's file (a scene with an ``identify``
    section) opens over its ``parameter`` dimension.  Units are the
    ``units`` attributes of the file (SI);
    ``time`` is in seconds since the start of the trajectory
    (``decode_times=False`` by default: its CF units name a nominal
    reference date).

    Args:
        path: an HDF5 file written by rps3-run (or joined by
            ``rps3-run merge``).
        **kwargs: passed to ``xarray.open_dataset`` (engine h5netcdf).

    Returns:
        The dataset; variables as in docs/hdf5.md (``force`` [N],
        ``force_by_effect`` [N], ``length`` [m], ``lambda`` [N/m], ...).

    Raises:
        FileNotFoundError: the file is missing, or a part a joined file
            reads is (named; HDF5 alone would read its cases as NaN).
        ValueError: the file is not HDF5, or not an rps3-run file.
        OSError: a part of a joined file cannot be opened or lacks a
            dataset.
    """
    import xarray as xr

    path = os.fspath(path)
    keys = _check(path)
    kwargs.setdefault("engine", "h5netcdf")
    # time stays in seconds: its units name a nominal reference date (CF,
    # docs/hdf5.md) that xarray would otherwise decode into dates
    kwargs.setdefault("decode_times", False)
    ds = xr.open_dataset(path, **kwargs)
    # the variables have CF names (trajectory__amp_2; a file written before
    # them, the dotted key): the dotted keys name the coordinates
    var = {k: h5io.key_name(k) if h5io.key_name(k) in ds.variables else k
           for k in keys}
    keys = [k for k in keys if var[k] in ds.variables]
    if not keys:
        return ds
    names = _short_names(keys, {str(n) for n in (*ds.variables, *ds.dims)})
    ds = ds.rename({var[k]: names[k] for k in keys if var[k] != names[k]})
    dims = [names[k] for k in keys]
    ds = ds.assign_coords(case_index=("case", np.arange(ds.sizes["case"])))
    values = [np.asarray(ds[d].values) for d in dims]
    if not _is_product(values):
        return ds
    ds = ds.drop_vars("case", errors="ignore")
    if len(dims) == 1:
        # one key: its values are distinct (a product of one); as unstack
        # does for several keys, the dimension is sorted by value
        ds = ds.swap_dims(case=dims[0]).sortby(dims[0])
    else:
        ds = ds.set_index(case=dims).unstack("case")
    # the swept dimensions where case was: first, in the file's key order
    return ds.transpose(*dims, ...)
