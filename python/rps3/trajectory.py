"""Trajectories with exact derivatives, evaluated by the library:
the paper's helix (section VI, Tables I-II), a sinusoid per pose
coordinate, a table of sampled poses (the interpolant's own
derivatives: docs/trajectories.md), waypoints joined by a time law, and
paths of the platform centre (line, circle or rising circle, table)."""

from __future__ import annotations

from dataclasses import dataclass, field
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
            "trajectory.table.rate": "rate", "trajectory.table.acc": "acc",
            "trajectory.waypoints.times": "times",
            "trajectory.waypoints.poses": "poses",
            "trajectory.waypoints.blend_ratio": "blend",
            "trajectory.path.blend_ratio": "blend",
            "trajectory.path.table.t": "times",
            "trajectory.path.table.centre": "centre"}


@dataclass(frozen=True)
class Trajectory:
    """Samples of a trajectory: inputs of Model.inverse.  The (n, 3) arrays
    are views of one component-major block (Fortran-ordered), the layout
    the library reads without a copy."""

    t: FloatArray       #: sample times, (n,) [s]
    pose: FloatArray    #: (alpha, beta, z_c), (n, 3) [rad, rad, m]
    dpose: FloatArray   #: first derivative, (n, 3) [rad/s, rad/s, m/s]
    ddpose: FloatArray  #: second derivative, (n, 3) [rad/s^2, rad/s^2, m/s^2]
    #: the library's description (rps3.control's controllers follow it)
    spec: Spec | None = field(default=None, repr=False, compare=False)


class Spec:
    """A trajectory as the library holds it (rps3_traj), with the arrays it
    points to kept alive: the controllers of rps3.control follow it, and
    ``eval`` evaluates it at any times."""

    def __init__(self, c: Any, keep: tuple[Any, ...] = ()) -> None:
        self.c = c
        self._keep = keep

    @property
    def duration(self) -> float:
        """Time span [s]."""
        return float(lib.rps3_traj_duration(self.c))

    def eval(self, t: ArrayLike, model: Model | None = None) -> Trajectory:
        """The pose, rate and acceleration at times t [s] (rps3_traj_eval)."""
        return _evaluate(model or Model(), self.c, None, t, self._keep)


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
              t: ArrayLike | None, keep: tuple[Any, ...] = ()) -> Trajectory:
    chk = ffi.new("rps3_check *")
    if lib.rps3_traj_check(model._c, tr, chk) != lib.RPS3_OK:
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
    return Trajectory(times, block[0].T, block[1].T, block[2].T,
                      spec=Spec(tr, keep))


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
    # the arrays stay referenced by the trajectory's spec
    return _evaluate(model or Model(), tr, samples, t, (tm, q, dq, ddq))


# ------------------------------------------------- waypoints and paths

def _law(law: str, name: str = "law") -> int:
    k = lib.rps3_time_law_index(str(law).encode()) if isinstance(law, str) else -1
    if k < 0:
        names = [ffi.string(lib.rps3_time_law_name(i)).decode() for i in range(3)]
        raise ValueError(f"{name}: {law!r} is not one of {', '.join(names)}")
    return int(k)


def _real_rows(x: ArrayLike, name: str, ncol: int | None = 3) -> FloatArray:
    a = np.asarray(x)
    if a.dtype.kind == "c":
        raise TypeError(f"{name}: complex values are not accepted")
    if a.dtype.kind not in "biuf":
        raise TypeError(f"{name}: expected real numbers, got dtype {a.dtype}")
    a = np.ascontiguousarray(a, dtype=np.float64)
    if ncol is None:
        if a.ndim != 1:
            raise ValueError(f"{name}: expected a 1-d array, got shape {a.shape}")
    elif a.ndim != 2 or a.shape[1] != ncol:
        raise ValueError(f"{name}: expected shape (n, {ncol}), got {a.shape}")
    return a


def waypoints(times: ArrayLike, poses: ArrayLike, *, law: str = "lspb",
              blend: float | None = None, vmax: ArrayLike | None = None,
              amax: ArrayLike | None = None, samples: int | None = None,
              t: ArrayLike | None = None, model: Model | None = None) -> Trajectory:
    """Poses at given times joined by a time law per coordinate (the
    runner's ``waypoints`` kind, include/rps3.h rps3_waypoints).

    Args:
        times: (n,) times [s], times[0] = 0, strictly increasing, n >= 2.
        poses: (n, 3) poses (alpha, beta, z_c) [rad, rad, m].
        law: ``"lspb"`` (rests at every waypoint, parabolic blends),
            ``"minimum_jerk"`` (rests at every waypoint) or ``"quintic"``
            (through the inner waypoints without stopping).
        blend: LSPB blend fraction of each segment, 0 < f <= 1/2 (0.1).
        vmax: rate limits [rad/s, rad/s, m/s] (0: none; LSPB and
            minimum_jerk): a segment is stretched until no coordinate
            exceeds them, and the span grows accordingly.
        amax: acceleration limits [rad/s^2, rad/s^2, m/s^2], likewise.
        samples: number of samples over the (stretched) span (1001); or
        t: the sample times [s].
        model: the manipulator every pose must be reachable for.

    Raises:
        TypeError, ValueError: naming the argument (and the row).
    """
    tm = _real_rows(times, "times", None)
    q = _real_rows(poses, "poses")
    if q.shape[0] != tm.size:
        raise ValueError(f"poses: {q.shape[0]} rows for {tm.size} times")
    tr = ffi.new("rps3_traj *")
    lib.rps3_traj_default(tr)
    tr.kind = lib.RPS3_TRAJ_WAYPOINTS
    tr.wp.n = tm.size
    tr.wp.time = ffi.from_buffer("double[]", tm)
    tr.wp.pose = ffi.cast("const double (*)[3]", ffi.from_buffer("double[]", q))
    tr.wp.law = _law(law)
    if blend is not None:
        tr.wp.blend = _number(blend, "blend")
    for name, value in (("vmax", vmax), ("amax", amax)):
        if value is not None:
            for k, x in enumerate(_vector(value, name)):
                getattr(tr.wp, name)[k] = x
    return _evaluate(model or Model(), tr, samples, t, (tm, q))


def _path(shape: int, duration: float, law: str, blend: float | None) -> Any:
    tr = ffi.new("rps3_traj *")
    lib.rps3_traj_default(tr)
    tr.kind = lib.RPS3_TRAJ_PATH
    tr.path.shape = shape
    tr.path.duration = _number(duration, "duration")
    tr.path.law = _law(law)
    if blend is not None:
        tr.path.blend = _number(blend, "blend")
    return tr


def line(start: ArrayLike, end: ArrayLike, duration: float, *,
         law: str = "lspb", blend: float | None = None,
         samples: int | None = None, t: ArrayLike | None = None,
         model: Model | None = None) -> Trajectory:
    """The platform centre on a straight line from start to end [m] in
    duration [s] under a time law (``"lspb"`` with blend fraction blend,
    default 0.1, or ``"minimum_jerk"``), turned into the pose by inverting
    (3)-(4): every point must keep 0 < rho_c < r/2 from the Z axis.

    Raises:
        TypeError, ValueError: naming the argument out of range.
    """
    tr = _path(lib.RPS3_PATH_LINE, duration, law, blend)
    for name, value in (("start", start), ("end", end)):
        for k, x in enumerate(_vector(value, name)):
            getattr(tr.path, name)[k] = x
    return _evaluate(model or Model(), tr, samples, t)


def circle(centre: ArrayLike, radius: float, duration: float, *,
           angle0: float = 0.0, turns: float = 1.0, pitch: float = 0.0,
           law: str = "lspb", blend: float | None = None,
           samples: int | None = None, t: ArrayLike | None = None,
           model: Model | None = None) -> Trajectory:
    """The platform centre on a horizontal circle: centre [m] at t = 0,
    radius [m], starting angle angle0 [rad] from +X, turns (< 0 clockwise)
    in duration [s] under the time law.  With pitch [m] != 0 the circle
    rises by pitch per turn, uniformly in time (the path helix; the paper's
    helix is centre (0, 0, z_i), radius r*, pitch h, law lspb, blend
    t_a / T*).  Every point must keep 0 < rho_c < r/2 from the Z axis.

    Raises:
        TypeError, ValueError: naming the argument out of range.
    """
    pitch_v = _number(pitch, "pitch")
    shape = lib.RPS3_PATH_CIRCLE if pitch_v == 0.0 else lib.RPS3_PATH_HELIX
    tr = _path(shape, duration, law, blend)
    for k, x in enumerate(_vector(centre, "centre")):
        tr.path.centre[k] = x
    tr.path.radius = _number(radius, "radius")
    tr.path.angle0 = _number(angle0, "angle0")
    tr.path.turns = _number(turns, "turns")
    tr.path.pitch = pitch_v
    return _evaluate(model or Model(), tr, samples, t)


def path_table(times: ArrayLike, centre: ArrayLike, rate: ArrayLike | None = None,
               acc: ArrayLike | None = None, *, samples: int | None = None,
               t: ArrayLike | None = None, model: Model | None = None) -> Trajectory:
    """The platform centre (x, y, z) [m] sampled in rows at times [s],
    interpolated as :func:`table` interpolates poses (quintic or cubic
    Hermite with given rates [m/s] and accelerations [m/s^2], else the
    not-a-knot cubic spline, at least 4 rows), then turned into the pose by
    inverting (3)-(4).  The path must turn by less than pi/2 about the Z
    axis from one row to the next, and keep 0 < rho_c < r/2.

    Raises:
        TypeError, ValueError: naming the argument (and the row).
    """
    tm = _real_rows(times, "times", None)
    c = _real_rows(centre, "centre")
    n = tm.size
    if c.shape[0] != n:
        raise ValueError(f"centre: {c.shape[0]} rows for {n} times")
    if acc is not None and rate is None:
        raise ValueError("acc: accelerations need the rates as well")
    rows = "const double (*)[3]"
    if rate is None:
        dc = np.empty((n, 3))
        work = np.empty(n)
        rc = lib.rps3_table_spline(n, ffi.from_buffer("double[]", tm),
                                   ffi.cast(rows, ffi.from_buffer("double[]", c)),
                                   ffi.cast("double (*)[3]",
                                            ffi.from_buffer("double[]", dc)),
                                   ffi.from_buffer("double[]", work))
        if rc != lib.RPS3_OK:
            raise ValueError(f"times: the spline needs at least 4 rows at "
                             f"finite, strictly increasing times, with finite "
                             f"centres (got {n} rows)")
    else:
        dc = _real_rows(rate, "rate")
    ddc = None if acc is None else _real_rows(acc, "acc")
    for name, a in (("rate", dc), ("acc", ddc)):
        if a is not None and a.shape != c.shape:
            raise ValueError(f"{name}: shape {a.shape} differs from that of "
                             f"centre {c.shape}")
    psi = np.empty(n)
    if lib.rps3_table_unwrap(n, ffi.cast(rows, ffi.from_buffer("double[]", c)),
                             ffi.from_buffer("double[]", psi)) != lib.RPS3_OK:
        raise ValueError("centre: a row is not finite")
    tr = ffi.new("rps3_traj *")
    lib.rps3_traj_default(tr)
    tr.kind = lib.RPS3_TRAJ_PATH
    tr.path.shape = lib.RPS3_PATH_TABLE
    tb = tr.path.table
    tb.n = n
    tb.time = ffi.from_buffer("double[]", tm)
    tb.value = ffi.cast(rows, ffi.from_buffer("double[]", c))
    tb.rate = ffi.cast(rows, ffi.from_buffer("double[]", dc))
    if ddc is not None:
        tb.acc = ffi.cast(rows, ffi.from_buffer("double[]", ddc))
    tr.path.table_psi = ffi.from_buffer("double[]", psi)
    return _evaluate(model or Model(), tr, samples, t, (tm, c, dc, ddc, psi))
