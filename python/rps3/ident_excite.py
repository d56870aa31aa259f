"""Exciting trajectories for identification (docs/identification.md,
"Exciting trajectories"): finite Fourier series optimised for the
conditioning of the column-scaled base regressor within the mechanism's
limits, for the paper model's parameter sets or a general layout on the
library's regressor; rps3.ident_paper re-exports every name."""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from rps3 import ident as _id
from rps3.ident_paper import Geometry, PaperSet, paper_regressor
from rps3.model import Model


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
    g, and each friction kind's vreg, Geometry.vreg_of) times
    ``layout.matrix``.

    Raises:
        ValueError: a point fails in the library (its message).
    """
    from rps3 import ident_c

    geo = geometry or Geometry()
    lay = layout or _id.Layout()
    m = Model(R=geo.R, rho=geo.rho, g=geo.g, friction={"vreg": geo.vreg_of("pin")},
              prismatic_friction={"vreg": geo.vreg_of("prismatic")},
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
           samples: int = 120, seed: int = 1, maxiter: int | None = None,
           layout: _id.Layout | None = None, restarts: int | None = None,
           method: str | None = None) -> Excitation:
    """An exciting trajectory: the Fourier coefficients (``harmonics`` per
    coordinate, base frequency f0 [Hz], about the pose q0) that minimise
    the condition number (``criterion="cond"``, as log cond) or maximise
    log det of the column-scaled base regressor over one period
    (``samples`` points) of the paper model's set ``pset``, or with
    ``layout`` of a general layout's base parameters (the library's
    regressor of the standard parameters, :func:`layout_regressor`),
    subject to :class:`Limits` (under the ``nominal``
    Model arguments, default Table II) from a seeded random start scaled
    to ``amplitude``.  A start outside the limits is shrunk towards q0
    until inside.

    ``method``: ``"slsqp"`` (the default with a layout; scipy.optimize's
    SLSQP, finite-difference gradients, every limit a constraint at each
    of ``2 samples`` points with 1 % of its range kept as slack: the
    criterion and the per-sample limits are smooth in the coefficients,
    their peaks are not; ``maxiter`` iterations, default 200, and, while
    SLSQP reports a failure, up to ``restarts`` further runs from the
    best iterate inside the limits so far, default 2) or ``"cobyla"``
    (the default for a paper set; derivative-free on the limits' peaks
    over the samples; ``maxiter`` evaluations, default 100, and
    ``restarts`` further runs, default 0).
    A final point outside the limits on a grid four times finer is shrunk
    towards q0 until inside.  The result says whether the optimiser
    converged and whether the limits hold on that grid; it is returned
    either way, with a RuntimeWarning when the optimiser did not converge.

    Raises:
        ValueError: no feasible start (q0 outside the limits), an unknown
            criterion or method, or both pset and layout given.
    """
    if criterion not in ("cond", "logdet"):
        raise ValueError(f"criterion: expected 'cond' or 'logdet', got {criterion!r}")
    if layout is not None and pset is not None:
        raise ValueError("layout: give a paper set (pset) or a general layout, not both")
    meth = method if method is not None else ("cobyla" if layout is None else "slsqp")
    if meth not in ("cobyla", "slsqp"):
        raise ValueError(f"method: expected 'cobyla' or 'slsqp', got {method!r}")
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
    if meth == "slsqp":
        success, message, nfev, best = _slsqp(
            start, objective, geo, nom, lim, samples, amplitude,
            200 if maxiter is None else maxiter, 2 if restarts is None else restarts,
            # log det per base parameter: the mean log eigenvalue, of
            # log cond's size (its gradient, SLSQP's first step, too)
            1.0 if criterion == "cond" else float(base.rank))
        shrink, tries = 0.99, 60
    else:
        # derivative-free: the limits are peaks over the samples (not smooth)
        x0 = start.vector()
        nfev = 0
        for _ in range(1 + (restarts or 0)):
            # a restart begins a new trust region at the last point: COBYLA's
            # shrinks to tol about the first local optimum it meets
            res = opt.minimize(objective, x0, method="COBYLA",
                               constraints=[{"type": "ineq", "fun": constraint}],
                               options={"maxiter": 100 if maxiter is None else maxiter,
                                        "tol": 1e-4,
                                        "rhobeg": 0.2 * float(np.abs(x0).mean())})
            nfev += int(res.nfev)
            if min(constraint(res.x)) < 0:
                break
            x0 = res.x
        best = start.with_vector(res.x)
        success, message = bool(res.success), str(res.message)
        shrink, tries = 0.97, 20
    mg = _margins(peaks(best, geo, nom, 4 * samples), lim)
    if min(mg.values()) < 0:
        # the optimiser ends at a point its model of the limits allowed,
        # on its own samples: shrink towards q0 until it is inside on the
        # fine grid
        for _ in range(tries):
            best = Fourier(best.q0, shrink * best.a, shrink * best.b, f0)
            mg = _margins(peaks(best, geo, nom, 4 * samples), lim)
            if min(mg.values()) >= 0:
                break
    feasible = min(mg.values()) >= 0
    if not feasible and min(_margins(peaks(start, geo, nom, 4 * samples), lim).values()) >= 0:
        best, feasible = start, True          # keep the feasible start
        mg = _margins(peaks(best, geo, nom, 4 * samples), lim)
    c, ld = crit(best)
    if not success:
        import warnings

        warnings.warn(f"design: the optimiser did not converge ({message}); "
                      f"condition number {c:.3g} from {c0:.3g}", RuntimeWarning, stacklevel=2)
    return Excitation(best, criterion, c, ld, c0, ld0, success, message,
                      seed, nfev, feasible, base.base_names, ps, geo, lim, mg,
                      layout)


def sample_margins(fourier: Fourier, geometry: Geometry, nominal: dict[str, Any],
                   limits: Limits, t: ArrayLike) -> np.ndarray:
    """Every limit's margin at every time t (flat), each divided by the
    scale of :func:`_margin_scale` (1 at a limit's range): link strokes,
    rates, accelerations and forces per leg, the rates, accelerations and
    forces on both sides (smooth in the coefficients, unlike their
    absolute values), the transmission, beta's range, in that order,
    each block sample by sample; a pose the library cannot solve has
    margins -1."""
    q, dq, ddq = fourier.eval(t)
    mdl = geometry.model(**nominal)
    res = mdl.inverse(q, dq, ddq)
    from rps3 import velocity

    mot = velocity.pose_rates(mdl, q, dq, ddq, check_status=False)
    lim, sc = limits, _margin_scale(limits)
    beta = q[:, 1:2]
    blocks = [(mot.l - lim.l_min) / sc["l_min"], (lim.l_max - mot.l) / sc["l_max"],
              (lim.dl_max - mot.dl) / sc["dl_max"], (lim.dl_max + mot.dl) / sc["dl_max"],
              (lim.ddl_max - mot.ddl) / sc["ddl_max"], (lim.ddl_max + mot.ddl) / sc["ddl_max"],
              (lim.F_max - res.force) / sc["F_max"], (lim.F_max + res.force) / sc["F_max"],
              (lim.transmission_max - np.reshape(res.transmission, (-1, 1)))
              / sc["transmission_max"],
              (beta - lim.beta_min) / sc["beta_min"], (lim.beta_max - beta) / sc["beta_max"]]
    ok = np.asarray(res.ok, bool) & mot.ok
    g = np.concatenate([np.where(ok[:, None], b, -1.0).ravel() for b in blocks])
    return np.where(np.isfinite(g), g, -1.0)


#: the slack SLSQP keeps from every limit (a fraction of its range): its
#: last iterate may violate its linearised constraints slightly, and the
#: peaks between its samples exceed theirs
_SLACK = 0.01
#: SLSQP's stopping tolerance on the criterion (log cond, or -log det per
#: base parameter): a relative change of 1e-4 in the condition number (in
#: the geometric mean of the eigenvalues); tighter, its line search fails
#: where the smallest singular values meet (log cond is not
#: differentiable there) instead of stopping
_FTOL = 1e-4
#: the floor of SLSQP's scaled margins (10 ranges outside a limit)
_FLOOR = 10.0


def _slsqp(start: Fourier, objective: Any, geo: Geometry, nom: dict[str, Any], lim: Limits,
           samples: int, amplitude: ArrayLike, maxiter: int, restarts: int,
           per: float) -> tuple[bool, str, int, Fourier]:
    """design's SLSQP: the coefficients scaled so that each is about the
    excursion it makes over the amplitude asked for (coordinate k's
    harmonic j moves q_k by a_kj / (w j)), the criterion divided by
    ``per``, the limits at 2 samples points as constraints; while SLSQP
    reports a failure (its line search or its linearised constraints,
    which a new run's fresh quasi-Newton matrix often passes), up to
    ``restarts`` further runs from the best point so far.  Returns the last run's
    success flag and message, the number of criterion evaluations (finite
    differences included) and the best iterate whose sampled limits hold
    (within half the slack), else the start."""
    opt = _id._need("scipy.optimize")
    H = start.harmonics
    w = 2 * np.pi * start.f0 * np.arange(1, H + 1)
    # a coordinate asked not to move still gets a scale: a tenth of its range
    dflt = np.array([1.0, 0.1 * (lim.beta_max - lim.beta_min), 0.1 * (lim.l_max - lim.l_min)])
    amp = np.abs(np.asarray(amplitude, float))
    amp = np.where(amp > 0, amp, dflt)
    s = np.tile((amp[:, None] * w[None, :]).ravel(), 2)
    tc = np.linspace(0.0, start.period, 2 * samples, endpoint=False)
    count = [0]

    def fun(u: np.ndarray) -> float:
        count[0] += 1
        return float(objective(u * s)) / per

    def cons(u: np.ndarray) -> np.ndarray:
        g = sample_margins(start.with_vector(u * s), geo, nom, lim, tc) - _SLACK
        # near a singular pose the transmission and forces grow without
        # bound: a floor keeps SLSQP's linearisation of a wild step sane
        return np.maximum(g, -_FLOOR)

    best_u, best_f = start.vector() / s, math.inf

    def keep(u: np.ndarray) -> None:
        # SLSQP returns its last iterate, which a failed line search may
        # leave far outside the limits: keep the best one inside
        nonlocal best_u, best_f
        f = fun(u)
        if f < best_f and float(np.min(cons(u))) >= -0.5 * _SLACK:
            best_u, best_f = np.array(u, copy=True), f

    success, message = False, ""
    for _ in range(1 + max(restarts, 0)):
        res = opt.minimize(fun, best_u, method="SLSQP",
                           constraints=[{"type": "ineq", "fun": cons}], callback=keep,
                           options={"maxiter": maxiter, "ftol": _FTOL})
        success, message = bool(res.success), str(res.message)
        keep(res.x)
        if success:
            break
    return success, message, count[0], start.with_vector(best_u * s)


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
