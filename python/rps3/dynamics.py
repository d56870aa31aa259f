"""Forward dynamics: the link accelerations that actuator forces produce at
a state, Mq(l) ddl + hq(l, dl) = F (include/rps3.h, rps3_fwddyn), over
arrays of states in one C call.

    model = rps3.Model()
    fd = rps3.dynamics.forward(model, l, dl, F)     # (n, 3) each
    fd.ddl                                          # (n, 3) [m/s^2]
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from rps3._core import FloatArray, IntArray, buf, per_point, results
from rps3._rps3 import ffi, lib
from rps3.errors import check, points3, same_shape
from rps3.model import Model


@dataclass(frozen=True)
class Forward:
    """Result of :func:`forward`: per state (leading axis n, absent for one
    state).  Failed states hold NaN; their status says why and
    ``message`` the first failure's text."""

    ddl: FloatArray      #: link accelerations, (n, 3) [m/s^2]
    pose: FloatArray     #: platform pose (alpha, beta, z_c), (n, 3) [rad, rad, m]
    dpose: FloatArray    #: its rates, (n, 3) [rad/s, rad/s, m/s]
    theta: FloatArray    #: link angles, (n, 3) [rad]
    dtheta: FloatArray   #: their rates, (n, 3) [rad/s]
    ddtheta: FloatArray  #: their accelerations, (n, 3) [rad/s^2]
    Mq: FloatArray       #: joint-space mass matrix, (n, 3, 3) [kg]
    hq: FloatArray       #: bias forces (velocity products, gravity, friction), (n, 3) [N]
    Mcond: FloatArray    #: 1-norm condition number of Mq, (n,) [-]
    T: FloatArray        #: kinetic energy of the selected effects, (n,) [J]
    P: FloatArray        #: potential energy, zero at the base plane, (n,) [J]
    mode: IntArray       #: assembly mode (+1 the level platform's side, -1 the other)
    status: IntArray     #: rps3 status code per state, 0 = ok
    message: str         #: "point I: ..." of the first failure, "" if none

    @property
    def ok(self) -> np.ndarray:
        """Boolean mask of the states that succeeded."""
        return np.asarray(self.status) == 0


def _message(msg: Any, nfail: int) -> str:
    return ffi.string(msg).decode() if nfail else ""


def forward(model: Model, l: ArrayLike, dl: ArrayLike, F: ArrayLike, *,
            check_status: bool = True) -> Forward:
    """Forward dynamics of the model's selected effects (rps3_fwddyn).

    The states are computed in order with one workspace: the theta solve of
    state i starts from state i-1's root when the model's ``warm_start`` is
    on (the default), so that a sequence along a motion stays on its
    assembly mode; with ``warm_start=False`` each starts cold (rps3_fk).
    One of the effects platform_inertia, link_inertia or payload must be
    selected (with a mass), else the mass matrix is singular.

    Args:
        model: the manipulator.
        l: (n, 3) or (3,) link lengths [m].
        dl: link rates [m/s], same shape.
        F: actuator forces [N], > 0 extends, same shape.
        check_status: raise the exception of the first failing state
            (rps3.errors; e.g. SingularError near a singular configuration);
            False: return the statuses and NaN for the failed states.

    Returns:
        Forward: ddl [m/s^2], the pose and its rates, theta, Mq [kg], hq [N],
        T, P [J], status.

    Raises:
        TypeError, ValueError: an argument is not a real array of the right
            shape, or holds a non-finite value (named).
        rps3.errors.Rps3Error: a state failed (check_status).
    """
    lens, single = points3(l, "l")
    rates, _ = points3(dl, "dl")
    force, _ = points3(F, "F")
    same_shape(rates, lens, "dl", "l", dl, l)
    same_shape(force, lens, "F", "l", F, l)
    n = lens.shape[1]
    out = results(n, {"ddl": (3,), "pose": (3,), "dpose": (3,), "theta": (3,),
                      "dtheta": (3,), "ddtheta": (3,), "Mq": (3, 3),
                      "hq": (3,), "Mcond": (), "T": (), "P": ()},
                  ("mode", "status"))
    d = model._workspace()
    msg = ffi.new("char[320]")
    nfail = lib.rps3py_fwddyn_n(
        model._c, d, n, buf(lens), buf(rates), buf(force),
        *(buf(out[k]) for k in ("ddl", "pose", "dpose", "theta", "dtheta",
                                "ddtheta", "Mq", "hq", "Mcond", "T", "P")),
        buf(out["mode"], "int[]"), buf(out["status"], "int[]"), msg, 320)
    if check_status and nfail:
        first = int(np.flatnonzero(out["status"])[0])
        check(int(out["status"][first]), msg)
    return Forward(**{k: per_point(v, single) for k, v in out.items()},
                   message=_message(msg, nfail))
