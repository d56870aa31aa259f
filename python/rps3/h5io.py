"""Read rps3-run HDF5 files with h5py.

Every function takes an open ``h5py.File`` (open it with
``with h5py.File(path, "r") as f``) and finds axes through the dimension
scales, so that it does not depend on the order in which datasets were
written.  See docs/hdf5.md for the file format.
"""

import numpy as np

# effects whose shares are the weight of the bodies, and their inertia
GRAVITY_EFFECTS = ("platform_gravity", "link_gravity")
INERTIA_EFFECTS = ("platform_inertia", "link_inertia")


def text(value):
    """A string read from HDF5 (bytes or str) as str."""
    return value.decode() if isinstance(value, bytes) else str(value)


def dims(ds):
    """Names of the dimensions of dataset ``ds``, from its dimension scales."""
    names = []
    for axis in ds.dims:
        if len(axis) == 0:
            raise ValueError(f"{ds.name}: an axis has no dimension scale")
        names.append(axis[0].name.rsplit("/", 1)[-1])
    return tuple(names)


def effects(f):
    """Effect names along the ``effect`` axis of force_by_effect."""
    return [text(n) for n in f["force_by_effect"].dims[2][0][()]]


def key_name(key):
    """The variable name of a swept scene key in a file: CF names are made
    of letters, digits and underscores, so '.' is written '__' and '[k]'
    '_k' (``trajectory.amp[2]`` -> ``trajectory__amp_2``); the variable's
    ``scene_key`` attribute holds the dotted key (runner/out_cf.h)."""
    return key.replace(".", "__").replace("[", "_").replace("]", "")


def _key_variable(f, key):
    """The variable of swept key ``key`` (dotted, or already a variable
    name); a file written before the CF names has the dotted name."""
    for name in (key_name(key), key):
        if name in f:
            return f[name]
    raise KeyError(f"{key} is not a swept key of {f.filename}")


def sweep_keys(f):
    """Swept keys (dotted, as in the scene) in file order: the variables of
    the ``coordinates`` attribute of ``force`` (or of ``status``)."""
    ds = f["force"] if "force" in f else f["status"]
    coords = text(ds.attrs.get("coordinates", ""))
    return [text(f[c].attrs.get("scene_key", c)) for c in coords.split()
            if c != "case_time"]


def sweep_value(f, key):
    """[case] array of the values of swept key ``key`` (dotted)."""
    return _key_variable(f, key)[()]


def sweep_values(f):
    """{swept key (dotted): [case] array of its values}."""
    return {k: sweep_value(f, k) for k in sweep_keys(f)}


def times(f):
    """[case, time] array of sample times [s] (NaN past a case's end)."""
    ncase, nt = f["force"].shape[:2]
    if "case_time" in f:
        return f["case_time"][()]
    t = f["force"].dims[1][0][()]
    return np.broadcast_to(t, (ncase, nt))


def case_where(f, **values):
    """Index of the one case whose swept keys have the given values.

    Keys are the variable names of the keys (dotted names with '.' written
    as '__', see key_name), e.g. ``case_where(f, manipulator__m_over_M=0.5)``.
    """
    sel = np.ones(f["status"].shape[0], dtype=bool)
    for name, value in values.items():
        col = _key_variable(f, name.replace("__", ".") if name not in f
                            else name)[()]
        if col.dtype.kind in "SO":
            sel &= np.array([text(v) for v in col]) == value
        else:
            sel &= np.isclose(col, value, rtol=0, atol=1e-12 * max(1, abs(value)))
    idx = np.flatnonzero(sel)
    if len(idx) != 1:
        raise LookupError(f"{values}: {len(idx)} matching cases in {f.filename}")
    return int(idx[0])


def effect_sum(f, names, case=slice(None)):
    """Sum of the shares of the named effects present, [case, time, link]."""
    fe = f["force_by_effect"][case]
    have = effects(f)
    out = np.zeros(fe.shape[:-2] + fe.shape[-1:])
    for n in names:
        if n in have:
            out += fe[..., have.index(n), :]
    return out


def failed(f):
    """Indices of failed cases and their messages."""
    status = f["status"][()]
    msgs = f["message"][()]
    return [(int(c), int(status[c]), text(msgs[c])) for c in np.flatnonzero(status)]
