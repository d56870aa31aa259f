"""Helpers shared by the modules of the package: arrays to and from the
library's component-major layout, and validation messages."""

from __future__ import annotations

import numbers
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rps3._rps3 import ffi, lib

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int32]


def text(cdata: Any) -> str:
    """A C string (char * or char[]) as str."""
    return ffi.string(cdata).decode()


# numpy kinds whose values are real numbers as float64 takes them: signed
# and unsigned integers and floats.  Complex numbers (the imaginary part
# would be dropped), strings (parsed silently by float64), booleans, dates
# and Python objects are refused by name instead of being converted.
_REAL_KINDS = "iuf"
_KIND_NAMES = {"c": "complex numbers", "b": "booleans", "U": "strings",
               "S": "byte strings", "O": "Python objects", "M": "dates",
               "m": "time spans", "V": "records"}


def real_array(x: ArrayLike, name: str) -> FloatArray:
    """x as a float64 array, for an argument `name` that takes real numbers.

    Raises:
        TypeError: naming the argument, for complex, string, boolean or
            object values (a complex pose would lose its imaginary part, a
            string would be parsed), or a masked array with masked values.
        ValueError: naming the argument, for ragged nested sequences.
    """
    if isinstance(x, (str, bytes)):
        raise TypeError(f"{name}: expected real numbers, got a string {x!r}")
    if np.ma.is_masked(x):
        raise TypeError(f"{name}: a masked array with masked values: fill "
                        "them or leave those points out")
    try:
        a = np.asarray(x)
    except (ValueError, TypeError) as e:  # ragged lists
        raise ValueError(f"{name}: not an array of numbers: {e}") from None
    if a.dtype.kind not in _REAL_KINDS:
        what = _KIND_NAMES.get(a.dtype.kind, "not real numbers")
        raise TypeError(f"{name}: expected real numbers, got an array of "
                        f"{a.dtype} ({what})")
    return a.astype(np.float64, copy=False)


def real_number(value: Any, name: str) -> float:
    """One real number as float, for an argument `name` (a Python or numpy
    number, or a 0-d array).  Booleans are taken as 0 and 1 (the library's
    flags are integers).

    Raises:
        TypeError: naming the argument, for complex numbers, strings and
            other objects (never converted: float() would drop an imaginary
            part or parse a string).
        ValueError: naming the argument, for an array of more than one
            value.
    """
    if isinstance(value, (bool, np.bool_)):
        return float(value)
    if isinstance(value, numbers.Real):
        return float(value)  # int, float, Fraction, numpy integers and floats
    if isinstance(value, (str, bytes)):
        raise TypeError(f"{name}: expected a number, got a string {value!r}")
    if isinstance(value, np.ndarray) and value.ndim == 0:
        return float(real_array(value, name))
    if isinstance(value, (np.ndarray, list, tuple)):
        raise ValueError(f"{name}: expected one number, got {value!r}")
    raise TypeError(f"{name}: expected a real number, got {value!r} "
                    f"({type(value).__name__})")


def points(x: ArrayLike, name: str) -> tuple[FloatArray, bool]:
    """An (n, 3) or (3,) array of float64 as the library's component-major
    (3, n) contiguous array; the flag says the input was one point.  The
    array itself, transposed, when it already is float64 in that layout
    (Fortran-ordered (n, 3), as the package's own results and trajectories
    are); a copy otherwise (C-ordered or strided input, other dtypes)."""
    a = real_array(x, name)
    single = a.ndim == 1
    if single:
        a = a[np.newaxis, :]
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{name}: expected shape (n, 3) or (3,), got "
                         f"{np.shape(x)}")
    return np.ascontiguousarray(a.T), single


def motion_points(pose: ArrayLike, dpose: ArrayLike | None,
                  ddpose: ArrayLike | None
                  ) -> tuple[FloatArray, bool, dict[str, FloatArray]]:
    """pose as :func:`points`, with the rates given (dpose, ddpose; None
    leaves one out) in the same layout, keyed by name.

    Raises:
        ValueError: a shape is wrong, or a rate's differs from the pose's.
    """
    p, single = points(pose, "pose")
    given: dict[str, FloatArray] = {}
    for name, value in (("dpose", dpose), ("ddpose", ddpose)):
        if value is None:
            continue
        v, _ = points(value, name)
        if v.shape != p.shape:
            raise ValueError(f"{name}: shape {np.shape(value)} differs from "
                             f"that of pose {np.shape(pose)}")
        given[name] = v
    return p, single, given


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
    """Short description of an rps3 status code (0 = success).

    Raises:
        TypeError: status is not an integer.
    """
    if isinstance(status, np.ndarray) and status.ndim == 0:
        status = status[()]
    if not isinstance(status, numbers.Integral) or isinstance(status, (bool, np.bool_)):
        raise TypeError(f"status: expected an integer status code, got {status!r}")
    return text(lib.rps3_strerror(int(status)))
