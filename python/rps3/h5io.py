"""Read rps3-run HDF5 files with h5py.

Every function takes an open ``h5py.File`` (open it with
``with h5py.File(path, "r") as f``) and finds axes through the dimension
scales, so that it does not depend on the order in which datasets were
written.  See docs/hdf5.md for the file format.
"""

import numbers
import os

import h5py
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
    ``scene_key`` attribute holds the dotted key (runner/output/out_h5.h)."""
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
    the ``coordinates`` attribute of the per-case ``status`` (written
    whatever ``--fields`` selects)."""
    if "status" not in f:
        return []  # an identification's file: no cases
    coords = text(f["status"].attrs.get("coordinates", ""))
    return [text(f[c].attrs.get("scene_key", c)) for c in coords.split()
            if c != "case_time" and c in f]


def sweep_value(f, key):
    """[case] array of the values of swept key ``key`` (dotted)."""
    return _key_variable(f, key)[()]


def sweep_values(f):
    """{swept key (dotted): [case] array of its values}."""
    return {k: sweep_value(f, k) for k in sweep_keys(f)}


def times(f):
    """[case, time] array of sample times [s] (NaN past a case's end):
    case_time where the cases' time grids differ (the samples' dimension
    is then ``sample``), else ``time`` for every case."""
    if "case_time" in f:
        return f["case_time"][()]
    t = f["time"][()]
    return np.broadcast_to(t, (len(f["case"]), len(t)))


def case_where(f, **values):
    """Index of the one case whose swept keys have the given values.

    Keys are the variable names of the keys (dotted names with '.' written
    as '__', see key_name), e.g. ``case_where(f, manipulator__m_over_M=0.5)``.
    """
    sel = np.ones(len(f["case"]), dtype=bool)
    for name, value in values.items():
        # a variable's name (its dotted key in scene_key), or the dotted key
        # with '.' written '__'
        key = (text(f[name].attrs.get("scene_key", name)) if name in f
               else name.replace("__", "."))
        if key not in sweep_keys(f):
            raise KeyError(f"{key} is not a swept key of {f.filename}")
        col = _key_variable(f, key)[()]
        if col.dtype.kind in "SO":
            if not isinstance(value, str):
                raise TypeError(f"{name}: {key} takes names, got {value!r}")
            sel &= np.array([text(v) for v in col]) == value
        else:
            if not isinstance(value, numbers.Real) or isinstance(value, bool):
                raise TypeError(f"{name}: expected a real number, got {value!r}")
            x = float(value)
            sel &= np.isclose(col, x, rtol=0, atol=1e-12 * max(1.0, abs(x)))
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


# ------------------------------------------------------------- file checks

def check_file(f, path=None):
    """Raise ValueError unless ``f`` is an output file of rps3-run: the root
    attribute ``rps3_version`` (every rps3 program writes it) and the
    datasets ``scene`` and ``status`` (rps3-run's files, inverse dynamics
    and simulation alike; docs/hdf5.md)."""
    path = path or f.filename
    if "rps3_version" not in f.attrs:
        raise ValueError(f"{path}: not an rps3 file: it has no root attribute "
                         "rps3_version (rps3-run writes it; docs/hdf5.md)")
    # an identification's file (content "identification") is over its
    # parameters, not over cases (docs/identification.md)
    # (rps3-run's with its scene, rps3.ident fit's with its input file)
    if text(f.attrs.get("content", "")) == "identification":
        if "theta" not in f or ("scene" not in f and "input_sha256" not in f.attrs):
            raise ValueError(f"{path}: an identification file without its "
                             "theta or scene (or input file)")
        return
    # the samples' dimension: time, or sample where the cases' time grids
    # differ (case_time then holds the seconds)
    missing = [k for k in ("scene", "status", "case") if k not in f]
    # a design study's file (content "design") has poses, not samples
    if ("time" not in f and "sample" not in f
            and text(f.attrs.get("content", "")) != "design"):
        missing.append("time")
    if missing:
        raise ValueError(f"{path}: an rps3 file but not one of rps3-run's "
                         f"(no dataset {', '.join(missing)}): read it with "
                         "h5py or xarray.open_dataset")


def _source_candidates(path, name):
    """The files HDF5 tries, in its order, for a virtual dataset's source
    file ``name`` stored in the file at ``path`` (H5Pset_virtual_prefix):
    the name itself when absolute, then its last component under each
    prefix of HDF5_VDS_PREFIX (``${ORIGIN}`` = the file's directory), under
    the file's directory, relative to the working directory, and under
    the directory of the file's resolved path."""
    origin = os.path.dirname(os.path.abspath(path))
    out = []
    rel = name
    if os.path.isabs(name):
        out.append(name)
        rel = os.path.basename(name)
    for prefix in os.environ.get("HDF5_VDS_PREFIX", "").split(os.pathsep):
        if prefix:
            out.append(os.path.join(prefix.replace("${ORIGIN}", origin), rel))
    out += [os.path.join(origin, rel), rel,
            os.path.join(os.path.dirname(os.path.realpath(path)), rel)]
    return out


def check_sources(f, path=None):
    """Raise unless every source of every virtual dataset of ``f`` (a file
    joined by ``rps3-run merge``) opens and holds its dataset: HDF5 reads a
    missing source as its fill values (NaN, status -1) without an error.

    Raises:
        FileNotFoundError: a part is not found where HDF5 looks for it
            (named, with the places looked at).
        OSError: a part is there but HDF5 cannot open it, or it lacks the
            dataset mapped, or that dataset is smaller than the map.
    """
    path = path or f.filename
    opened = {}
    try:
        for key in f:
            ds = f[key]
            if not isinstance(ds, h5py.Dataset) or not ds.is_virtual:
                continue
            for src in ds.virtual_sources():
                if src.file_name == ".":
                    continue
                if src.file_name not in opened:
                    opened[src.file_name] = _open_source(path, src.file_name, key)
                part, where = opened[src.file_name]
                dset = src.dset_name
                if dset not in part or not isinstance(part[dset], h5py.Dataset):
                    raise OSError(f"{path}: dataset {key} reads {dset} of part "
                                  f"{where}, which has no such dataset")
                shape = part[dset].shape
                _, last = src.src_space.get_select_bounds()
                if len(last) != len(shape) or any(e >= n for e, n in zip(last, shape)):
                    raise OSError(f"{path}: dataset {key} reads {dset} of part "
                                  f"{where} up to index {last}, but its shape "
                                  f"is {shape}")
    finally:
        for part, _ in opened.values():
            part.close()


def _open_source(path, name, key):
    """The part ``name`` opened as HDF5 would find it: (file, its path)."""
    tried = _source_candidates(path, name)
    errors = []
    for cand in tried:
        if not os.path.exists(cand):
            continue
        try:
            return h5py.File(cand, "r"), cand
        except OSError as e:  # as HDF5: the next place
            errors.append(f"{cand}: {e}")
    if errors:
        raise OSError(f"{path}: dataset {key} reads part {name}, which cannot "
                      f"be opened: {'; '.join(errors)}")
    raise FileNotFoundError(
        f"{path}: dataset {key} reads part {name}, which is missing (looked "
        f"for at {', '.join(dict.fromkeys(tried))}): a joined file reads its "
        "parts; put the part back, point HDF5_VDS_PREFIX to its directory, "
        "or join the parts into one file with rps3-run merge --copy "
        "(docs/scale-out.md)")
