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

import functools
import math
from dataclasses import dataclass, field
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
    [m/s^2], the Coulomb regularisation vreg [rad/s] (0: the exact sign)."""

    R: float = 0.2286
    rho: float = 0.5
    d: float = 0.1524
    g: float = 9.80665
    vreg: float = 0.0

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


# ----------------------------------------------------- exciting trajectories

@dataclass(frozen=True)
class Limits:
    """What an exciting trajectory must keep: link strokes [m], link rates
    [m/s] and accelerations [m/s^2], forces [N] under the nominal
    parameters, the force transmission [-] (Dynamics.transmission), and
    beta's range [rad]."""

    l_min: float = 0.25
    l_max: float = 0.40
    dl_max: float = 0.3
    ddl_max: float = 3.0
    F_max: float = 20.0
    transmission_max: float = 20.0
    beta_min: float = 0.02
    beta_max: float = 0.5


@dataclass(frozen=True)
class Fourier:
    """A finite Fourier series per pose coordinate (alpha, beta, z_c):
    q_k(t) = q0_k + sum_j a_kj / (w j) sin(w j t) - b_kj / (w j) cos(w j t),
    w = 2 pi f0: periodic with period 1 / f0, rates and accelerations in
    closed form.  a, b are (3, H) [rad/s, rad/s, m/s]."""

    q0: np.ndarray
    a: np.ndarray
    b: np.ndarray
    f0: float

    @property
    def harmonics(self) -> int:
        return int(self.a.shape[1])

    @property
    def period(self) -> float:
        return 1.0 / self.f0

    def eval(self, t: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """pose, dpose, ddpose (n, 3) at times t (n,) [s]."""
        ta = np.asarray(t, float).reshape(-1)
        w = 2 * np.pi * self.f0 * np.arange(1, self.harmonics + 1)
        s, c = np.sin(np.outer(ta, w)), np.cos(np.outer(ta, w))
        q = self.q0 + s @ (self.a / w).T - c @ (self.b / w).T
        dq = c @ self.a.T + s @ self.b.T
        ddq = -s @ (self.a * w).T + c @ (self.b * w).T
        return q, dq, ddq

    def vector(self) -> np.ndarray:
        return np.concatenate([self.a.ravel(), self.b.ravel()])

    def with_vector(self, x: ArrayLike) -> Fourier:
        xa = np.asarray(x, float)
        n = 3 * self.harmonics
        return Fourier(self.q0, xa[:n].reshape(3, -1), xa[n:].reshape(3, -1), self.f0)


@dataclass(frozen=True)
class Excitation:
    """An optimised exciting trajectory and how it was found."""

    fourier: Fourier
    criterion: str           #: "cond" or "logdet"
    cond: float              #: condition number of the column-scaled base regressor
    logdet: float            #: log det of its (Y^T Y / N), columns scaled to unit RMS
    cond_start: float        #: the condition number at the starting point
    logdet_start: float      #: log det at the starting point
    converged: bool          #: the optimiser's success flag
    message: str             #: the optimiser's message
    seed: int
    nfev: int
    feasible: bool           #: every limit holds on the check grid
    base_names: tuple[str, ...]
    pset: PaperSet
    geometry: Geometry
    limits: Limits
    margins: dict[str, float] = field(default_factory=dict)  #: limit - peak
    layout: _id.Layout | None = None  #: the general layout designed for, or None


def _criteria(Yb: np.ndarray) -> tuple[float, float]:
    A = Yb.reshape(-1, Yb.shape[-1])
    A = A / np.sqrt(np.mean(A**2, axis=0)).clip(1e-300)
    sv = np.linalg.svd(A / math.sqrt(A.shape[0]), compute_uv=False)
    cond = float(sv[0] / sv[-1]) if sv[-1] > 0 else math.inf
    return cond, float(2 * np.log(sv.clip(1e-300)).sum())


@functools.lru_cache(maxsize=16)
def structural_base(geometry: Geometry | None = None, pset: PaperSet | None = None,
                    samples: int = 200, seed: int = 7) -> _id.Base:
    """The base parameters of the set at random states inside the
    workspace (beta in (0.05, 0.45) rad, z_c in (0.27, 0.36) m)."""
    rng = np.random.default_rng(seed)
    n = samples
    q = np.column_stack([rng.uniform(-np.pi, np.pi, n), rng.uniform(0.05, 0.45, n),
                         rng.uniform(0.27, 0.36, n)])
    dq = rng.normal(size=(n, 3)) * [1.0, 0.5, 0.05]
    ddq = rng.normal(size=(n, 3)) * [5.0, 2.0, 0.3]
    ps = pset or PaperSet()
    Y = paper_regressor(q, dq, ddq, geometry, ps)
    # a payload in the set: its parameters first, so M regroups into them
    return _id.base_parameters(Y, ps.names)


#: the body effects of the general model's regressor (its friction kinds
#: are the layout's)
_BODY_EFFECTS = ("platform_gravity", "link_gravity", "platform_inertia", "link_inertia")


def layout_regressor(pose: ArrayLike, dpose: ArrayLike, ddpose: ArrayLike,
                     geometry: Geometry | None = None,
                     layout: _id.Layout | None = None) -> np.ndarray:
    """Y (n, 3, layout.n) of a general layout's parameters at the poses,
    rates and accelerations (n, 3): the library's regressor of the 82
    standard parameters (rps3.ident.regressor_std, the geometry's R, rho,
    g, and vreg for both friction kinds) times ``layout.matrix``.

    Raises:
        ValueError: a point fails in the library (its message).
    """
    from rps3 import ident_c

    geo = geometry or Geometry()
    lay = layout or _id.Layout()
    fr = {"vreg": geo.vreg}
    m = Model(R=geo.R, rho=geo.rho, g=geo.g, friction=fr, prismatic_friction=fr,
              effects=list(_BODY_EFFECTS) + [f"{k}_friction" for k in lay.friction])
    return lay.regressor(ident_c.regressor_std(m, pose, dpose, ddpose))


@functools.lru_cache(maxsize=16)
def layout_base(geometry: Geometry | None = None, layout: _id.Layout | None = None,
                samples: int = 300, seed: int = 7) -> _id.Base:
    """The structural base parameters of a general layout at random states
    inside the workspace (as :func:`structural_base`)."""
    rng = np.random.default_rng(seed)
    n = samples
    q = np.column_stack([rng.uniform(-np.pi, np.pi, n), rng.uniform(0.05, 0.45, n),
                         rng.uniform(0.27, 0.36, n)])
    dq = rng.normal(size=(n, 3)) * [1.0, 0.5, 0.05]
    ddq = rng.normal(size=(n, 3)) * [5.0, 2.0, 0.3]
    lay = layout or _id.Layout()
    return _id.base_parameters(layout_regressor(q, dq, ddq, geometry, lay), lay.names)


def condition(fourier: Fourier, *, geometry: Geometry | None = None,
              pset: PaperSet | None = None, layout: _id.Layout | None = None,
              samples: int = 120) -> float:
    """The condition number of the column-scaled base regressor over one
    period of the series (``samples`` points): :func:`design`'s criterion
    "cond", of the paper set ``pset`` or of the general ``layout``."""
    geo = geometry or Geometry()
    t = np.linspace(0.0, fourier.period, samples, endpoint=False)
    q, dq, ddq = fourier.eval(t)
    if layout is not None:
        base = layout_base(geo, layout)
        Y = layout_regressor(q, dq, ddq, geo, layout)
    else:
        ps = pset or PaperSet()
        base = structural_base(geo, ps)
        Y = paper_regressor(q, dq, ddq, geo, ps)
    return _criteria(base.reduce(Y))[0]


def peaks(fourier: Fourier, geometry: Geometry, nominal: dict[str, Any],
          samples: int) -> dict[str, float]:
    """Each limited quantity's peak over one period."""
    t = np.linspace(0.0, fourier.period, samples, endpoint=False)
    q, dq, ddq = fourier.eval(t)
    from rps3 import velocity

    mdl = geometry.model(**nominal)
    res = mdl.inverse(q, dq, ddq)
    out = {"beta_min": float(q[:, 1].min()), "beta_max": float(q[:, 1].max())}
    if not np.all(res.ok):
        out["reach"] = 0.0
        return out
    mot = velocity.pose_rates(mdl, q, dq, ddq, check_status=False)
    out.update(l_min=float(np.nanmin(mot.l)), l_max=float(np.nanmax(mot.l)),
               dl_max=float(np.nanmax(np.abs(mot.dl))),
               ddl_max=float(np.nanmax(np.abs(mot.ddl))),
               F_max=float(np.nanmax(np.abs(res.force))),
               transmission_max=float(np.nanmax(res.transmission)))
    return out


def _margins(pk: dict[str, float], lim: Limits) -> dict[str, float]:
    if "reach" in pk:
        return {"reach": -1.0}
    return {"l_min": pk["l_min"] - lim.l_min, "l_max": lim.l_max - pk["l_max"],
            "dl_max": lim.dl_max - pk["dl_max"], "ddl_max": lim.ddl_max - pk["ddl_max"],
            "F_max": lim.F_max - pk["F_max"],
            "transmission_max": lim.transmission_max - pk["transmission_max"],
            "beta_min": pk["beta_min"] - lim.beta_min, "beta_max": lim.beta_max - pk["beta_max"]}


#: scales that make each margin of :func:`_margins` about 1 at the limit
def _margin_scale(lim: Limits) -> dict[str, float]:
    return {"l_min": lim.l_max - lim.l_min, "l_max": lim.l_max - lim.l_min,
            "dl_max": lim.dl_max, "ddl_max": lim.ddl_max, "F_max": lim.F_max,
            "transmission_max": lim.transmission_max,
            "beta_min": lim.beta_max - lim.beta_min, "beta_max": lim.beta_max - lim.beta_min,
            "reach": 1.0}


def random_fourier(q0: ArrayLike, amplitude: ArrayLike, f0: float, harmonics: int,
                   seed: int) -> Fourier:
    """A Fourier series of random coefficients (seeded) scaled so that each
    coordinate's peak excursion from q0 is ``amplitude`` (3,)."""
    rng = np.random.default_rng(seed)
    a = rng.normal(size=(3, harmonics))
    b = rng.normal(size=(3, harmonics))
    fo = Fourier(np.asarray(q0, float), a, b, f0)
    return scale_to(fo, amplitude)


def excursion(fo: Fourier, samples: int = 512) -> np.ndarray:
    q, _, _ = fo.eval(np.linspace(0.0, fo.period, samples, endpoint=False))
    return np.abs(q - fo.q0).max(axis=0)


def scale_to(fo: Fourier, amplitude: ArrayLike) -> Fourier:
    """fo with each coordinate's coefficients scaled to the peak excursion
    ``amplitude`` (3,) from q0."""
    s = np.asarray(amplitude, float) / excursion(fo).clip(1e-300)
    return Fourier(fo.q0, fo.a * s[:, None], fo.b * s[:, None], fo.f0)


def design(*, geometry: Geometry | None = None, pset: PaperSet | None = None,
           limits: Limits | None = None, nominal: dict[str, Any] | None = None,
           q0: ArrayLike = (0.0, 0.25, 0.31), amplitude: ArrayLike = (1.5, 0.12, 0.03),
           f0: float = 0.1, harmonics: int = 4, criterion: str = "cond",
           samples: int = 120, seed: int = 1, maxiter: int = 100,
           layout: _id.Layout | None = None, restarts: int = 0) -> Excitation:
    """An exciting trajectory: the Fourier coefficients (``harmonics`` per
    coordinate, base frequency f0 [Hz], about the pose q0) that minimise
    the condition number (``criterion="cond"``, as log cond) or maximise
    log det of the column-scaled base regressor over one period
    (``samples`` points) of the paper model's set ``pset``, or with
    ``layout`` of a general layout's base parameters (the library's
    regressor of the standard parameters, :func:`layout_regressor`),
    subject to :class:`Limits` (under the ``nominal``
    Model arguments, default Table II), by COBYLA (scipy.optimize,
    derivative-free: the limits are peaks over the samples) from a
    seeded random start scaled to ``amplitude``.  A start outside the
    limits is shrunk towards q0 until inside.  The result says whether the
    optimiser converged and whether the limits hold on a grid four times
    finer; it is returned either way, with a RuntimeWarning when the
    optimiser did not converge.

    Raises:
        ValueError: no feasible start (q0 outside the limits), an unknown
            criterion, or both pset and layout given.
    """
    if criterion not in ("cond", "logdet"):
        raise ValueError(f"criterion: expected 'cond' or 'logdet', got {criterion!r}")
    if layout is not None and pset is not None:
        raise ValueError("layout: give a paper set (pset) or a general layout, not both")
    opt = _id._need("scipy.optimize")
    geo = geometry or Geometry()
    ps = pset or PaperSet()
    lim = limits or Limits()
    nom = dict(nominal or {})
    base = structural_base(geo, ps) if layout is None else layout_base(geo, layout)
    start = random_fourier(q0, amplitude, f0, harmonics, seed)
    sc = _margin_scale(lim)
    for _ in range(30):
        if min(_margins(peaks(start, geo, nom, samples), lim).values()) > 0:
            break
        start = Fourier(start.q0, 0.7 * start.a, 0.7 * start.b, f0)
    else:
        raise ValueError(f"q0: no Fourier series about {np.asarray(q0).tolist()} "
                         "keeps the limits")
    t = np.linspace(0.0, start.period, samples, endpoint=False)

    def crit(fo: Fourier) -> tuple[float, float]:
        q, dq, ddq = fo.eval(t)
        try:
            Y = (paper_regressor(q, dq, ddq, geo, ps) if layout is None
                 else layout_regressor(q, dq, ddq, geo, layout))
        except ValueError:
            return math.inf, -math.inf
        return _criteria(base.reduce(Y))

    def objective(x: np.ndarray) -> float:
        c, ld = crit(start.with_vector(x))
        if criterion == "cond":
            return math.log(c) if math.isfinite(c) else 1e3
        return -ld if math.isfinite(ld) else 1e3

    names = list(_margins(peaks(start, geo, nom, samples), lim))

    def constraint(x: np.ndarray) -> np.ndarray:
        m = _margins(peaks(start.with_vector(x), geo, nom, samples), lim)
        return np.array([m.get(k, -1.0) / sc[k] for k in names])

    c0, ld0 = crit(start)
    # derivative-free: the limits are peaks over the samples (not smooth)
    x0 = start.vector()
    nfev = 0
    for _ in range(1 + restarts):
        # a restart begins a new trust region at the last point: COBYLA's
        # shrinks to tol about the first local optimum it meets
        res = opt.minimize(objective, x0, method="COBYLA",
                           constraints=[{"type": "ineq", "fun": constraint}],
                           options={"maxiter": maxiter, "tol": 1e-4,
                                    "rhobeg": 0.2 * float(np.abs(x0).mean())})
        nfev += int(res.nfev)
        if min(constraint(res.x)) < 0:
            break
        x0 = res.x
    best = start.with_vector(res.x)
    mg = _margins(peaks(best, geo, nom, 4 * samples), lim)
    if min(mg.values()) < 0:
        # COBYLA ends at a point its linear model of the limits allowed:
        # shrink towards q0 until it is inside on the fine grid
        for _ in range(20):
            best = Fourier(best.q0, 0.97 * best.a, 0.97 * best.b, f0)
            mg = _margins(peaks(best, geo, nom, 4 * samples), lim)
            if min(mg.values()) >= 0:
                break
    feasible = min(mg.values()) >= 0
    if not feasible and min(_margins(peaks(start, geo, nom, 4 * samples), lim).values()) >= 0:
        best, feasible = start, True          # keep the feasible start
        mg = _margins(peaks(best, geo, nom, 4 * samples), lim)
    c, ld = crit(best)
    if not res.success:
        import warnings

        warnings.warn(f"design: the optimiser did not converge ({res.message}); "
                      f"condition number {c:.3g} from {c0:.3g}", RuntimeWarning, stacklevel=2)
    return Excitation(best, criterion, c, ld, c0, ld0, bool(res.success), str(res.message),
                      seed, nfev, feasible, base.base_names, ps, geo, lim, mg,
                      layout)


def unoptimised(ex: Excitation, seeds: Any = range(10, 20),
                amplitude: ArrayLike | None = None, samples: int = 120) -> np.ndarray:
    """The condition numbers (:func:`condition`, of ex's set or layout) of
    random, unoptimised Fourier series (:func:`random_fourier`) with ex's
    q0, f0 and harmonics, one per seed, each coordinate's peak excursion
    ``amplitude`` (default: the optimised series' own): the reference the
    optimised ``ex.cond`` is compared with."""
    fo = ex.fourier
    amp = excursion(fo) if amplitude is None else np.asarray(amplitude, float)
    kw: dict[str, Any] = ({"layout": ex.layout} if ex.layout is not None
                          else {"pset": ex.pset})
    return np.array([condition(random_fourier(fo.q0, amp, fo.f0, fo.harmonics, s),
                               geometry=ex.geometry, samples=samples, **kw)
                     for s in seeds])


def write_table(path: str, fourier: Fourier, *, periods: int = 1, dt: float = 0.01,
                comment: str = "") -> None:
    """The trajectory as a table the runner plays (``trajectory.kind:
    table``, docs/trajectories.md): t, alpha, beta, z_c with their rates
    and accelerations (the quintic Hermite interpolant), every dt [s] over
    ``periods`` periods; CSV, or HDF5 (``.h5``/``.hdf5``, a ``units``
    attribute on each dataset)."""
    n = int(round(periods * fourier.period / dt)) + 1
    t = np.linspace(0.0, periods * fourier.period, n)
    q, dq, ddq = fourier.eval(t)
    cols = {"t": (t, "s")}
    for k, (nm, u) in enumerate((("alpha", "rad"), ("beta", "rad"), ("z_c", "m"))):
        cols[nm] = (q[:, k], u)
    for k, (nm, u) in enumerate((("alpha", "rad/s"), ("beta", "rad/s"), ("z_c", "m/s"))):
        cols[f"{nm}_dot"] = (dq[:, k], u)
    for k, (nm, u) in enumerate((("alpha", "rad/s^2"), ("beta", "rad/s^2"), ("z_c", "m/s^2"))):
        cols[f"{nm}_ddot"] = (ddq[:, k], u)
    if path.endswith((".h5", ".hdf5")):
        import h5py

        with h5py.File(path, "w") as f:
            f.attrs["Conventions"] = "CF-1.10"
            f.attrs["title"] = "rps3 exciting trajectory"
            if comment:
                f.attrs["comment"] = comment
            for nm, (v, u) in cols.items():
                ds = f.create_dataset(nm, data=v)
                ds.attrs["units"] = u
        return
    with open(path, "w", encoding="utf-8") as fh:
        for line in comment.splitlines():
            fh.write(f"# {line}\n")
        fh.write("# " + ", ".join(f"{nm} [{u}]" for nm, (_, u) in cols.items()) + "\n")
        fh.write(", ".join(cols) + "\n")
        data = np.column_stack([v for v, _ in cols.values()])
        np.savetxt(fh, data, delimiter=", ", fmt="%.17g")
