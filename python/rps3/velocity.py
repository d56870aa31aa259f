"""Velocities, accelerations and Jacobians of the manipulator over arrays of
points, in one C call each (include/rps3.h: rps3_velocity,
rps3_acceleration, rps3_joint_velocity, rps3_joint_acceleration).

    model = rps3.Model()
    v = rps3.velocity.pose_rates(model, pose, dpose, ddpose)   # -> dl, ddl, ...
    w = rps3.velocity.joint_rates(model, l, dl)                # -> pose, dpose, ...
    J = rps3.velocity.jacobian(model, pose)                    # dl/dpose (n, 3, 3)
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

_MSG = 320


@dataclass(frozen=True)
class Motion:
    """The joint and Cartesian motion of points (leading axis n, absent for
    one point); the rate and acceleration fields are NaN where their inputs
    were not given, and every field NaN for a failed point."""

    pose: FloatArray     #: (alpha, beta, z_c), (n, 3) [rad, rad, m]
    l: FloatArray        #: link lengths, (n, 3) [m]
    theta: FloatArray    #: link angles, (n, 3) [rad]
    c: FloatArray        #: platform centre (x_c, y_c, z_c), (n, 3) [m]
    dpose: FloatArray    #: pose rates, (n, 3) [rad/s, rad/s, m/s]
    dl: FloatArray       #: link rates, (n, 3) [m/s]
    dtheta: FloatArray   #: link angle rates, (n, 3) [rad/s]
    vc: FloatArray       #: platform centre velocity, base axes, (n, 3) [m/s]
    omega: FloatArray    #: platform angular velocity, base axes, (n, 3) [rad/s]
    ddl: FloatArray      #: link accelerations, (n, 3) [m/s^2]
    ddtheta: FloatArray  #: link angle accelerations, (n, 3) [rad/s^2]
    ac: FloatArray       #: platform centre acceleration, (n, 3) [m/s^2]
    domega: FloatArray   #: platform angular acceleration, (n, 3) [rad/s^2]
    status: IntArray     #: rps3 status code per point, 0 = ok
    message: str         #: "point I: ..." of the first failure, "" if none
    #: platform angular velocity in platform axes by the paper's (31)-(33)
    #: (errata), a second formulation: rot^T omega (pose_rates only), (n, 3) [rad/s]
    omega_body: FloatArray | None = None
    #: homogeneous transform (1) of the platform, (n, 4, 4) [-, m] (pose_rates only)
    transform: FloatArray | None = None

    @property
    def ok(self) -> np.ndarray:
        """Boolean mask of the points that succeeded."""
        return np.asarray(self.status) == 0


@dataclass(frozen=True)
class Jacobian:
    """The rate maps at poses, d(output)/d(alpha, beta, z_c): entry [i, r, k]
    is output r's rate per unit rate of pose coordinate k at point i
    (leading axis absent for one point)."""

    l: FloatArray        #: d l / d pose, (n, 3, 3) [m/rad, m/rad, 1]
    theta: FloatArray    #: d theta / d pose, (n, 3, 3) [1, 1, rad/m]
    vc: FloatArray       #: d vc / d pose rates, (n, 3, 3) [m/rad, m/rad, 1]
    omega: FloatArray    #: d omega / d pose rates, (n, 3, 3) [1, 1, rad/m]
    status: IntArray     #: rps3 status code per point, 0 = ok
    message: str         #: "point I: ..." of the first failure, "" if none


_FIELDS = ("pose", "l", "theta", "c", "dpose", "dl", "dtheta", "vc", "omega",
           "ddl", "ddtheta", "ac", "domega")


def _finish(out: dict[str, np.ndarray], single: bool, msg: Any, nfail: int,
            check_status: bool) -> dict[str, Any]:
    if check_status and nfail:
        first = int(np.flatnonzero(out["status"])[0])
        check(int(out["status"][first]), msg)
    res: dict[str, Any] = {k: per_point(v, single) for k, v in out.items()}
    res["message"] = ffi.string(msg).decode() if nfail else ""
    return res


def pose_rates(model: Model, pose: ArrayLike, dpose: ArrayLike | None = None,
               ddpose: ArrayLike | None = None, *,
               check_status: bool = True) -> Motion:
    """From the platform's motion to the links': inverse kinematics
    (2)-(7), (39), then the rate map (alpha', beta', z') -> (l', theta', vc,
    omega) and one order higher (rps3_ik, rps3_velocity,
    rps3_acceleration).

    Args:
        model: the manipulator.
        pose: (n, 3) or (3,) poses (alpha, beta, z_c) [rad, rad, m].
        dpose: their rates [rad/s, rad/s, m/s], same shape, or None.
        ddpose: accelerations [rad/s^2, rad/s^2, m/s^2] (with dpose), or None.
        check_status: raise the first failing point's exception
            (rps3.errors); False: statuses, NaN for failed points.

    Returns:
        Motion: l, theta, c, transform; with dpose dl, dtheta, vc, omega,
        omega_body; with ddpose ddl, ddtheta, ac, domega (NaN otherwise).
    """
    p, single = points3(pose, "pose")
    inputs = [p, None, None]
    for k, (name, value) in enumerate((("dpose", dpose), ("ddpose", ddpose))):
        if value is None:
            continue
        if k == 1 and dpose is None:
            raise ValueError("ddpose: accelerations need the rates (dpose)")
        v, _ = points3(value, name)
        same_shape(v, p, name, "pose", value, pose)
        inputs[k + 1] = v
    n = p.shape[1]
    out = results(n, {**{f: (3,) for f in _FIELDS}, "omega_body": (3,),
                      "transform": (4, 4)}, ("status",))
    out["pose"][...] = p
    out["omega_body"][...] = np.nan
    for f in (("dpose",) if inputs[1] is not None else ()):
        out[f][...] = inputs[1]
    if inputs[1] is None:
        out["dpose"][...] = np.nan
    for f in ("dl", "dtheta", "vc", "omega", "ddl", "ddtheta", "ac", "domega"):
        out[f][...] = np.nan
    d = model._workspace()
    msg = ffi.new(f"char[{_MSG}]")
    nfail = lib.rps3py_velocity_n(
        model._c, d, n, buf(p), buf(inputs[1]), buf(inputs[2]),
        *(buf(out[k]) for k in ("l", "theta", "c", "dl", "dtheta", "vc",
                                "omega", "ddl", "ddtheta", "ac", "domega",
                                "omega_body", "transform")),
        buf(out["status"], "int[]"), msg, _MSG)
    bad = out["status"] != 0
    out["pose"][:, bad] = np.nan
    out["dpose"][:, bad] = np.nan
    return Motion(**_finish(out, single, msg, nfail, check_status))


def joint_rates(model: Model, l: ArrayLike, dl: ArrayLike | None = None,
                ddl: ArrayLike | None = None, *,
                check_status: bool = True) -> Motion:
    """From the links' motion to the platform's: forward kinematics (the
    theta solve (8)-(10)), then the joint-rate route (25)-(30) and one
    order higher (rps3_fk, rps3_joint_velocity, rps3_joint_acceleration).
    The points are solved in order with one workspace: each theta solve
    starts from the previous point's root when the model's warm_start is
    on.

    Args:
        model: the manipulator.
        l: (n, 3) or (3,) link lengths [m].
        dl: link rates [m/s], same shape, or None.
        ddl: link accelerations [m/s^2] (with dl), or None.
        check_status: raise the first failing point's exception; False:
            statuses, NaN for failed points.

    Returns:
        Motion: pose, theta, c; with dl dpose, dtheta, vc, omega; with ddl
        ddtheta, ac, domega (NaN otherwise; ddpose is not computed by the
        library's joint route).
    """
    lens, single = points3(l, "l")
    inputs = [lens, None, None]
    for k, (name, value) in enumerate((("dl", dl), ("ddl", ddl))):
        if value is None:
            continue
        if k == 1 and dl is None:
            raise ValueError("ddl: accelerations need the rates (dl)")
        v, _ = points3(value, name)
        same_shape(v, lens, name, "l", value, l)
        inputs[k + 1] = v
    n = lens.shape[1]
    out = results(n, {f: (3,) for f in _FIELDS}, ("status",))
    for f in ("dpose", "dtheta", "vc", "omega", "ddtheta", "ac", "domega"):
        out[f][...] = np.nan
    out["l"][...] = lens
    out["dl"][...] = np.nan if inputs[1] is None else inputs[1]
    out["ddl"][...] = np.nan if inputs[2] is None else inputs[2]
    d = model._workspace()
    msg = ffi.new(f"char[{_MSG}]")
    nfail = lib.rps3py_joint_velocity_n(
        model._c, d, n, buf(lens), buf(inputs[1]), buf(inputs[2]),
        *(buf(out[k]) for k in ("pose", "theta", "c", "dpose", "dtheta", "vc",
                                "omega", "ddtheta", "ac", "domega")),
        buf(out["status"], "int[]"), msg, _MSG)
    bad = out["status"] != 0
    for f in ("l", "dl", "ddl"):
        out[f][:, bad] = np.nan
    return Motion(**_finish(out, single, msg, nfail, check_status))


def jacobian(model: Model, pose: ArrayLike, *,
             check_status: bool = True) -> Jacobian:
    """The rate maps at poses as matrices: d l / d pose, d theta / d pose
    and the platform's velocity per unit pose rate (the maps of
    rps3_velocity, linear in the pose rates: column k is the output for
    the unit rate of coordinate k, exact).  The joint-space inverse,
    d pose / d l, is ``np.linalg.inv(J.l)`` away from singular poses.

    Args:
        model: the manipulator.
        pose: (n, 3) or (3,) poses (alpha, beta, z_c) [rad, rad, m].
        check_status: raise the first failing point's exception; False:
            statuses, NaN for failed points.

    Returns:
        Jacobian: (n, 3, 3) matrices l, theta, vc, omega, status.
    """
    p, single = points3(pose, "pose")
    n = p.shape[1]
    out = results(n, {"l": (3, 3), "theta": (3, 3), "vc": (3, 3),
                      "omega": (3, 3)}, ("status",))
    d = model._workspace()
    msg = ffi.new(f"char[{_MSG}]")
    nfail = lib.rps3py_jacobian_n(
        model._c, d, n, buf(p), *(buf(out[k]) for k in ("l", "theta", "vc",
                                                         "omega")),
        buf(out["status"], "int[]"), msg, _MSG)
    return Jacobian(**_finish(out, single, msg, nfail, check_status))
