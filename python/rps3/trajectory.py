"""Trajectories with exact derivatives, evaluated by the library:
the paper's helix (section VI, Tables I-II), a sinusoid per pose
coordinate, and a table of sampled poses (the interpolant's own
derivatives: docs/trajectories.md)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from rps3._core import FloatArray, check_error, real_array, strerror
from rps3._rps3 import ffi, lib
from rps3.model import Model, _number, _vector

# the library's dotted names -> keyword arguments
_KEYWORD = {"trajectory.radius": "radius", "trajectory.pitch": "pitch",
            "trajectory.z0": "z0", "trajectory.period": "period",
            "trajectory.blend": "blend", "trajectory.mean": "mean",
            "trajectory.amp": "amp", "trajectory.freq": "freq",
            "trajectory.phase": "phase", "trajectory.duration": "duration",
            "trajectory.table.t": "times", "trajectory.table.pose": "pose",
            "trajectory.table.rate": "rate", "trajectory.table.acc": "acc"}


@dataclass(frozen=True)
class Trajectory:
    """Samples of a trajectory: inputs of Model.inverse.  The (n, 3) arrays
    are views of one component-major block (Fortran-ordered), the layout
    the library reads without a copy."""

    t: FloatArray       #: sample times, (n,) [s]
    pose: FloatArray    #: (alpha, beta, z_c), (n, 3) [rad, rad, m]
    dpose: FloatArray   #: first derivative, (n, 3) [rad/s, rad/s, m/s]
    ddpose: FloatArray  #: second derivative, (n, 3) [rad/s^2, rad/s^2, m/s^2]


def _times(duration: float, samples: int | None, t: ArrayLike | None) -> FloatArray:
    if t is not None:
        if samples is not None:
            raise ValueError("t: give samples or t, not both")
        return np.ascontiguousarray(real_array(t, "t")).reshape(-1)
    n = 1001 if samples is None else samples
    if not isinstance(n, (int, np.integer)) or isinstance(n, bool):
        raise TypeError(f"samples: expected an integer >= 2, got {samples!r}")
    if n < 2:
        raise ValueError(f"samples: expected an integer >= 2, got {samples!r}")
    return np.linspace(0.0, duration, int(n))


def _evaluate(model: Model, tr: Any, samples: int | None,
              t: ArrayLike | None) -> Trajectory:
    chk = ffi.new("rps3_check *")
    if lib.rps3_traj_validate(model._c, tr, chk) != lib.RPS3_OK:
        raise check_error(chk, _KEYWORD)
    times = _times(float(lib.rps3_traj_duration(tr)), samples, t)
    n = times.size
    # one component-major block, pose, rate and acceleration (3, 3, n): the
    # (n, 3) fields are transposed views of it, which Model's stages pass to
    # the library as they are (no copy)
    block = np.empty((3, 3, n))
    status = lib.rps3py_traj_eval_n(
        model._c, tr, n, ffi.from_buffer("double[]", times),
        *(ffi.from_buffer("double[]", block[k]) for k in range(3)))
    if status != lib.RPS3_OK:
        raise ValueError(f"t: {strerror(status)} (the span is 0 to "
                         f"{lib.rps3_traj_duration(tr)} s)")
    return Trajectory(times, block[0].T, block[1].T, block[2].T)


def helix(*, radius: float | None = None, pitch: float | None = None,
          z0: float | None = None, period: float | None = None,
          blend: float | None = None, samples: int | None = None,
          t: ArrayLike | None = None, model: Model | None = None) -> Trajectory:
    """The paper's helix (35)-(37): the platform centre climbs a helix of
    radius r* and pitch h in one period T*, with parabolic blends t_a.

    Arguments left out take Table II's values (r* = 0.000266 m,
    h = 0.03048 m, z_i = 0.3048 m, T* = 10 s, t_a = 1 s).

    Args:
        radius: helix radius r* [m], below r / 2 of the model.
        pitch: rise per turn h [m].
        z0: start height z_i of the platform centre [m].
        period: time of one turn T* [s].
        blend: blend time t_a [s], 0 < t_a <= T* / 2.
        samples: number of samples from 0 to T* (default 1001); or
        t: the sample times [s] themselves.
        model: the manipulator the helix is checked against (Table II).

    Raises:
        ValueError: naming the argument that is out of range.
        TypeError: naming the argument that is not real numbers.
    """
    tr = ffi.new("rps3_traj *")
    lib.rps3_traj_default(tr)
    for name, value in (("radius", radius), ("pitch", pitch), ("z0", z0),
                        ("period", period), ("blend", blend)):
        if value is not None:
            setattr(tr.helix, name, _number(value, name))
    return _evaluate(model or Model(), tr, samples, t)


def sine(*, mean: ArrayLike, amp: ArrayLike, freq: ArrayLike,
         duration: float, phase: ArrayLike = (0.0, 0.0, 0.0),
         samples: int | None = None, t: ArrayLike | None = None,
         model: Model | None = None) -> Trajectory:
    """pose_k(t) = mean_k + amp_k sin(2 pi freq_k t + phase_k), k = alpha,
    beta, z_c, for 0 <= t <= duration.

    Args:
        mean: (alpha, beta, z_c) means [rad, rad, m].
        amp: amplitudes [rad, rad, m].
        freq: frequencies [Hz].
        duration: time span [s].
        phase: phases [rad].
        samples: number of samples from 0 to duration (default 1001); or
        t: the sample times [s] themselves.
        model: the manipulator the trajectory is checked against.

    Raises:
        ValueError: naming the argument that is out of range.
        TypeError: naming the argument that is not real numbers.
    """
    tr = ffi.new("rps3_traj *")
    tr.kind = lib.RPS3_TRAJ_SINE
    for name, value in (("mean", mean), ("amp", amp), ("freq", freq),
                        ("phase", phase)):
        for k, x in enumerate(_vector(value, name)):
            getattr(tr.sine, name)[k] = x
    tr.sine.duration = _number(duration, "duration")
    return _evaluate(model or Model(), tr, samples, t)


def _rows(x: ArrayLike, name: str, n: int) -> FloatArray:
    a = np.ascontiguousarray(real_array(x, name))
    if a.shape != (n, 3):
        raise ValueError(f"{name}: expected shape ({n}, 3), got {a.shape}")
    return a


def table(times: ArrayLike, pose: ArrayLike, rate: ArrayLike | None = None,
          acc: ArrayLike | None = None, *, samples: int | None = None,
          t: ArrayLike | None = None, model: Model | None = None) -> Trajectory:
    """A motion given as rows: pose[i] at times[i], interpolated with the
    interpolant's exact rate and acceleration, as the runner's ``table``
    kind: the quintic Hermite interpolant of pose, rate and acc; the cubic
    Hermite one of pose and rate; or, without rates, the not-a-knot cubic
    spline of the poses (at least 4 rows; its error is O(h^4), O(h^3),
    O(h^2) in pose, rate and acceleration for rows every h).  The
    trajectory's time starts at the first row (t = times - times[0]).

    Args:
        times: (n,) strictly increasing row times [s].
        pose: (n, 3) rows of (alpha, beta, z_c) [rad, rad, m].
        rate: (n, 3) rates at the rows, or None for the spline's.
        acc: (n, 3) accelerations at the rows (with rate), or None.
        samples: number of samples over the span (default 1001); or
        t: the sample times [s] themselves, from 0.
        model: the manipulator every row must be reachable for.

    Raises:
        ValueError: naming the argument and its row (e.g. ``pose: ...
            trajectory.table.pose[3] = ...: pose unreachable``).
        TypeError: naming the argument that is not real numbers.
    """
    tm = np.ascontiguousarray(real_array(times, "times")).reshape(-1)
    n = tm.size
    q = _rows(pose, "pose", n)
    if acc is not None and rate is None:
        raise ValueError("acc: accelerations need the rates as well")
    if rate is None:
        dq = np.empty((n, 3))
        work = np.empty(n)
        rc = lib.rps3_table_spline(n, ffi.from_buffer("double[]", tm),
                                   ffi.cast("const double (*)[3]",
                                            ffi.from_buffer("double[]", q)),
                                   ffi.cast("double (*)[3]",
                                            ffi.from_buffer("double[]", dq)),
                                   ffi.from_buffer("double[]", work))
        if rc == lib.RPS3_ERANGE:
            raise ValueError("pose: the spline's rates overflow")
        if rc != lib.RPS3_OK:
            raise ValueError(f"times: the spline needs at least 4 rows at "
                             f"finite, strictly increasing times, with "
                             f"finite poses (got {n} rows)")
    else:
        dq = _rows(rate, "rate", n)
    ddq = None if acc is None else _rows(acc, "acc", n)
    tr = ffi.new("rps3_traj *")
    lib.rps3_traj_default(tr)
    tr.kind = lib.RPS3_TRAJ_TABLE
    tr.table.n = n
    tr.table.time = ffi.from_buffer("double[]", tm)
    tr.table.value = ffi.cast("const double (*)[3]", ffi.from_buffer("double[]", q))
    tr.table.rate = ffi.cast("const double (*)[3]", ffi.from_buffer("double[]", dq))
    if ddq is not None:
        tr.table.acc = ffi.cast("const double (*)[3]",
                                ffi.from_buffer("double[]", ddq))
    # the arrays stay referenced here while the library reads them
    return _evaluate(model or Model(), tr, samples, t)
