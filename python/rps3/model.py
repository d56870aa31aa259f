"""rps3.Model: the manipulator, validated once, and its per-point stages
over arrays of points (the loop runs in C, in the library's batch entry
points)."""

from __future__ import annotations

import difflib
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from rps3._core import (
    FloatArray,
    IntArray,
    buf,
    check_error,
    motion_points,
    per_point,
    points,
    results,
    text,
)
from rps3._rps3 import ffi, lib
from rps3.body import Body, _as_body, _number, _vector

#: names of the physical effects, in the library's order (bit k = 1 << k)
EFFECTS: tuple[str, ...] = tuple(text(lib.rps3_effect_name(k))
                                 for k in range(lib.RPS3_NEFFECT))

#: the paper's selection: gravity and inertia of platform and links
DEFAULT_EFFECTS: tuple[str, ...] = tuple(
    n for k, n in enumerate(EFFECTS) if lib.RPS3_EFF_DEFAULT & (1 << k))

_METHODS = {"lagrange": lib.RPS3_LAGRANGE,
            "newton_euler": lib.RPS3_NEWTON_EULER}
_THETA = {"closed_form": lib.RPS3_THETA_CLOSED_FORM,
          "multiroot": lib.RPS3_THETA_MULTIROOT}
#: names of the results ``inverse`` can compute (the library's
#: ``RPS3_OUT_*`` bits, include/rps3.h enum rps3_output), all by default
OUTPUTS: tuple[str, ...] = tuple(text(lib.rps3_output_name(k))
                                 for k in range(lib.RPS3_NOUTPUT))

# the library's dotted field names -> Model's keyword arguments
_KEYWORD = {"payload.mass": "payload", "payload.com": "payload",
            "payload.inertia": "payload", "pin_friction.viscous": "friction",
            "pin_friction.coulomb": "friction",
            "pin_friction.vreg": "friction"}
_KEYWORD.update({f"{b}.{k}": "bodies" for b in
                 ("platform", "leg1.cylinder", "leg1.piston", "leg2.cylinder",
                  "leg2.piston", "leg3.cylinder", "leg3.piston")
                 for k in ("mass", "com", "inertia")})
_KEYWORD.update({f"leg{i}.{kind}.{k}": arg for i in (1, 2, 3)
                 for kind, arg in (("pin_friction", "friction"),
                                   ("prismatic_friction", "prismatic_friction"))
                 for k in ("viscous", "coulomb", "vreg")})
#: the Model arguments of the paper's bodies, which general bodies replace
_PAPER_BODY_ARGS = ("M", "m_over_M", "m", "d", "link_Ic")
@dataclass(frozen=True)
class Kinematics:
    """Result of Model.ik: per point (leading axis n, absent for one point)."""

    l: FloatArray          #: link lengths l_i, (n, 3) [m]
    theta: FloatArray      #: link angles theta_i from the base plane, (n, 3) [rad]
    status: IntArray       #: rps3 status code per point, 0 = ok (rps3.strerror)
    warn: IntArray         #: warning bits per point

    @property
    def ok(self) -> np.ndarray:
        """Boolean mask of the points that succeeded."""
        return np.asarray(self.status) == 0


@dataclass(frozen=True)
class Pose:
    """Result of Model.fk: per point (leading axis n, absent for one point)."""

    pose: FloatArray       #: (alpha, beta, z_c), (n, 3) [rad, rad, m]
    theta: FloatArray      #: link angles theta_i, (n, 3) [rad]
    niter: IntArray        #: iterations of the theta solve per point
    status: IntArray       #: rps3 status code per point, 0 = ok
    warn: IntArray         #: warning bits (2: beta ~ 0, alpha set to 0)

    @property
    def ok(self) -> np.ndarray:
        """Boolean mask of the points that succeeded."""
        return np.asarray(self.status) == 0


@dataclass(frozen=True)
class Dynamics:
    """Result of Model.inverse: per point (leading axis n, absent for one
    point).  Failed points hold NaN; their status says why."""

    force: FloatArray      #: actuating forces F_i, (n, 3) [N], > 0 extends
    shares: dict[str, FloatArray]  #: share of each selected effect in force, (n, 3) [N]
    lambda_: FloatArray    #: multipliers of (8)-(10), (n, 3) [N/m]; NaN under newton_euler
    condition: FloatArray  #: 1-norm condition number of the lambda system, (n,)
    transmission: FloatArray  #: force transmission (n,): largest |F_i| per unit platform load [-]
    energy_residual: FloatArray  #: energy-rate residual (n,) [W]; NaN without the output "certify"
    l: FloatArray          #: link lengths, (n, 3) [m]
    theta: FloatArray      #: link angles, (n, 3) [rad]
    status: IntArray       #: rps3 status code per point, 0 = ok
    warn: IntArray         #: warning bits (1: ill-conditioned lambda system)

    @property
    def ok(self) -> np.ndarray:
        """Boolean mask of the points that succeeded."""
        return np.asarray(self.status) == 0


def _effect_bits(effects: Iterable[str]) -> int:
    return _name_bits(effects, "effects", "effect", EFFECTS)


def _name_bits(names: Iterable[str], arg: str, what: str,
               known: tuple[str, ...]) -> int:
    if isinstance(names, str):
        raise ValueError(f"{arg}: expected a list of names, got {names!r}")
    bits = 0
    for name in names:
        k = known.index(name) if name in known else -1
        if k < 0:
            close = difflib.get_close_matches(str(name), known, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise ValueError(f"{arg}: unknown {what} {name!r}{hint}; known: "
                             f"{', '.join(known)}")
        if bits & (1 << k):
            raise ValueError(f"{arg}: {name!r} is given twice")
        bits |= 1 << k
    return bits


def _choice(table: dict[str, int], value: str, name: str) -> int:
    if not isinstance(value, str):
        raise TypeError(f"{name}: expected one of {', '.join(table)}, got {value!r}")
    if value not in table:
        raise ValueError(f"{name}: {value!r} is not one of {', '.join(table)}")
    return table[value]


def _per_leg(value: Any, name: str) -> list[Any]:
    """One value for the three legs, or a sequence of three."""
    if isinstance(value, (list, tuple)):
        if len(value) != 3:
            raise ValueError(f"{name}: expected one value for every leg or a "
                             f"list of three, got {len(value)}")
        return list(value)
    return [value] * 3


class Model:
    """The manipulator of Lee & Shah (1988), validated once, then read-only.

    Every argument is keyword-only and optional; an argument left out takes
    the library's default, the paper's Table II: R = 0.2286 m, rho = 0.5,
    M = 0.18 kg, m/M = 0.5, d = 0.1524 m, g = 9.80665 m/s^2, no payload, no
    friction, the paper's effects (gravity and inertia of platform and
    links), the Lagrange formulation, theta in closed form.

    Args:
        R: base radius, centre to the pin joints [m].
        rho: r / R, r the platform radius to the ball joints [-].
        M: platform mass, a uniform disc of radius r [kg].
        m_over_M: link mass over platform mass [-] (or give ``m``).
        m: mass of each link [kg] (or give ``m_over_M``).
        d: pin joint to link centroid [m].
        link_Ic: moment of inertia of a link about its centroid [kg m^2].
        g: gravitational acceleration, along -Z [m/s^2].
        payload: ``{"mass": kg, "com": [m]*3, "inertia": [kg m^2]*3}``, a
            rigid payload on the platform (select the ``payload`` effect).
        friction: ``{"viscous": N m s/rad, "coulomb": N m, "vreg": rad/s}``
            at the pins (select the ``pin_friction`` effect; vreg > 0
            regularises the Coulomb sign, include/rps3.h rps3_friction);
            with general bodies also a list of three, one per leg.
        prismatic_friction: ``{"viscous": N s/m, "coulomb": N, "vreg":
            m/s}`` in the prismatic joints, the force each actuator
            overcomes (select the ``prismatic_friction`` effect), or a
            list of three, one per leg; either bodies.
        bodies: ``"paper"`` (default: the disc platform M, links m at d
            with link_Ic, massless pistons) or the general bodies, a dict
            of :class:`Body` (or dicts of mass, com, inertia):
            ``platform``, and either ``cylinder`` and ``piston`` (three
            identical legs, each in its own axes) or ``legs``, a list of
            three dicts of ``cylinder`` and ``piston`` (a key a leg leaves
            out takes the top-level one); a body left out is massless.
            General bodies replace M, m (m_over_M), d and link_Ic, which
            must then be left out.
        effects: names of the effects to compute, from ``rps3.EFFECTS``.
        method: ``"lagrange"`` (the paper's) or ``"newton_euler"``.
        theta: ``"closed_form"`` (39) or ``"multiroot"`` (8)-(10) in
            ``inverse``.
        solver: GSL multiroot solver of the theta solve, e.g. ``"hybridsj"``.
        tol: theta solve tolerance on the dimensionless (8)-(10) [-].
        max_iter: theta solve iteration limit.
        warm_start: start each theta solve from the previous point's.
        cond_warn: condition number above which a point is flagged [-].
        cond_max: condition number above which a point fails [-].
        outputs: names of the results ``inverse`` computes, from
            ``rps3.OUTPUTS`` (default: all): ``"forces"``, ``"effects"``
            (the per-effect shares), ``"theta"``, ``"lambda"``,
            ``"transmission"``, ``"certify"`` (the energy-rate residual).
            The results left out are NaN; the checks (status, warn) do not
            depend on them.  ``["forces"]`` alone is the library's leanest
            pass (docs/library.md).

    Raises:
        ValueError: naming the argument, when a value is out of range or an
            unknown name.
        TypeError: naming the argument, when a value is not a real number
            (complex, a string, an object) or a name is not a string.

    The stages take (n, 3) arrays of real numbers (TypeError naming the
    argument for complex, string, boolean or object arrays, which would
    otherwise lose their imaginary part or be parsed) of any layout and
    never modify them; a
    float64 array in Fortran order (as the trajectories and the results
    are) reaches the library without a copy, others are copied into that
    layout first.  The results are new arrays (views of one block per
    call), Fortran-ordered (n, 3).
    """

    def __init__(self, *, R: float | None = None, rho: float | None = None,
                 M: float | None = None, m_over_M: float | None = None,
                 m: float | None = None, d: float | None = None,
                 link_Ic: float | None = None, g: float | None = None,
                 payload: dict[str, Any] | None = None,
                 friction: dict[str, Any] | Sequence[dict[str, Any]] | None = None,
                 prismatic_friction: dict[str, Any] | Sequence[dict[str, Any]]
                 | None = None,
                 bodies: str | dict[str, Any] | None = None,
                 effects: Sequence[str] | None = None,
                 method: str | None = None, theta: str | None = None,
                 solver: str | None = None, tol: float | None = None,
                 max_iter: int | None = None, warm_start: bool | None = None,
                 cond_warn: float | None = None,
                 cond_max: float | None = None,
                 outputs: Sequence[str] | None = None) -> None:
        c = ffi.new("rps3_model *")
        lib.rps3_model_default(c)
        keyword = dict(_KEYWORD)
        general = bodies is not None and not (isinstance(bodies, str)
                                              and bodies == "paper")
        if general:
            given = dict(M=M, m_over_M=m_over_M, m=m, d=d, link_Ic=link_Ic)
            for name in _PAPER_BODY_ARGS:
                if given[name] is not None:
                    raise ValueError(f"{name}: the paper's bodies' parameter, "
                                     "with general bodies: give it in bodies")
            self._bodies(c, bodies)
        default_ratio = c.m / c.M  # Table II's m/M
        for name, value in (("R", R), ("rho", rho), ("M", M), ("d", d),
                            ("link_Ic", link_Ic), ("g", g)):
            if value is not None:
                setattr(c, name, _number(value, name))
        if m is not None and m_over_M is not None:
            raise ValueError("m_over_M: give m or m_over_M, not both")
        if m is not None:
            c.m = _number(m, "m")
        else:
            # the paper gives m/M: with M alone, the links keep Table II's m/M
            ratio = (default_ratio if m_over_M is None
                     else _number(m_over_M, "m_over_M"))
            c.m = ratio * c.M
            keyword["m"] = "m_over_M"
        if payload is not None:
            self._payload(c, payload)
        if friction is not None:
            laws = _per_leg(friction, "friction")
            if not general and isinstance(friction, (list, tuple)):
                raise ValueError("friction: one law per leg needs general bodies "
                                 "(the paper's legs share one)")
            if general:
                for i, law in enumerate(laws):
                    self._friction(c.leg[i].pin, law, "friction")
            else:
                self._friction(c.friction, laws[0], "friction")
        if prismatic_friction is not None:
            for i, law in enumerate(_per_leg(prismatic_friction, "prismatic_friction")):
                self._friction(c.leg[i].prismatic, law, "prismatic_friction")
        o = c.opt
        if effects is not None:
            o.effects = _effect_bits(effects)
        if method is not None:
            o.method = _choice(_METHODS, method, "method")
        if theta is not None:
            o.theta = _choice(_THETA, theta, "theta")
        if outputs is not None:
            o.outputs = _name_bits(outputs, "outputs", "output", OUTPUTS)
        if solver is not None:
            k = lib.rps3_solver_index(str(solver).encode())
            if k < 0:
                raise ValueError(f"solver: unknown solver {solver!r}")
            o.solver = k
        for name, fval in (("tol", tol), ("cond_warn", cond_warn),
                           ("cond_max", cond_max)):
            if fval is not None:
                setattr(o, name, _number(fval, name))
        for name, ival in (("max_iter", max_iter), ("warm_start", warm_start)):
            if ival is not None:
                num = _number(ival, name)
                if num != int(num) or abs(num) > 2**31 - 1:
                    raise ValueError(f"{name}: expected an integer, got {ival!r}")
                setattr(o, name, int(num))
        chk = ffi.new("rps3_check *")
        if lib.rps3_model_init(c, chk) != lib.RPS3_OK:
            raise check_error(chk, keyword)
        self._c = c

    @staticmethod
    def _payload(c: Any, payload: dict[str, Any]) -> None:
        unknown = set(payload) - {"mass", "com", "inertia"}
        if unknown:
            raise ValueError(f"payload: unknown keys {sorted(unknown)}")
        if "mass" in payload:
            c.payload.mass = _number(payload["mass"], "payload")
        for key in ("com", "inertia"):
            if key in payload:
                for i, x in enumerate(_vector(payload[key], "payload")):
                    getattr(c.payload, key)[i] = x

    @staticmethod
    def _friction(law: Any, friction: dict[str, Any], arg: str) -> None:
        if not isinstance(friction, dict):
            raise TypeError(f"{arg}: expected a dict of viscous, coulomb, vreg, "
                            f"got {friction!r}")
        unknown = set(friction) - {"viscous", "coulomb", "vreg"}
        if unknown:
            raise ValueError(f"{arg}: unknown keys {sorted(unknown)}")
        for key in ("viscous", "coulomb", "vreg"):
            if key in friction:
                setattr(law, key, _number(friction[key], arg))

    @staticmethod
    def _bodies(c: Any, bodies: Any) -> None:
        if not isinstance(bodies, dict):
            raise (ValueError if isinstance(bodies, str) else TypeError)(
                f"bodies: expected 'paper' or a dict of bodies, got {bodies!r}")
        unknown = set(bodies) - {"platform", "cylinder", "piston", "legs"}
        if unknown:
            raise ValueError(f"bodies: unknown keys {sorted(unknown)}; known: "
                             "platform, cylinder, piston, legs")
        c.bodies = lib.RPS3_BODIES_GENERAL
        _as_body(bodies.get("platform", Body()), "bodies.platform")._set(c.platform)
        legs = bodies.get("legs")
        if legs is None:
            legs = [{}] * 3
        if not isinstance(legs, (list, tuple)) or len(legs) != 3:
            raise ValueError(f"bodies.legs: expected a list of three dicts, got {legs!r}")
        for i, leg in enumerate(legs):
            if not isinstance(leg, dict) or set(leg) - {"cylinder", "piston"}:
                raise ValueError(f"bodies.legs[{i}]: expected a dict of cylinder "
                                 f"and piston, got {leg!r}")
            for part in ("cylinder", "piston"):
                where = f"bodies.legs[{i}].{part}" if part in leg else f"bodies.{part}"
                b = _as_body(leg.get(part, bodies.get(part, Body())), where)
                b._set(getattr(c.leg[i], part))

    # ------------------------------------------------------------ reading

    @property
    def effects(self) -> tuple[str, ...]:
        """Names of the selected effects, in the library's order."""
        return tuple(n for k, n in enumerate(EFFECTS)
                     if self._c.opt.effects & (1 << k))

    @property
    def outputs(self) -> tuple[str, ...]:
        """Names of the results ``inverse`` computes, in the library's order."""
        return tuple(n for k, n in enumerate(OUTPUTS)
                     if self._c.opt.outputs & (1 << k))

    @property
    def bodies(self) -> str | dict[str, Any]:
        """``"paper"``, or the general bodies as read back from the
        library: ``{"platform": Body, "legs": [{"cylinder": Body,
        "piston": Body}, ...]}``."""
        c = self._c
        if c.bodies != lib.RPS3_BODIES_GENERAL:
            return "paper"
        return {"platform": Body._get(c.platform),
                "legs": [{"cylinder": Body._get(c.leg[i].cylinder),
                          "piston": Body._get(c.leg[i].piston)} for i in range(3)]}

    def __getattr__(self, name: str) -> float:
        # the model's numbers, read from the validated C structure
        if name in ("R", "rho", "M", "m", "d", "link_Ic", "g", "r"):
            return float(getattr(self.__dict__["_c"], name))
        raise AttributeError(name)

    def __repr__(self) -> str:
        if self._c.bodies == lib.RPS3_BODIES_GENERAL:
            return (f"rps3.Model(R={self.R!r}, rho={self.rho!r}, bodies='general', "
                    f"effects={list(self.effects)!r})")
        return (f"rps3.Model(R={self.R!r}, rho={self.rho!r}, M={self.M!r}, "
                f"m={self.m!r}, d={self.d!r}, effects={list(self.effects)!r})")

    # ------------------------------------------------------------- stages

    def _workspace(self) -> Any:
        # one workspace per call: calls from several threads never share one
        out = ffi.new("rps3_data **")
        status = lib.rps3_data_alloc(self._c, out)
        if status == lib.RPS3_ENOMEM:
            raise MemoryError("rps3_data_alloc: out of memory")
        if status != lib.RPS3_OK:
            raise RuntimeError(f"rps3_data_alloc failed with status {status}")
        return ffi.gc(out[0], lib.rps3_data_free)

    def _run(self, fn: Any, inputs: dict[str, Any], outputs: dict[str, Any],
             n: int) -> None:
        d = self._workspace()
        cin = ffi.new("rps3_batch_in *")
        cout = ffi.new("rps3_batch_out *")
        cin.n = n
        keep = []  # the buffers must live through the call
        for name, a in inputs.items():
            keep.append(buf(a))
            setattr(cin, name, keep[-1])
        for name, a in outputs.items():
            keep.append(buf(a, "int[]" if a.dtype == np.int32 else "double[]"))
            setattr(cout, name, keep[-1])
        status = fn(self._c, d, cin, cout)
        if status != lib.RPS3_OK:  # a call the checks above let through
            raise RuntimeError(text(d.err.msg))

    def ik(self, pose: ArrayLike) -> Kinematics:
        """Inverse kinematics, eqs. (2)-(7) and (39).

        Args:
            pose: (n, 3) or (3,) array of (alpha, beta, z_c) [rad, rad, m].

        Returns:
            Kinematics: link lengths [m] and angles [rad] per point, status.
        """
        p, single = points(pose, "pose")
        n = p.shape[1]
        out = results(n, {"l": (3,), "theta": (3,)}, ("status", "warn"))
        self._run(lib.rps3_ik_batch, {"pose": p}, out, n)
        return Kinematics(**{k: per_point(v, single) for k, v in out.items()})

    def fk(self, lengths: ArrayLike, guess: ArrayLike | None = None) -> Pose:
        """Forward kinematics: link lengths -> theta (8)-(10) -> pose.

        Args:
            lengths: (n, 3) or (3,) link lengths [m].
            guess: theta [rad] to start each point's solve from, same shape;
                None: each solve starts from the previous point's solution
                (warm_start) or from the level-platform guess.

        Returns:
            Pose: (alpha, beta, z_c) [rad, rad, m], theta, iterations, status.
        """
        lens, single = points(lengths, "lengths")
        n = lens.shape[1]
        inputs: dict[str, Any] = {"l": lens}
        if guess is not None:
            g, _ = points(guess, "guess")
            if g.shape != lens.shape:
                raise ValueError(f"guess: shape {np.shape(guess)} differs from "
                                 f"that of lengths {np.shape(lengths)}")
            inputs["guess"] = g
        out = results(n, {"pose": (3,), "theta": (3,)},
                      ("niter", "status", "warn"))
        self._run(lib.rps3_fk_batch, inputs, out, n)
        return Pose(**{k: per_point(v, single) for k, v in out.items()})

    def inverse(self, pose: ArrayLike, dpose: ArrayLike | None = None,
                ddpose: ArrayLike | None = None) -> Dynamics:
        """Inverse dynamics, eqs. (21)-(24) and (34), of the selected effects.

        Args:
            pose: (n, 3) or (3,) array of (alpha, beta, z_c) [rad, rad, m].
            dpose: its time derivative [rad/s, rad/s, m/s], same shape;
                needed when an inertial effect or the output "certify" is
                selected.
            ddpose: second derivative [rad/s^2, rad/s^2, m/s^2], same shape.

        Returns:
            Dynamics: forces [N], per-effect shares [N], lambda [N/m],
            condition number, transmission, energy residual [W], l, theta,
            status, warn.

        Raises:
            ValueError: a shape is wrong, or rates are needed and missing.
        """
        p, single, given = motion_points(pose, dpose, ddpose)
        n = p.shape[1]
        inputs: dict[str, Any] = {"pose": p, **given}
        needs = ((self._c.opt.effects & lib.RPS3_EFF_DYNAMIC)
                 or (self._c.opt.outputs & lib.RPS3_OUT_CERTIFY))
        missing = [k for k in ("dpose", "ddpose") if k not in inputs]
        if needs and missing and n > 0:
            raise ValueError(f"{missing[0]}: needed by the effects "
                             f"{list(self.effects)} or the output 'certify', "
                             "and not given")
        out = results(n, {"F": (3,), "F_effect": (lib.RPS3_NEFFECT, 3),
                          "lambda": (3,), "cond": (), "transmission": (),
                          "energy_residual": (),
                          "l": (3,), "theta": (3,)}, ("status", "warn"))
        self._run(lib.rps3_inverse_batch, inputs, out, n)
        shares = {name: per_point(out["F_effect"][k], single)
                  for k, name in enumerate(EFFECTS) if name in self.effects}
        return Dynamics(
            force=per_point(out["F"], single), shares=shares,
            lambda_=per_point(out["lambda"], single),
            condition=per_point(out["cond"], single),
            transmission=per_point(out["transmission"], single),
            energy_residual=per_point(out["energy_residual"], single),
            l=per_point(out["l"], single), theta=per_point(out["theta"], single),
            status=per_point(out["status"], single),
            warn=per_point(out["warn"], single))
