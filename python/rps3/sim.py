"""Simulation of the plant (include/rps3.h, rps3_sim): the state (l, dl)
integrated by the library under a controller of rps3.control, recorded at
given output times in one C call (the loop over times, steps and ticks runs
in C; only a Python controller calls back into the interpreter).

    plant = rps3.Model(m_over_M=0.5)
    traj = rps3.trajectory.helix()
    sim = rps3.sim.Simulation(plant, integrator="rk4", h=1e-3)
    sim.start(traj.pose[0])
    res = sim.run(traj.t, rps3.control.pd(plant, traj))
    res.l, res.force, res.energy_residual            # (n, 3) [m], [N]; (n,) [J]
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from rps3._core import FloatArray, IntArray, buf, results, text
from rps3._rps3 import ffi, lib
from rps3.control import Controller
from rps3.errors import Rps3Error, check, error, real_array, real_number
from rps3.model import Model

#: integrators of the simulation, in the library's order
INTEGRATORS: tuple[str, ...] = tuple(text(lib.rps3_integrator_name(k))
                                     for k in range(lib.RPS3_NINTEGRATOR))


@dataclass(frozen=True)
class SimResult:
    """A run recorded at its output times t (n,).  After a failure
    (``status`` != 0) the times past ``failed_at`` hold NaN and the
    failure's status."""

    t: FloatArray           #: output times, (n,) [s]
    l: FloatArray           #: link lengths, (n, 3) [m]
    dl: FloatArray          #: link rates, (n, 3) [m/s]
    pose: FloatArray        #: platform pose (alpha, beta, z_c), (n, 3) [rad, rad, m]
    dpose: FloatArray       #: its rates, (n, 3) [rad/s, rad/s, m/s]
    force: FloatArray       #: forces applied (saturated) at t, (n, 3) [N]; NaN at the start
    force_cmd: FloatArray   #: forces commanded at the last tick, (n, 3) [N]; NaN at the start
    l_meas: FloatArray      #: lengths measured at the last tick, (n, 3) [m]; NaN at the start
    dl_meas: FloatArray     #: rates measured at the last tick, (n, 3) [m/s]
    l_des: FloatArray       #: a library controller's desired lengths, (n, 3) [m]; NaN otherwise
    dl_des: FloatArray      #: its desired rates, (n, 3) [m/s]; NaN otherwise
    T: FloatArray           #: kinetic energy, (n,) [J]
    P: FloatArray           #: potential energy, zero at the base plane, (n,) [J]
    work: FloatArray        #: work of the actuators since the start, (n,) [J]
    work_friction: FloatArray  #: work of the pin friction since the start (<= 0), (n,) [J]
    energy_residual: FloatArray  #: T + P - E0 - work - work_friction, (n,) [J]
    status_t: IntArray      #: status per output time, 0 = reached
    status: int             #: 0, or the status that stopped the run
    message: str            #: the library's message of the failure, "" if none
    failed_at: float        #: time of the failure [s], NaN if none
    nsteps: int             #: integrator steps since start
    nevals: int             #: forward dynamics evaluations since start
    nticks: int             #: controller calls at the control rate since start
    nsat: int               #: ticks with a saturated actuator since start

    @property
    def ok(self) -> bool:
        """Whether the run reached every output time."""
        return self.status == 0


class Simulation:
    """A simulated plant (a copy of the model) with its integrator options.

    Args:
        plant: the simulated manipulator; its effects (one of the inertias
            at least) and theta-solve options apply.
        integrator: one of INTEGRATORS: ``"rk4"`` (fixed step h, the
            default), ``"rkf45"``, ``"rk8pd"`` (adaptive), ``"msbdf"``
            (implicit BDF), ``"rk4imp"`` (implicit, fixed step).
        h: fixed step of rk4 and rk4imp (the largest that divides each
            control period evenly is used); first step of the others [s].
        epsabs, epsrel: adaptive error control on (l, dl, work) [-].
        hmin: adaptive steps below this fail the run [s].
        max_steps: integrator steps allowed per control period.
        fmax: actuator saturation |F_i| <= fmax [N]; 0: none.
        l_min, l_max: stroke of the links [m]; leaving it fails the run.
        noise_l, noise_dl: standard deviations of the measured lengths [m]
            and rates [m/s] (Gaussian, seeded).
        quant_l, quant_dl: quanta of the measured lengths [m] and rates
            [m/s]; 0: none.
        seed: seed of the noise generator.

    Raises:
        TypeError, ValueError: an option that is not a real number, or out
            of range (the library's message, naming the option).
    """

    def __init__(self, plant: Model, *, integrator: str = "rk4",
                 h: float = 1e-3, epsabs: float = 1e-9, epsrel: float = 1e-9,
                 hmin: float = 1e-12, max_steps: int = 100000,
                 fmax: float = 0.0, l_min: float = 0.0,
                 l_max: float = math.inf, noise_l: float = 0.0,
                 noise_dl: float = 0.0, quant_l: float = 0.0,
                 quant_dl: float = 0.0, seed: int = 0) -> None:
        if not isinstance(plant, Model):
            raise TypeError(f"plant: expected an rps3.Model, got {type(plant).__name__}")
        k = (lib.rps3_integrator_index(integrator.encode())
             if isinstance(integrator, str) else -1)
        if k < 0:
            raise ValueError(f"integrator: {integrator!r} is not one of "
                             f"{', '.join(INTEGRATORS)}")
        o = ffi.new("rps3_sim_options *")
        lib.rps3_sim_options_default(o)
        o.integrator = k
        for name, value in (("h", h), ("epsabs", epsabs), ("epsrel", epsrel),
                            ("hmin", hmin), ("fmax", fmax), ("l_min", l_min),
                            ("noise_l", noise_l), ("noise_dl", noise_dl),
                            ("quant_l", quant_l), ("quant_dl", quant_dl)):
            setattr(o, name, real_number(value, name))
        o.l_max = real_number(l_max, "l_max", finite=False)
        if math.isnan(o.l_max):
            raise ValueError("l_max: must not be NaN")
        for name, ivalue, hi in (("max_steps", max_steps, 2**63 - 1),
                                 ("seed", seed, 2**64 - 1)):
            if isinstance(ivalue, (bool, np.bool_)) or not isinstance(
                    ivalue, (int, np.integer)):
                raise TypeError(f"{name}: expected an integer, got {ivalue!r}")
            if not 0 <= int(ivalue) <= hi:
                raise ValueError(f"{name}: out of range, got {ivalue!r}")
        o.max_steps = int(max_steps)
        o.seed = int(seed) & 0xFFFFFFFFFFFFFFFF
        self.plant = plant
        self.integrator = INTEGRATORS[k]
        out = ffi.new("rps3_sim **")
        chk = ffi.new("rps3_check *")
        st = lib.rps3_sim_alloc(plant._c, o, out, chk)
        if st == lib.RPS3_EINVAL:
            msg = text(chk.msg)
            # the library names the option as the runner's key: simulate.h
            raise ValueError(msg.replace("simulate.", "", 1) if msg else
                             "invalid simulation options")
        check(st, chk.msg)
        self._s = ffi.gc(out[0], lib.rps3_sim_free)
        self._started = False
        self.last_result: SimResult | None = None

    # ------------------------------------------------------------ state

    @property
    def t(self) -> float:
        """Simulated time [s]."""
        return float(lib.rps3_sim_now(self._s).t)

    @property
    def status(self) -> int:
        """0, or the status that stopped the run."""
        return int(lib.rps3_sim_now(self._s).status)

    @property
    def E0(self) -> float:
        """T + P at the start [J]."""
        return float(lib.rps3_sim_now(self._s).E0)

    @property
    def mode(self) -> int:
        """The tracked assembly mode (+1 the level platform's side)."""
        return int(lib.rps3_sim_now(self._s).mode)

    def start(self, pose: ArrayLike, dpose: ArrayLike = (0.0, 0.0, 0.0),
              t0: float = 0.0) -> None:
        """Start (or restart) at time t0 [s] from the pose (alpha, beta,
        z_c) [rad, rad, m] and its rates [rad/s, rad/s, m/s]: the
        closed-form inverse kinematics fixes l, dl and the assembly mode.
        Clears the work, the counters and the status, reseeds the noise.

        Raises:
            TypeError, ValueError: pose or dpose not 3 finite real numbers.
            rps3.errors.Rps3Error: the library's status at the start (e.g.
                ReachError for an unreachable pose), with its message.
        """
        p = real_array(pose, "pose")
        v = real_array(dpose, "dpose")
        for name, a in (("pose", p), ("dpose", v)):
            if a.shape != (3,):
                raise ValueError(f"{name}: expected shape (3,), got {a.shape}")
        t = real_number(t0, "t0")
        st = lib.rps3_sim_start(self._s, t, ffi.new("double[3]", list(p)),
                                ffi.new("double[3]", list(v)))
        self._started = st == lib.RPS3_OK
        check(st, lib.rps3_sim_data(self._s).err.msg)

    def run(self, t: ArrayLike, controller: Controller, *,
            check_status: bool = True) -> SimResult:
        """Advance under the controller through the output times t [s]
        (increasing, t[0] >= the simulated time; a time equal to it records
        the present state), recording the state at each: one C call.  A
        later call continues from the last time.  Over several calls, or
        with outputs between ticks, the run is the same as in one call
        (rps3_sim_advance at each output time; the library's ticks are
        counted from the start).

        Args:
            t: (n,) output times [s].
            controller: a controller of rps3.control.
            check_status: raise when the run stops early (the exception of
                its status, with the library's message, e.g. SingularError;
                the partial result is ``exc.result`` and ``last_result``);
                False: return the result with its status.

        Raises:
            TypeError, ValueError: bad times or controller (named).
            The exception a Python controller raised, at once.
            rps3.errors.Rps3Error: the run stopped early (check_status).
        """
        if not isinstance(controller, Controller):
            raise TypeError(f"controller: expected an rps3.control controller, "
                            f"got {type(controller).__name__}")
        if not self._started:
            raise rps3_state("run: start() the simulation first")
        times = real_array(t, "t")
        if times.ndim == 0:
            times = times.reshape(1)
        if times.ndim != 1:
            raise ValueError(f"t: expected a 1-d array of times, got shape {times.shape}")
        times = np.ascontiguousarray(times)
        n = times.size
        if n and times[0] < lib.rps3_sim_now(self._s).t:
            raise ValueError(f"t: the first time {times[0]!r} is before the "
                             f"simulated time {float(lib.rps3_sim_now(self._s).t)!r}")
        if n > 1 and not (np.diff(times) > 0).all():
            i = int(np.flatnonzero(np.diff(times) <= 0)[0]) + 1
            raise ValueError(f"t: not strictly increasing at index {i}")
        out = results(n, {"l": (3,), "dl": (3,), "pose": (3,), "dpose": (3,),
                          "F": (3,), "F_cmd": (3,), "l_meas": (3,),
                          "dl_meas": (3,), "l_des": (3,), "dl_des": (3,),
                          "T": (), "P": (), "W": (2,), "residual": ()},
                      ("status",))
        o = ffi.new("rps3py_sim_out *")
        keep = []
        for name, a in out.items():
            keep.append(buf(a, "int[]" if a.dtype == np.int32 else "double[]"))
            setattr(o, name, keep[-1])
        lib.rps3py_sim_run(self._s, controller._c, controller._ctrl, n,
                           buf(times), o)
        s = lib.rps3_sim_now(self._s)
        status = int(s.status)
        res = SimResult(
            t=times, **{k: np.moveaxis(out[k], -1, 0)
                        for k in ("l", "dl", "pose", "dpose", "l_meas",
                                  "dl_meas", "l_des", "dl_des")},
            force=np.moveaxis(out["F"], -1, 0),
            force_cmd=np.moveaxis(out["F_cmd"], -1, 0),
            T=out["T"], P=out["P"], work=out["W"][0],
            work_friction=out["W"][1], energy_residual=out["residual"],
            status_t=out["status"], status=status,
            message=text(lib.rps3_sim_data(self._s).err.msg) if status else "",
            failed_at=float(s.failed_at), nsteps=int(s.nsteps),
            nevals=int(s.nevals), nticks=int(s.nticks), nsat=int(s.nsat))
        self.last_result = res
        controller._raise_pending()
        if check_status and status:
            exc = error(status, res.message)
            exc.result = res  # type: ignore[attr-defined]
            raise exc
        return res


def rps3_state(msg: str) -> Rps3Error:
    return error(lib.RPS3_ESTATE, msg)  # type: ignore[return-value]


def simulate(plant: Model, controller: Controller, t: ArrayLike,
             pose: ArrayLike, dpose: ArrayLike = (0.0, 0.0, 0.0), *,
             check_status: bool = True, **options: Any) -> SimResult:
    """A Simulation of plant with options, started at t[0] from pose and
    dpose, run through the times t [s] under controller: the result."""
    times = real_array(t, "t")
    if times.ndim != 1 or times.size == 0:
        raise ValueError(f"t: expected a non-empty 1-d array, got shape {times.shape}")
    sim = Simulation(plant, **options)
    sim.start(pose, dpose, float(times[0]))
    return sim.run(times, controller, check_status=check_status)
