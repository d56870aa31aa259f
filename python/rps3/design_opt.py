"""The optimisers of rps3.design (docs/design-optimisation.md): NSGA-II
Pareto fronts (``pareto``, pymoo) and constrained single-objective optima
(``optimise``, NLopt) over the design variables, with the dense-grid check
of an optimum (``neighbourhood``).  rps3.design re-exports every public
name; pymoo and nlopt are the optional ``rps3[design]`` dependencies.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from rps3 import _optimise
from rps3 import errors as _errors
from rps3._core import FloatArray
from rps3._rps3 import lib
from rps3.design import (
    UNITS,
    Design,
    Grid,
    Options,
    _eval,
    _range,
    grid,
    summarise,
)
from rps3.design_task import _samples, _spec, _task_c, _task_result
from rps3.errors import points3, real_number

if TYPE_CHECKING:
    from rps3.trajectory import Spec, Trajectory

# ------------------------------------------------------------ optimisation

#: an optimiser stopped without meeting its tolerances, or returned a
#: design that breaks a constraint (rps3.errors.ConvergenceWarning)
ConvergenceWarning = _errors.ConvergenceWarning


#: what can be optimised: name -> (+1 minimised, -1 maximised, unit, needs)
OBJECTIVES: dict[str, tuple[int, str, str]] = {
    "peak_force": (1, "N", "task"), "rms_force": (1, "N", "task"),
    "peak_power": (1, "W", "task"), "volume": (-1, "m rad^2", "grid"),
    "gti": (-1, "1", "grid"), "good_fraction": (-1, "1", "grid")}

#: the design variables beyond Design's fields: l_max = stroke_ratio l_min
DERIVED = ("stroke_ratio",)


def _variables(variables: Mapping[str, Sequence[float]]) -> tuple[
        tuple[str, ...], FloatArray, FloatArray]:
    if not isinstance(variables, Mapping) or not variables:
        raise ValueError("variables: expected a mapping of design variables to "
                         f"(lower, upper) bounds, got {variables!r}")
    names = tuple(variables)
    for name in names:
        if name not in UNITS and name not in DERIVED:
            raise ValueError(f"variables[{name!r}]: not a design variable; one of "
                             f"{', '.join([*UNITS, *DERIVED])}")
    if "stroke_ratio" in names and "l_max" in names:
        raise ValueError("variables['stroke_ratio']: give stroke_ratio or l_max, "
                         "not both")
    bounds = [_range(variables[k], f"variables[{k!r}]") for k in names]
    return names, np.array([b[0] for b in bounds]), np.array([b[1] for b in bounds])


def _apply(base: Design, names: tuple[str, ...], values: FloatArray) -> Design:
    kw = {k: float(v) for k, v in zip(names, values)}
    ratio = kw.pop("stroke_ratio", None)
    if ratio is not None:
        kw["l_max"] = ratio * kw.get("l_min", base.l_min)
    return base.replace(**kw)


def _reach_violation(ds: Design, poses: FloatArray, opts: Options | None
                     ) -> tuple[float, float]:
    """How far the poses (3, n) are outside ds's workspace, at the worst
    pose: the largest excess over a limit, lengths relative to l_max and
    angles in radians (<= 0: every pose reachable; a pose that does not
    assemble or is singular counts 1); and the least LTI among them."""
    s, a, _ = _eval(ds, poses, 0.0, opts, True)
    flags = a["flags"]
    hard = (flags & (lib.RPS3_DESIGN_ASSEMBLY | lib.RPS3_DESIGN_SINGULAR)) != 0
    with np.errstate(invalid="ignore"):
        ex = [np.max((ds.l_min - a["l"]) / ds.l_max, axis=0),
              np.max((a["l"] - ds.l_max) / ds.l_max, axis=0),
              np.max(ds.theta_min - a["theta"], axis=0),
              np.max(a["theta"] - ds.theta_max, axis=0),
              np.max(a["ball"] - ds.ball_max, axis=0)]
        if ds.link_radius > 0:
            ex.append(-a["clearance"] / ds.l_max)
        excess = np.max(np.stack(ex), axis=0)
    excess = np.where(hard, 1.0, excess)
    # a pose the library flags must count as outside, whatever the rounding
    excess = np.where((flags != 0) & (excess <= 0), 1e-9, excess)
    lti = a["lti"][~hard]
    return float(np.max(excess)), float(np.min(lti)) if lti.size else 0.0


@dataclass
class _Problem:
    """A design problem: variables, objectives and constraints, evaluated
    design by design."""

    names: tuple[str, ...]
    lo: FloatArray
    hi: FloatArray
    objectives: tuple[str, ...]
    base: Design
    trajectory: Any = None
    samples: int = 201
    grid: Grid | None = None
    covers: FloatArray | None = None
    volume_min: float | None = None
    force_max: float | None = None
    lti_min: float | None = None
    options: Options | None = None
    platform_mass: str = "fixed"
    reached_task: int = 0   # designs evaluated that follow the task

    @property
    def constraint_names(self) -> tuple[str, ...]:
        out = []
        if self.trajectory is not None:
            out.append("task_reach")
        if self.covers is not None:
            out.append("covers")
        for name in ("volume_min", "force_max", "lti_min"):
            if getattr(self, name) is not None:
                out.append(name)
        return tuple(out)

    def design(self, x: FloatArray) -> Design:
        ds = _apply(self.base, self.names, self.lo + np.asarray(x) * (self.hi - self.lo))
        if self.platform_mass == "area":
            # a plate of the base design's areal density: M grows as r^2
            ds = ds.replace(M=self.base.M * (ds.r / self.base.r) ** 2)
        return ds

    def values(self, x: FloatArray) -> tuple[dict[str, float], dict[str, float]]:
        """Objectives (natural units and sense) and constraint values (<= 0
        satisfied) of the scaled point x; an invalid design has NaN
        objectives and every constraint at 1."""
        try:
            ds = self.design(x)
        except ValueError:
            return ({k: math.nan for k in self.objectives},
                    {k: 1.0 for k in self.constraint_names})
        obj: dict[str, float] = {}
        con: dict[str, float] = {}
        lti_floor = math.inf
        need_grid = self.volume_min is not None or any(
            OBJECTIVES[k][2] == "grid" for k in self.objectives)
        if need_grid:
            s = summarise(ds, self.grid if self.grid is not None else grid(ds),
                          options=self.options)
            for k in self.objectives:
                if OBJECTIVES[k][2] == "grid":
                    obj[k] = float(getattr(s, k))
            if self.volume_min is not None:
                con["volume_min"] = 1.0 - s.volume / self.volume_min
        if self.trajectory is not None:
            tr = self.trajectory
            try:
                traj_poses = tr.eval(np.linspace(0.0, tr.duration, self.samples),
                                     ds.model()).pose
            except ValueError:
                # a task this design's model refuses (e.g. a helix wider
                # than the platform allows): it cannot follow it
                for k in self.objectives:
                    if OBJECTIVES[k][2] == "task":
                        obj[k] = math.nan
                con["task_reach"] = 1.0
                if self.force_max is not None:
                    con["force_max"] = 1.0
                lti_floor = 0.0
                traj_poses = None
        if self.trajectory is not None and traj_poses is not None:
            tr = self.trajectory
            viol, lti_t = _reach_violation(ds, np.ascontiguousarray(traj_poses.T),
                                           self.options)
            status, res, _ = _task_c(ds, tr.c, self.samples, True, self.options)
            t = _task_result(res)
            if status != lib.RPS3_OK:
                viol = max(viol, 1e-9)
            else:
                self.reached_task += 1
            con["task_reach"] = viol
            lti_floor = min(lti_floor, lti_t)
            vals = {"peak_force": t.peak_force, "rms_force": t.rms_force,
                    "peak_power": t.peak_power}
            for k in self.objectives:
                if OBJECTIVES[k][2] == "task":
                    obj[k] = vals[k]
            if self.force_max is not None:
                con["force_max"] = t.peak_force / self.force_max - 1.0
        if self.covers is not None:
            viol, lti_c = _reach_violation(ds, self.covers, self.options)
            con["covers"] = viol
            lti_floor = min(lti_floor, lti_c)
        if self.lti_min is not None:
            con["lti_min"] = self.lti_min - lti_floor
        return obj, {k: con[k] for k in self.constraint_names}

    def minimised(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Objectives all minimised (maximised ones negated; NaN, of an
        invalid design, as a large penalty) and the constraints."""
        obj, con = self.values(x)
        f = np.array([OBJECTIVES[k][0] * obj[k] for k in self.objectives])
        f = np.where(np.isfinite(f), f, 1e30)
        return f, np.array([con[k] for k in self.constraint_names])


def _problem(variables: Mapping[str, Sequence[float]], objectives: Sequence[str],
             base: Design | None, trajectory: Any, samples: int | None,
             grid_: Grid | None, covers: ArrayLike | None,
             volume_min: float | None, force_max: float | None,
             lti_min: float | None, options: Options | None,
             platform_mass: str = "fixed") -> _Problem:
    names, lo, hi = _variables(variables)
    if platform_mass not in ("fixed", "area"):
        raise ValueError(f"platform_mass: {platform_mass!r} is not 'fixed' or 'area'")
    if platform_mass == "area" and "M" in names:
        raise ValueError("variables['M']: with platform_mass='area' M follows r")
    base = Design() if base is None else base
    if not isinstance(base, Design):
        raise TypeError(f"base: expected a Design, got {type(base).__name__}")
    for k in objectives:
        if k not in OBJECTIVES:
            raise ValueError(f"objective: {k!r} is not one of {', '.join(OBJECTIVES)}")
    if len(set(objectives)) != len(objectives):
        raise ValueError(f"objectives: {list(objectives)} names one twice")
    needs_task = [k for k in objectives if OBJECTIVES[k][2] == "task"]
    if (needs_task or force_max is not None) and trajectory is None:
        what = needs_task[0] if needs_task else "force_max"
        raise ValueError(f"trajectory: {what} needs a task trajectory")
    # every bound must make a valid design with the others mid-range
    mid = (lo + hi) / 2
    for j, name in enumerate(names):
        for side, v in (("lower", float(lo[j])), ("upper", float(hi[j]))):
            x = mid.copy()
            x[j] = v
            if name == "stroke_ratio" and v <= 1:
                raise ValueError(f"variables['stroke_ratio']: {side} bound {v!r} "
                                 "must be > 1 (l_max above l_min: a stroke > 0)")
            try:
                _apply(base, names, x)
            except ValueError as e:
                raise ValueError(f"variables[{name!r}]: the {side} bound {v!r} "
                                 f"makes no valid design: {e}") from None
    tr = None
    if trajectory is not None:
        tr_c, n_default = _spec(trajectory)
        from rps3.trajectory import Spec
        tr = trajectory.spec if not isinstance(trajectory, Spec) else trajectory
        samples = _samples(samples, n_default)
    cov = None
    if covers is not None:
        cov, _ = points3(covers, "covers")
        if cov.shape[1] == 0:
            raise ValueError("covers: no pose given")
    checks: dict[str, float | None] = {}
    for name, value in (("volume_min", volume_min), ("force_max", force_max)):
        checks[name] = None if value is None else real_number(value, name, lo=0.0,
                                                              lo_open=True)
    lti = None if lti_min is None else real_number(lti_min, "lti_min", lo=0.0)
    if lti is not None and lti > 1:
        raise ValueError(f"lti_min: must be <= 1 (the LTI is in [0, 1]), got {lti!r}")
    return _Problem(names, lo, hi, tuple(objectives), base, tr, samples or 201,
                    grid_, cov, checks["volume_min"], checks["force_max"], lti,
                    options, platform_mass)


@dataclass(frozen=True)
class Optimum:
    """A constrained optimum found by NLopt."""

    design: Design                  #: the design found
    objective: str                  #: what was optimised
    value: float                    #: its value [the objective's unit]
    variables: dict[str, float]     #: the design variables' values
    constraints: dict[str, float]   #: each constraint's value, <= 0 met
    feasible: bool                  #: every constraint met (within ctol)
    converged: bool                 #: NLopt met a stopping tolerance
    status: str                     #: NLopt's result, e.g. "XTOL_REACHED"
    algorithm: str                  #: "COBYLA" or "AUGLAG"
    nevals: int                     #: designs evaluated
    seed: int                       #: seed of the starting sample
    problem: _Problem = field(repr=False, compare=False)


def _lhs(n: int, k: int, seed: int) -> FloatArray:
    """A Latin hypercube of n points in [0, 1]^k."""
    rng = np.random.default_rng(seed)
    u = (np.argsort(rng.random((k, n)), axis=1).T + rng.random((n, k))) / n
    return np.asarray(u)


def optimise(variables: Mapping[str, Sequence[float]],
             objective: str = "peak_force", *, base: Design | None = None,
             trajectory: Trajectory | Spec | None = None,
             samples: int | None = None, grid: Grid | None = None,
             covers: ArrayLike | None = None, volume_min: float | None = None,
             force_max: float | None = None, lti_min: float | None = None,
             algorithm: str = "COBYLA", x0: Mapping[str, float] | None = None,
             prescan: int = 16, seed: int = 1, xtol_rel: float = 1e-4,
             ftol_rel: float = 1e-8, maxeval: int = 400, ctol: float = 1e-9,
             platform_mass: str = "fixed", options: Options | None = None) -> Optimum:
    """The design that minimises (or maximises) one objective under
    constraints, by NLopt's derivative-free COBYLA (or an augmented
    Lagrangian around BOBYQA, "AUGLAG").

    Args:
        variables: design variables and their bounds, e.g. ``{"rho": (0.3,
            0.9), "R": (0.15, 0.3)}``: fields of Design, or
            ``stroke_ratio`` (l_max = stroke_ratio l_min).
        objective: one of OBJECTIVES: ``peak_force``, ``rms_force``,
            ``peak_power`` (of the task, minimised), ``volume``, ``gti``,
            ``good_fraction`` (over the grid, maximised).
        base: the design the variables change (default Design()).
        trajectory: the task (a Trajectory, or its spec); the design must
            follow it (constraint ``task_reach``).
        samples: samples of the task (default: the Trajectory's).
        grid: the poses of volume, gti, good_fraction (default: each
            design's ``grid(design)``).
        covers: (n, 3) poses every design must reach (e.g. the reachable
            poses of Table II's design: "at least its workspace").
        volume_min: least workspace volume over grid [m rad^2].
        force_max: largest peak actuator force of the task [N].
        lti_min: least LTI along the task and over covers [-].
        algorithm: "COBYLA" or "AUGLAG".
        x0: the starting design variables; default: the best of a Latin
            hypercube of ``prescan`` designs drawn with ``seed``.
        xtol_rel, ftol_rel, maxeval: NLopt's stopping rules (relative to
            the variables scaled to [0, 1]).
        ctol: constraint tolerance.
        platform_mass: "fixed" (base.M for every design) or "area" (a
            plate of base's areal density: M = base.M (r / base.r)^2).

    Returns:
        Optimum.  When NLopt stops without meeting xtol_rel or ftol_rel
        (evaluation budget, roundoff, failure) ``converged`` is False,
        and when the design breaks a constraint ``feasible`` is False;
        either way a ConvergenceWarning says so.

    Raises:
        ValueError: naming the argument: an unknown or duplicated
            variable, inverted or empty bounds, a bound that makes no valid
            design (a negative or empty stroke), a constraint out of range,
            a task that no design tried can follow (``trajectory``).
    """
    if algorithm not in ("COBYLA", "AUGLAG"):
        raise ValueError(f"algorithm: {algorithm!r} is not COBYLA or AUGLAG")
    for name, v, least in (("maxeval", maxeval, 1), ("prescan", prescan, 1),
                           ("seed", seed, 0)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < least:
            raise ValueError(f"{name}: expected an integer >= {least}, got {v!r}")
    for name, fv in (("xtol_rel", xtol_rel), ("ftol_rel", ftol_rel)):
        real_number(fv, name, lo=0.0, lo_open=True)
    ctol = real_number(ctol, "ctol", lo=0.0)
    pb = _problem(variables, (objective,), base, trajectory, samples, grid,
                  covers, volume_min, force_max, lti_min, options, platform_mass)
    n = len(pb.names)

    def key(f: float, g: FloatArray) -> tuple[float, float]:
        viol = float(np.max(g)) if g.size else -math.inf
        return (max(viol, 0.0) if viol > ctol else 0.0, f)

    if x0 is not None:
        if set(x0) != set(pb.names):
            raise ValueError(f"x0: expected values of {list(pb.names)}, got "
                             f"{sorted(x0)}")
        start = np.array([(real_number(x0[k], f"x0[{k!r}]") - pb.lo[j])
                          / (pb.hi[j] - pb.lo[j]) for j, k in enumerate(pb.names)])
        if np.any(start < 0) or np.any(start > 1):
            raise ValueError(f"x0: {dict(x0)} is outside the variables' bounds")
    else:
        best = None
        for x in _lhs(prescan, n, seed):
            f, g = pb.minimised(x)
            if best is None or key(f[0], g) < best[0]:
                best = (key(f[0], g), x)
        assert best is not None
        start = best[1]
    loc = _optimise.nlopt_minimise(
        lambda x: (lambda fg: (float(fg[0][0]), fg[1]))(pb.minimised(x)),
        len(pb.constraint_names), start, algorithm=algorithm,
        xtol_rel=xtol_rel, ftol_rel=ftol_rel, maxeval=maxeval, ctol=ctol)
    if pb.trajectory is not None and pb.reached_task == 0:
        raise ValueError(
            "trajectory: outside the workspace of every design tried "
            f"({loc.nevals + (0 if x0 is not None else prescan)} designs within "
            f"the bounds of {list(pb.names)}): widen the bounds or the joint "
            "limits, or move the task")
    ds = pb.design(loc.x)
    obj, con = pb.values(loc.x)
    feasible = all(v <= ctol for v in con.values())
    result = Optimum(design=ds, objective=objective, value=obj[objective],
                     variables={k: float(v) for k, v in zip(
                         pb.names, pb.lo + loc.x * (pb.hi - pb.lo))},
                     constraints=con, feasible=feasible,
                     converged=loc.converged, status=loc.status,
                     algorithm=algorithm, nevals=loc.nevals, seed=seed,
                     problem=pb)
    if not loc.converged or not feasible:
        why = [] if loc.converged else [f"NLopt stopped with {loc.status} "
                                        "before meeting its tolerances"]
        if not feasible:
            broken = [k for k, v in con.items() if v > ctol]
            why.append(f"the design breaks {', '.join(broken)}")
        warnings.warn(f"optimise: {'; '.join(why)}", ConvergenceWarning,
                      stacklevel=2)
    return result


def neighbourhood(opt: Optimum, *, half_width: float = 0.05, n: int = 9
                  ) -> tuple[float, Design | None, int]:
    """The best feasible design of a dense grid around an optimum: n nodes
    per variable over +- half_width of its bound's span (clipped to the
    bounds).  Returns (its objective value, the design, the number of
    feasible nodes); (NaN, None, 0) when none is feasible.  An optimum is
    a local one when no node beats it."""
    pb = opt.problem
    x = np.array([(opt.variables[k] - pb.lo[j]) / (pb.hi[j] - pb.lo[j])
                  for j, k in enumerate(pb.names)])
    axes = [np.clip(np.linspace(v - half_width, v + half_width, n), 0, 1) for v in x]
    sense = OBJECTIVES[opt.objective][0]
    best: tuple[float, Design | None] = (math.inf, None)
    count = 0
    for node in np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, len(x)):
        obj, con = pb.values(node)
        if all(v <= 0 for v in con.values()) and np.isfinite(obj[opt.objective]):
            count += 1
            if sense * obj[opt.objective] < best[0]:
                best = (sense * obj[opt.objective], pb.design(node))
    return (sense * best[0] if best[1] is not None else math.nan), best[1], count


@dataclass(frozen=True)
class Pareto:
    """The feasible non-dominated designs NSGA-II found."""

    designs: list[Design]            #: the designs, in order of the first objective
    variables: FloatArray            #: (k, nvar) their design variables
    variable_names: tuple[str, ...]  #: the variables' names
    objectives: FloatArray           #: (k, nobj) objectives, natural units and sense
    objective_names: tuple[str, ...] #: the objectives' names
    constraints: FloatArray          #: (k, ncon) constraint values, <= 0 met
    constraint_names: tuple[str, ...]  #: their names
    seed: int                        #: the seed of the run
    pop_size: int                    #: population size
    n_gen: int                       #: generations
    nevals: int                      #: designs evaluated

    def hypervolume(self, reference: Mapping[str, float]) -> float:
        """The objective space the front dominates up to the reference
        point (one value per objective, in its unit: e.g. ``{"peak_force":
        20.0, "volume": 0.0}``), the product of the objectives' units."""
        if set(reference) != set(self.objective_names):
            raise ValueError(f"reference: expected values of "
                             f"{list(self.objective_names)}, got {sorted(reference)}")
        sense = np.array([OBJECTIVES[k][0] for k in self.objective_names])
        ref = sense * np.array([real_number(reference[k], f"reference[{k!r}]")
                                for k in self.objective_names])
        return _optimise.hypervolume(sense * self.objectives, ref)


def pareto(variables: Mapping[str, Sequence[float]],
           objectives: Sequence[str] = ("peak_force", "volume"), *,
           base: Design | None = None,
           trajectory: Trajectory | Spec | None = None,
           samples: int | None = None, grid: Grid | None = None,
           covers: ArrayLike | None = None, volume_min: float | None = None,
           force_max: float | None = None, lti_min: float | None = None,
           pop_size: int = 40, n_gen: int = 40, seed: int = 1,
           platform_mass: str = "fixed", options: Options | None = None) -> Pareto:
    """The Pareto front of two or more objectives under constraints, by
    pymoo's NSGA-II.

    Args: as ``optimise`` (objectives: two or more of OBJECTIVES), and
        pop_size, n_gen: population and generations of NSGA-II;
        seed: its random seed (recorded in the result: the same seed gives
        the same front).

    Returns:
        Pareto: the feasible non-dominated designs (none when no design
        met the constraints).

    Raises:
        ValueError: as ``optimise``.
    """
    if isinstance(objectives, str) or len(objectives) < 2:
        raise ValueError(f"objectives: expected two or more of "
                         f"{', '.join(OBJECTIVES)}, got {objectives!r}")
    for name, v, least in (("pop_size", pop_size, 2), ("n_gen", n_gen, 1),
                           ("seed", seed, 0)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < least:
            raise ValueError(f"{name}: expected an integer >= {least}, got {v!r}")
    pb = _problem(variables, tuple(objectives), base, trajectory, samples, grid,
                  covers, volume_min, force_max, lti_min, options, platform_mass)
    ncon = len(pb.constraint_names)

    def fun(X: FloatArray) -> tuple[FloatArray, FloatArray]:
        rows = [pb.minimised(x) for x in X]
        return (np.array([r[0] for r in rows]),
                np.array([r[1] for r in rows]).reshape(len(X), ncon))

    fr = _optimise.nsga2(fun, len(pb.names), len(objectives), ncon,
                         pop_size=pop_size, n_gen=n_gen, seed=seed)
    if pb.trajectory is not None and pb.reached_task == 0:
        raise ValueError(
            f"trajectory: outside the workspace of every design tried ({fr.nevals} "
            f"designs within the bounds of {list(pb.names)}): widen the bounds or "
            "the joint limits, or move the task")
    order = np.argsort(fr.f[:, 0], kind="stable")
    X = fr.x[order]
    sense = np.array([OBJECTIVES[k][0] for k in objectives])
    return Pareto(designs=[pb.design(x) for x in X],
                  variables=pb.lo + X * (pb.hi - pb.lo), variable_names=pb.names,
                  objectives=fr.f[order] * sense, objective_names=tuple(objectives),
                  constraints=fr.g[order], constraint_names=pb.constraint_names,
                  seed=int(seed), pop_size=int(pop_size), n_gen=int(n_gen),
                  nevals=fr.nevals)
