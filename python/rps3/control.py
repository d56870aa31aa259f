"""Controllers for rps3.sim.Simulation: the library's four (open loop, PD,
PD + gravity, computed torque; include/rps3.h, rps3_ctrl), a constant force,
and control laws written in Python, which the C simulation calls at each
tick through a cffi callback.

    traj = rps3.trajectory.helix()
    ctl = rps3.control.pd(model, traj, kp=2000.0, kd=40.0, rate=1000.0)

    def law(t, l, dl):                    # a Python controller: [s], [m], [m/s]
        return 2000.0 * (l_ref - l) - 40.0 * dl          # forces [N]
    ctl = rps3.control.python(law, rate=1000.0)

A Python controller costs a round trip into the interpreter per tick (a few
microseconds; docs/python.md gives the measured figure), against a fraction
of a microsecond for the library's controllers: keep the library's for long
sweeps.  An exception raised in the law stops the simulation at that tick,
and Simulation.run raises it (the same exception object) once the C call
has returned; the library is never left in an inconsistent state.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from rps3._rps3 import ffi, lib
from rps3.errors import check, real_array, real_number
from rps3.model import Model
from rps3.trajectory import Trajectory

#: kinds of the library's controllers, in its order
KINDS: tuple[str, ...] = tuple(ffi.string(lib.rps3_ctrl_name(k)).decode()
                               for k in range(lib.RPS3_NCTRL))

ControlLaw = Callable[[float, np.ndarray, np.ndarray], ArrayLike]


class Controller:
    """A force law the simulation calls at ``rate`` [Hz] with zero-order hold
    (rate 0: at every evaluation of the plant, a continuous force law).
    Build one with :func:`pd`, :func:`pd_gravity`, :func:`computed_torque`,
    :func:`open_loop`, :func:`constant` or :func:`python`."""

    rate: float
    _c: Any          # rps3_controller *
    _ctrl: Any       # rps3_ctrl * of a library controller, else NULL

    def _bind(self, fn: Any, state: Any, rate: float) -> None:
        self.rate = real_number(rate, "rate", lo=0.0)
        self._c = ffi.new("rps3_controller *")
        self._c.fn = fn
        self._c.state = state
        self._c.rate = self.rate
        self._ctrl = ffi.NULL

    def _raise_pending(self) -> None:
        """The exception a Python law raised during the last run, if any."""


class Library(Controller):
    """One of the library's controllers (rps3_ctrl): its own model of the
    mechanism (which may differ from the plant's) follows the trajectory;
    see include/rps3.h for each law.  Read-only attributes: kind, kp, kd,
    model, trajectory; after a run, ``l_des``, ``dl_des`` of the last tick
    [m, m/s]."""

    def __init__(self, kind: str, model: Model, trajectory: Trajectory, *,
                 kp: float = 0.0, kd: float = 0.0, rate: float = 1000.0) -> None:
        k = lib.rps3_ctrl_index(str(kind).encode()) if isinstance(kind, str) else -1
        if k < 0:
            raise ValueError(f"kind: {kind!r} is not one of {', '.join(KINDS)}")
        if not isinstance(model, Model):
            raise TypeError(f"model: expected an rps3.Model, got {type(model).__name__}")
        spec = getattr(trajectory, "spec", None)
        if spec is None:
            raise TypeError("trajectory: expected a trajectory of rps3.trajectory "
                            f"(helix, sine, table, waypoints, line, circle, ...), "
                            f"got {type(trajectory).__name__}")
        self.kind = KINDS[k]
        self.kp = real_number(kp, "kp", lo=0.0)
        self.kd = real_number(kd, "kd", lo=0.0)
        self.model = model
        self.trajectory = trajectory  # its arrays outlive the controller
        out = ffi.new("rps3_ctrl **")
        chk = ffi.new("rps3_check *")
        st = lib.rps3_ctrl_alloc(k, self.kp, self.kd, model._c, spec.c, out,
                                 chk)
        check(st, chk.msg)
        ctrl = ffi.gc(out[0], lib.rps3_ctrl_free)
        self._bind(lib.rps3py_ctrl_update_fn(), ctrl, rate)
        # the law with its capability: offered the plant's state
        self._c[0] = lib.rps3_ctrl_bind(ctrl, self.rate)
        self._ctrl = ctrl

    @property
    def l_des(self) -> np.ndarray:
        """Desired link lengths at the last tick [m]."""
        out = ffi.new("double[3]")
        lib.rps3_ctrl_last(self._ctrl, ffi.NULL, out, ffi.NULL, ffi.NULL)
        return np.array(list(out))

    @property
    def dl_des(self) -> np.ndarray:
        """Desired link rates at the last tick [m/s]."""
        out = ffi.new("double[3]")
        lib.rps3_ctrl_last(self._ctrl, ffi.NULL, ffi.NULL, out, ffi.NULL)
        return np.array(list(out))

    def __repr__(self) -> str:
        return (f"rps3.control.Library({self.kind!r}, kp={self.kp!r}, "
                f"kd={self.kd!r}, rate={self.rate!r})")


def open_loop(model: Model, trajectory: Trajectory, *,
              rate: float = 1000.0) -> Library:
    """F = the inverse dynamics of the desired motion in the controller's
    model (feedforward; rate 0 applies it continuously)."""
    return Library("open_loop", model, trajectory, rate=rate)


def pd(model: Model, trajectory: Trajectory, *, kp: float = 2000.0,
       kd: float = 40.0, rate: float = 1000.0) -> Library:
    """F = kp e + kd de, e = l_d - l: kp [N/m], kd [N s/m] (defaults those of
    the runner's scenes)."""
    return Library("pd", model, trajectory, kp=kp, kd=kd, rate=rate)


def pd_gravity(model: Model, trajectory: Trajectory, *, kp: float = 2000.0,
               kd: float = 40.0, rate: float = 1000.0) -> Library:
    """F = kp e + kd de + G(l), G the controller model's static forces at the
    measured lengths: kp [N/m], kd [N s/m]."""
    return Library("pd_gravity", model, trajectory, kp=kp, kd=kd, rate=rate)


def computed_torque(model: Model, trajectory: Trajectory, *, kp: float = 400.0,
                    kd: float = 40.0, rate: float = 1000.0) -> Library:
    """F = the controller model's inverse dynamics at the measured state with
    ddl = ddl_d + kp e + kd de: kp [1/s^2], kd [1/s] set the error dynamics
    e'' + kd e' + kp e = 0 when the models agree."""
    return Library("computed_torque", model, trajectory, kp=kp, kd=kd, rate=rate)


class Constant(Controller):
    """Constant actuator forces F [N] (zeros: the unactuated plant)."""

    def __init__(self, F: ArrayLike = (0.0, 0.0, 0.0), *, rate: float = 0.0) -> None:
        f = real_array(F, "F")
        if f.shape != (3,):
            raise ValueError(f"F: expected 3 forces, got shape {f.shape}")
        self.F = ffi.new("double[3]", [float(x) for x in f])
        self._bind(lib.rps3py_constant_force_fn(), self.F, rate)


def constant(F: ArrayLike = (0.0, 0.0, 0.0), *, rate: float = 0.0) -> Constant:
    """Constant actuator forces F [N], > 0 extends."""
    return Constant(F, rate=rate)


class Python(Controller):
    """A control law written in Python: ``fn(t, l, dl) -> F`` with the time
    t [s], the measured link lengths l [m] and rates dl [m/s] (new (3,)
    float64 arrays at each call; with noise or quantisation as the
    simulation's options say) and the commanded forces F [N], three real
    finite numbers.  Any exception the law raises (a bad return value
    included: TypeError, ValueError) stops the simulation at that tick and
    is re-raised by Simulation.run."""

    def __init__(self, fn: ControlLaw, *, rate: float = 1000.0) -> None:
        if not callable(fn):
            raise TypeError(f"fn: expected a callable fn(t, l, dl) -> F, got {fn!r}")
        self.fn = fn
        self.calls = 0
        self._error: BaseException | None = None
        self._handle = ffi.new_handle(self)
        self._bind(lib.rps3py_control_py_fn(), self._handle, rate)

    def _raise_pending(self) -> None:
        exc, self._error = self._error, None
        if exc is not None:
            raise exc

    def __repr__(self) -> str:
        return f"rps3.control.Python({self.fn!r}, rate={self.rate!r})"


def python(fn: ControlLaw, *, rate: float = 1000.0) -> Python:
    """A control law written in Python, ``fn(t, l, dl) -> F`` (t [s], l [m],
    dl [m/s], F [N]), called by the C simulation at each tick (rate [Hz];
    0: at every evaluation of the plant, ~4 per rk4 step)."""
    return Python(fn, rate=rate)


def _forces(value: Any) -> np.ndarray:
    try:
        f = real_array(value, "controller return value")
    except TypeError:
        raise TypeError(f"controller return value: expected 3 real forces [N], "
                        f"got {value!r}") from None
    if f.shape != (3,):
        raise ValueError(f"controller return value: expected 3 forces [N], got "
                         f"shape {f.shape}")
    return f


@ffi.def_extern(error=lib.RPS3_EINVAL)
def rps3py_control_py(state: Any, t: float, l: Any, dl: Any, F: Any) -> int:
    ctl = ffi.from_handle(state)
    try:
        ctl.calls += 1
        f = _forces(ctl.fn(t, np.frombuffer(ffi.buffer(l, 24)).copy(),
                           np.frombuffer(ffi.buffer(dl, 24)).copy()))
        F[0] = f[0]
        F[1] = f[1]
        F[2] = f[2]
        return 0
    except BaseException as exc:  # KeyboardInterrupt too: stop the run
        ctl._error = exc
        return int(lib.RPS3_EINVAL)
