"""Exceptions for the library's status codes, and the checks of the
arguments of the package's newer entry points (dynamics, velocity, sim,
control).

Every status code of the library (enum rps3_status, include/rps3.h) has
one exception class, a subclass of :class:`Rps3Error`; each carries the
code (``status``) and the library's message (``str(exc)``).  Caller
errors (``RPS3_EINVAL``) are also ``ValueError``\\ s.  Arguments are
checked before the library sees them: a wrong shape, a non-finite value
or a non-real (complex, object, string) array raises ``ValueError`` or
``TypeError`` naming the argument.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from rps3 import _core
from rps3._core import FloatArray, text
from rps3._rps3 import lib


class Rps3Error(RuntimeError):
    """A status of the library other than RPS3_OK.

    Attributes:
        status: the library's status code (``rps3.strerror(status)``).
    """

    status: int = 0

    def __init__(self, message: str, status: int | None = None) -> None:
        super().__init__(message)
        if status is not None:
            self.status = int(status)


class ReachError(Rps3Error):
    """RPS3_EREACH: pose unreachable (a link length <= 0, or a ball joint not
    above the base plane), or a link left its stroke in a simulation."""

    status = lib.RPS3_EREACH


class NoConvergenceError(Rps3Error):
    """RPS3_ENOCONV: the theta solve or the integrator did not converge."""

    status = lib.RPS3_ENOCONV


class BranchError(Rps3Error):
    """RPS3_EBRANCH: the theta solve converged outside (0, pi), or to a
    root no pose describes (a simulation that crosses into another
    assembly mode stops with RPS3_ESING: SingularError)."""

    status = lib.RPS3_EBRANCH


class SingularError(Rps3Error):
    """RPS3_ESING: a singular configuration (condition number, force
    transmission or mass matrix beyond the model's limits; in a
    simulation, also the singular surface crossed or reached)."""

    status = lib.RPS3_ESING


class DomainError(Rps3Error):
    """RPS3_EDOMAIN: a trajectory evaluated outside its time span."""

    status = lib.RPS3_EDOMAIN


class ResultRangeError(Rps3Error):
    """RPS3_ERANGE: finite inputs whose result overflowed."""

    status = lib.RPS3_ERANGE


class ModeError(Rps3Error):
    """RPS3_EMODE: the theta solve converged to another assembly mode."""

    status = lib.RPS3_EMODE


class EmptyWorkspaceError(Rps3Error):
    """RPS3_EEMPTY: no pose of the set a design is evaluated on is
    reachable (rps3.design reports it as ``empty``, never raises it)."""

    status = lib.RPS3_EEMPTY


class InvalidError(Rps3Error, ValueError):
    """RPS3_EINVAL: an argument the library rejected."""

    status = lib.RPS3_EINVAL


class StateError(Rps3Error):
    """RPS3_ESTATE: a stage called before the stage it reads from."""

    status = lib.RPS3_ESTATE


class ConvergenceWarning(RuntimeWarning):
    """An optimiser of rps3.design stopped without meeting its tolerances,
    or returned a design that breaks a constraint: the result says which
    (``converged``, ``feasible``, ``status``)."""


_CLASSES: dict[int, type[Rps3Error]] = {
    c.status: c for c in (ReachError, NoConvergenceError, BranchError,
                          SingularError, DomainError, ResultRangeError,
                          ModeError, EmptyWorkspaceError, InvalidError,
                          StateError)}


def error(status: int, message: str) -> Exception:
    """The exception of a status code with the library's message
    (MemoryError for RPS3_ENOMEM, Rps3Error for a code the package does
    not know)."""
    status = int(status)
    if status == lib.RPS3_ENOMEM:
        return MemoryError(message)
    cls = _CLASSES.get(status, Rps3Error)
    return cls(message, status)


def check(status: int, message: Any = None) -> None:
    """Raise the exception of a status other than RPS3_OK.  message: a str,
    a C string (char[]) or None (the code's description)."""
    if int(status) == lib.RPS3_OK:
        return
    if message is None:
        msg = text(lib.rps3_strerror(int(status)))
    elif isinstance(message, str):
        msg = message
    else:
        msg = text(message)
    raise error(status, msg or text(lib.rps3_strerror(int(status))))


# ------------------------------------------------------------------ arguments

def real_array(x: ArrayLike, name: str, *, finite: bool = True) -> FloatArray:
    """x as a float64 array (the package's one check of real numbers,
    rps3._core.real_array: TypeError naming the argument for complex,
    strings, objects); ValueError when finite and a value is NaN or
    infinite."""
    a = _core.real_array(x, name)
    if finite and a.size and not np.isfinite(a).all():
        bad = np.argwhere(~np.isfinite(a))[0]
        where = f" at index {tuple(int(i) for i in bad)}" if a.ndim else ""
        raise ValueError(f"{name}: non-finite value {a[tuple(bad)]!r}{where}")
    return a


def real_number(x: Any, name: str, *, lo: float | None = None,
                lo_open: bool = False, finite: bool = True) -> float:
    """x as a float: TypeError when not a real number, ValueError when
    non-finite (finite) or below lo (or at it, lo_open)."""
    if isinstance(x, (bool, np.bool_)) or not isinstance(
            x, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name}: expected a real number, got {x!r}")
    v = float(x)
    if finite and not np.isfinite(v):
        raise ValueError(f"{name}: must be finite, got {v!r}")
    if lo is not None and (v < lo or (lo_open and v == lo)):
        raise ValueError(f"{name}: must be {'>' if lo_open else '>='} {lo}, "
                         f"got {v!r}")
    return v


def points3(x: ArrayLike, name: str, *, finite: bool = True
            ) -> tuple[FloatArray, bool]:
    """An (n, 3) or (3,) real array as the library's component-major (3, n)
    contiguous array, and whether it was one point."""
    if finite:
        real_array(x, name)
    return _core.points(x, name)


def same_shape(a: FloatArray, ref: FloatArray, name: str, ref_name: str,
               given: ArrayLike, ref_given: ArrayLike) -> None:
    """ValueError when a and ref (component-major) differ in shape."""
    if a.shape != ref.shape:
        raise ValueError(f"{name}: shape {np.shape(given)} differs from that "
                         f"of {ref_name} {np.shape(ref_given)}")
