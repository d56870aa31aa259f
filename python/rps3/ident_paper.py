"""The paper model's regressor from the library's inverse dynamics, and
exciting trajectories for it or for a general layout's base parameters
(docs/identification.md, "The paper model's parameters" and "Exciting
trajectories").

The library's forces are linear in the paper model's inertia and friction
parameters at a fixed geometry (R, rho, d, g): each column of the
regressor is the force of one effect with a unit parameter
(``rps3.Model(...).inverse``), so the columns are the library's own
formulation, not a second one.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from rps3 import ident as _id
from rps3.model import Model

#: the paper model's linear parameters, in this order: platform mass M [kg]
#: (a uniform disc of radius r: its inertia M r^2 diag(1/4, 1/4, 1/2)),
#: each link's m d [kg m] (gravity) and m d^2 + link_Ic [kg m^2] (inertia
#: about the pin), a payload's mass [kg], first moment about the platform
#: centre [kg m] and inertia about the platform centre along the platform
#: axes [kg m^2], the pins' viscous [N m s/rad] and Coulomb [N m] friction
PAPER_NAMES: tuple[str, ...] = (
    "M", "md", "Ipin", "payload.m", "payload.mcx", "payload.mcy",
    "payload.mcz", "payload.Ixx", "payload.Iyy", "payload.Izz",
    "pin.fv", "pin.fc")
PAPER_UNITS: dict[str, str] = {
    "M": "kg", "md": "kg m", "Ipin": "kg m2", "payload.m": "kg",
    "payload.mcx": "kg m", "payload.mcy": "kg m", "payload.mcz": "kg m",
    "payload.Ixx": "kg m2", "payload.Iyy": "kg m2", "payload.Izz": "kg m2",
    "pin.fv": "N m s rad-1", "pin.fc": "N m"}


@dataclass(frozen=True)
class Geometry:
    """What the regressor takes as known: R [m], rho [-], d [m], g
    [m/s^2], the Coulomb regularisation vreg (0: the exact sign) of the
    pin friction [rad/s] and, unless ``vreg_prismatic`` [m/s] is given,
    of the prismatic friction (a general layout's) too."""

    R: float = 0.2286
    rho: float = 0.5
    d: float = 0.1524
    g: float = 9.80665
    vreg: float = 0.0
    vreg_prismatic: float | None = None

    def vreg_of(self, kind: str) -> float:
        """The regularisation of friction ``kind`` ("pin", "prismatic")."""
        if kind == "prismatic" and self.vreg_prismatic is not None:
            return self.vreg_prismatic
        return self.vreg

    def model(self, **kw: Any) -> Model:
        return Model(R=self.R, rho=self.rho, d=self.d, g=self.g, **kw)


@dataclass(frozen=True)
class PaperSet:
    """Which of the paper model's parameters are identified: the payload's
    seven (with which M is not separable: the payload's then hold the
    platform's disc as well, M keeps its given value) and the pin
    friction's two."""

    payload: bool = False
    friction: bool = True

    @property
    def names(self) -> tuple[str, ...]:
        out = [n for n in PAPER_NAMES
               if not (n.startswith("payload.") and not self.payload)
               and not (n.startswith("pin.") and not self.friction)]
        if self.payload:
            out.remove("M")
        return tuple(out)


def paper_parameters(*, M: float = 0.18, m: float = 0.09, d: float = 0.1524,
                     link_Ic: float = 0.0, R: float = 0.2286, rho: float = 0.5,
                     payload: dict[str, Any] | None = None,
                     friction: dict[str, float] | None = None,
                     pset: PaperSet | None = None) -> np.ndarray:
    """The parameters of ``pset`` (default PaperSet()) of a Model's
    arguments.  With a payload in the set, its parameters hold the
    platform's disc of mass M too."""
    ps = pset or PaperSet()
    v = {"M": M, "md": m * d, "Ipin": m * d * d + link_Ic}
    pay = _id.body_parameters(0.0)
    if ps.payload:
        r = rho * R
        pay = _id.body_parameters(M, inertia=[M * r**2 / 4, M * r**2 / 4, M * r**2 / 2])
    if payload:
        pay = pay + _id.body_parameters(payload.get("mass", 0.0), payload.get("com", (0, 0, 0)),
                                        payload.get("inertia", (0, 0, 0)))
    for k, n in enumerate(("m", "mcx", "mcy", "mcz")):
        v[f"payload.{n}"] = pay[k]
    v["payload.Ixx"], v["payload.Iyy"], v["payload.Izz"] = pay[4], pay[7], pay[9]
    fr = friction or {}
    v["pin.fv"], v["pin.fc"] = fr.get("viscous", 0.0), fr.get("coulomb", 0.0)
    return np.array([v[n] for n in ps.names])


#: payload offset used to extract the first-moment columns by a central
#: difference, exact since the force is quadratic in the offset [m]
_COM_STEP = 0.1


def paper_regressor(pose: ArrayLike, dpose: ArrayLike, ddpose: ArrayLike,
                    geometry: Geometry | None = None,
                    pset: PaperSet | None = None) -> np.ndarray:
    """Y (n, 3, p) of the paper model's parameters (``pset.names``) at the
    poses, rates and accelerations (n, 3), from the library's inverse
    dynamics: each column the forces [N] of one effect per unit parameter.

    Raises:
        ValueError: a point fails in the library (its status message).
    """
    geo = geometry or Geometry()
    ps = pset or PaperSet()
    q, dq, ddq = (np.asarray(a, float) for a in (pose, dpose, ddpose))

    def force(**kw: Any) -> np.ndarray:
        res = geo.model(**kw).inverse(q, dq, ddq)
        if not np.all(res.ok):
            k = int(np.flatnonzero(~res.ok)[0])
            raise ValueError(f"pose: point {k} {q[k].tolist()}: the inverse dynamics "
                             f"fail (status {int(res.status[k])})")
        return np.asarray(res.force, float)

    cols: dict[str, np.ndarray] = {}
    if "M" in ps.names:
        cols["M"] = force(M=1.0, m=0.0, effects=["platform_gravity", "platform_inertia"])
    cols["md"] = force(M=1.0, m=1.0, effects=["link_gravity"]) / geo.d
    cols["Ipin"] = force(M=1.0, m=0.0, link_Ic=1.0, effects=["link_inertia"])
    if ps.payload:
        def pay(mass: float, com: tuple[float, float, float] = (0.0, 0.0, 0.0),
                inertia: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> np.ndarray:
            return force(M=1.0, m=0.0, effects=["payload"],
                         payload={"mass": mass, "com": com, "inertia": inertia})
        cols["payload.m"] = pay(1.0)
        for k, ax in enumerate("xyz"):
            e = [0.0, 0.0, 0.0]
            e[k] = _COM_STEP
            plus = pay(1.0, (e[0], e[1], e[2]))
            minus = pay(1.0, (-e[0], -e[1], -e[2]))
            cols[f"payload.mc{ax}"] = (plus - minus) / (2 * _COM_STEP)
        # the library checks the triangle inequality of the principal
        # moments: each column the difference of two valid payloads
        ones = pay(0.0, inertia=(1.0, 1.0, 1.0))
        for k, ax in enumerate("xyz"):
            two = [1.0, 1.0, 1.0]
            two[k] = 2.0
            cols[f"payload.I{ax}{ax}"] = pay(0.0, inertia=(two[0], two[1], two[2])) - ones
    if ps.friction:
        fr = {"vreg": geo.vreg}
        cols["pin.fv"] = force(M=1.0, m=0.0, effects=["pin_friction"],
                               friction={**fr, "viscous": 1.0, "coulomb": 0.0})
        cols["pin.fc"] = force(M=1.0, m=0.0, effects=["pin_friction"],
                               friction={**fr, "viscous": 0.0, "coulomb": 1.0})
    return np.stack([cols[n] for n in ps.names], axis=-1)


def to_model_arguments(theta: ArrayLike, pset: PaperSet, *, d: float,
                       M: float = 0.18, R: float = 0.2286,
                       rho: float = 0.5) -> tuple[dict[str, Any] | None, str]:
    """rps3.Model's (and a scene's ``manipulator:``) arguments M, m, d,
    link_Ic, payload, friction from the set's parameters, with d (the
    geometry's) splitting m d and m d^2 + link_Ic; with a payload in the
    set M is the given one and the payload the rest.  Returns (arguments,
    "") or (None, why they do not map): a negative mass or moment, a
    payload with products of inertia about its centre of mass (the
    library's payload has principal moments along the platform axes)."""
    v = dict(zip(pset.names, np.asarray(theta, float)))
    m = v["md"] / d
    Ic = v["Ipin"] - m * d * d
    out: dict[str, Any] = {"M": float(v.get("M", M)), "m": float(m), "d": float(d),
                           "link_Ic": float(Ic)}
    why = []
    if m < 0:
        why.append(f"m = md / d = {m:.4g} kg < 0")
    if Ic < 0:
        why.append(f"link_Ic = Ipin - m d^2 = {Ic:.4g} kg m^2 < 0")
    if out["M"] <= 0:
        why.append(f"M = {out['M']:.4g} kg <= 0")
    if pset.payload:
        r = rho * R
        disc = _id.body_parameters(M, inertia=[M * r**2 / 4, M * r**2 / 4, M * r**2 / 2])
        mass = v["payload.m"] - disc[0]
        mc = np.array([v["payload.mcx"], v["payload.mcy"], v["payload.mcz"]]) - disc[1:4]
        I0 = np.array([v["payload.Ixx"], v["payload.Iyy"], v["payload.Izz"]]) - disc[[4, 7, 9]]
        if mass <= 0:
            why.append(f"payload mass = {mass:.4g} kg <= 0 beside the platform's M")
            com = np.zeros(3)
        else:
            com = mc / mass
        # about the centre of mass: I0 - mass (c.c - c_k^2); the products
        # mass c_j c_k would need principal axes off the platform's
        Ic3 = I0 - mass * (com @ com - com**2)
        prod = mass * abs(np.array([com[0] * com[1], com[0] * com[2], com[1] * com[2]]))
        if np.any(prod > 1e-3 * max(np.abs(Ic3).max(), 1e-300)):
            why.append("the payload's centre of mass is off the platform's axes: "
                       "its inertia about it has products the library's payload "
                       "(principal moments along the platform axes) cannot hold")
        if np.any(Ic3 < 0):
            why.append(f"payload principal moments {Ic3.tolist()} not all >= 0")
        out["payload"] = {"mass": float(mass), "com": com.tolist(), "inertia": Ic3.tolist()}
    if pset.friction:
        out["friction"] = {"viscous": float(v["pin.fv"]), "coulomb": float(v["pin.fc"])}
        if v["pin.fv"] < 0 or v["pin.fc"] < 0:
            why.append("a pin friction coefficient is negative")
    if why:
        return None, "; ".join(why)
    return out, ""


def standard_of(theta: ArrayLike, pset: PaperSet, *, d: float, M: float = 0.18,
                R: float = 0.2286, rho: float = 0.5) -> tuple[np.ndarray, _id.Layout] | None:
    """The 82 standard parameters (as a Layout with pin friction) of the
    set's parameters, via :func:`to_model_arguments`; None when they do
    not map."""
    args, _ = to_model_arguments(theta, pset, d=d, M=M, R=R, rho=rho)
    if args is None:
        return None
    lay = _id.Layout(legs="each", friction=("pin",))
    pi = _id.standard_parameters(R=R, rho=rho, M=args["M"], m=args["m"], d=d,
                                 link_Ic=args["link_Ic"], payload=args.get("payload"),
                                 pin_friction=args.get("friction"))
    return np.linalg.lstsq(lay.matrix, pi, rcond=None)[0], lay


#: the exciting trajectories, defined in rps3.ident_excite (which reads
#: this module's geometry and parameter sets)
_EXCITE = ("Excitation", "Fourier", "Limits", "_BODY_EFFECTS", "_criteria",
           "_margin_scale", "_margins", "condition", "design", "excursion",
           "layout_base", "layout_regressor", "peaks", "random_fourier", "sample_margins",
           "scale_to", "structural_base", "unoptimised", "write_table")


def __getattr__(name: str) -> Any:
    if name in _EXCITE:
        from rps3 import ident_excite
        return getattr(ident_excite, name)
    raise AttributeError(f"module 'rps3.ident_paper' has no attribute {name!r}")
