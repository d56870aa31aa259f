"""Helpers shared by the modules of the package: arrays to and from the
library's component-major layout, and validation messages."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rps3._rps3 import ffi, lib

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int32]


def text(cdata: Any) -> str:
    """A C string (char * or char[]) as str."""
    return ffi.string(cdata).decode()


def points(x: ArrayLike, name: str) -> tuple[FloatArray, bool]:
    """An (n, 3) or (3,) array of float64 as the library's component-major
    (3, n) contiguous array; the flag says the input was one point.  The
    array itself, transposed, when it already is float64 in that layout
    (Fortran-ordered (n, 3), as the package's own results and trajectories
    are); a copy otherwise (C-ordered or strided input, other dtypes)."""
    raw = np.asarray(x)
    if raw.dtype.kind not in "biuf":
        # numpy would drop an imaginary part with a warning, or fail
        # without naming the argument
        raise TypeError(f"{name}: expected real numbers, got dtype {raw.dtype}")
    a = raw.astype(np.float64, copy=False)
    single = a.ndim == 1
    if single:
        a = a[np.newaxis, :]
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{name}: expected shape (n, 3) or (3,), got "
                         f"{np.shape(x)}")
    return np.ascontiguousarray(a.T), single


def results(n: int, shapes: dict[str, tuple[int, ...]],
            counters: tuple[str, ...]) -> dict[str, np.ndarray]:
    """The output arrays of a batch call over n points, component-major
    (shape + (n,)), allocated once: the float64 fields `shapes` as views of
    one (rows, n) block, the int32 fields `counters` as rows of one (k, n)
    block.  Each view is C-contiguous, for the library to fill in place."""
    rows = [int(np.prod(shape)) for shape in shapes.values()]
    block = np.empty((sum(rows), n))
    ints = np.empty((len(counters), n), np.int32)
    out: dict[str, np.ndarray] = {}
    r = 0
    for (name, shape), k in zip(shapes.items(), rows):
        out[name] = block[r:r + k].reshape(shape + (n,))
        r += k
    for i, name in enumerate(counters):
        out[name] = ints[i]
    return out


def per_point(a: np.ndarray, single: bool) -> Any:
    """A component-major (..., 3, n) or (n,) output as (n, ..., 3) or (n,)
    (a view), or one point's value when the input was one point."""
    if a.ndim >= 2:
        a = np.moveaxis(a, -1, 0)
    return a[0] if single else a


def buf(a: np.ndarray | None, ctype: str = "double[]") -> Any:
    """a's (contiguous) data for the library, NULL for None."""
    if a is None:
        return ffi.NULL
    return ffi.from_buffer(ctype, a)


def field_name(field: int) -> str:
    """Dotted name of a library field id, as in its messages."""
    row = lib.rps3_field(field)
    return text(row.name) if row != ffi.NULL else "?"


def check_error(chk: Any, keyword: dict[str, str]) -> ValueError:
    """A ValueError naming the keyword argument behind a failed rps3_check:
    `keyword` maps the library's dotted names to the caller's names."""
    name = field_name(chk.field) if chk.field >= 0 else ""
    arg = keyword.get(name, name.rsplit(".", 1)[-1])
    return ValueError(f"{arg}: {text(chk.msg)}")


def strerror(status: int) -> str:
    """Short description of an rps3 status code (0 = success)."""
    return text(lib.rps3_strerror(int(status)))
