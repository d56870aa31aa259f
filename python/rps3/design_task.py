"""What a task asks of a design's actuators: the forces, powers and
strokes along a trajectory (docs/design.md); answered through
:mod:`rps3.design` too.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from rps3._core import FloatArray, text
from rps3._rps3 import ffi, lib
from rps3.design import Design, Options, _ws
from rps3.errors import ReachError, error

if TYPE_CHECKING:
    from rps3.trajectory import Spec, Trajectory

@dataclass(frozen=True)
class Task:
    """What a task asks of a design's actuators (rps3_design_task), per
    link (leading axis 3)."""

    F_peak: FloatArray     #: max_t |F_i| [N]
    F_rms: FloatArray      #: RMS of F_i over the samples [N]
    P_peak: FloatArray     #: max_t |F_i dl_i| [W]
    v_peak: FloatArray     #: max_t |dl_i| [m/s]
    l_lo: FloatArray       #: shortest length of each link [m]
    l_hi: FloatArray       #: longest [m]
    lti_min: float         #: least LTI along the task [-]
    nsamples: int          #: samples evaluated

    @property
    def peak_force(self) -> float:
        """The largest actuator force of any link [N]."""
        return float(np.max(self.F_peak))

    @property
    def rms_force(self) -> float:
        """The largest RMS force of any link [N]."""
        return float(np.max(self.F_rms))

    @property
    def peak_power(self) -> float:
        """The largest actuator power of any link [W]."""
        return float(np.max(self.P_peak))


def _spec(trajectory: Trajectory | Spec) -> tuple[Any, int | None]:
    from rps3.trajectory import Spec, Trajectory
    if isinstance(trajectory, Trajectory):
        if trajectory.spec is None:
            raise TypeError("trajectory: has no library description (spec)")
        return trajectory.spec.c, len(trajectory.t)
    if isinstance(trajectory, Spec):
        return trajectory.c, None
    raise TypeError(f"trajectory: expected an rps3.trajectory.Trajectory, "
                    f"got {type(trajectory).__name__}")


def _task_c(design: Design, tr: Any, samples: int, link_mass: bool,
            opts: Options | None) -> tuple[int, Any, str]:
    w = _ws()
    res = ffi.new("rps3_design_task *")
    status = lib.rps3_design_task_eval(
        w, design._c(), (opts or Options())._c(), tr, samples,
        lib.RPS3_DESIGN_LINK_MASS if link_mass else lib.RPS3_DESIGN_NO_LINK_MASS,
        res)
    return int(status), res, text(w.err.msg)


def _task_result(res: Any) -> Task:
    def v(name: str) -> FloatArray:
        return np.array([float(getattr(res, name)[i]) for i in range(3)])
    return Task(F_peak=v("F_peak"), F_rms=v("F_rms"), P_peak=v("P_peak"),
                v_peak=v("v_peak"), l_lo=v("l_lo"), l_hi=v("l_hi"),
                lti_min=float(res.lti_min), nsamples=int(res.nsamples))


def _samples(samples: int | None, default: int | None) -> int:
    n = samples if samples is not None else (default or 201)
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 2:
        raise ValueError(f"samples: expected an integer >= 2, got {samples!r}")
    return int(n)


def task(design: Design, trajectory: Trajectory | Spec, *,
         samples: int | None = None, link_mass: bool = True,
         options: Options | None = None) -> Task:
    """The actuator requirements of a task: the trajectory sampled at
    equally spaced times over its span, the forces by the library's batch
    inverse dynamics with the design's model (the payload included when
    design.payload > 0).

    Args:
        design: the design.
        trajectory: an rps3.trajectory.Trajectory (or its ``spec``).
        samples: number of samples (default: as many as the Trajectory
            has, 201 for a Spec).
        link_mass: False leaves the links' gravity and inertia out (the
            paper's case 1).
        options: how the LTI is evaluated.

    Raises:
        rps3.errors.ReachError: a sample is outside the design's
            workspace; the message names its time and why (the limits
            crossed), ``exc.result`` holds the requirements of the samples
            before it.
        ValueError: naming the argument (a trajectory the design's model
            refuses, samples < 2).
    """
    tr, n_default = _spec(trajectory)
    n = _samples(samples, n_default)
    status, res, msg = _task_c(design, tr, n, link_mass, options)
    if status == lib.RPS3_EREACH:
        exc = ReachError(f"trajectory: outside the design's workspace: {msg}",
                         status)
        exc.result = _task_result(res)  # type: ignore[attr-defined]
        raise exc
    if status != lib.RPS3_OK:
        raise error(status, f"trajectory: {msg}")
    return _task_result(res)
