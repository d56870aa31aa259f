"""The optimisers behind rps3.design: NSGA-II (pymoo) for Pareto fronts and
NLopt for a constrained single objective, over a box of scaled design
variables.  Both libraries are optional dependencies (``pip install
rps3[design]``), imported when an optimisation runs."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from rps3._core import FloatArray

#: NLopt's result codes that mean the optimiser met a stopping tolerance
#: (converged); the others (an evaluation or time budget spent, roundoff,
#: a failure, a forced stop) mean it did not
NLOPT_CONVERGED = {1: "SUCCESS", 2: "STOPVAL_REACHED", 3: "FTOL_REACHED",
                   4: "XTOL_REACHED"}
NLOPT_NOT_CONVERGED = {5: "MAXEVAL_REACHED", 6: "MAXTIME_REACHED",
                       -1: "FAILURE", -2: "INVALID_ARGS", -3: "OUT_OF_MEMORY",
                       -4: "ROUNDOFF_LIMITED", -5: "FORCED_STOP"}


def _require(module: str) -> Any:
    import importlib
    try:
        return importlib.import_module(module)
    except ImportError:
        pkg = {"pymoo": "pymoo", "nlopt": "nlopt"}[module.split(".")[0]]
        raise ImportError(
            f"rps3.design: the optimisation needs the {pkg!r} package "
            f"(pip install 'rps3[design]', or pip install {pkg})") from None


@dataclass
class Local:
    """What a run of NLopt ends with."""

    x: FloatArray          #: the best point, scaled to [0, 1]
    fun: float             #: its objective
    violation: float       #: its largest constraint value (<= tol: feasible)
    status: str            #: NLopt's result, e.g. "XTOL_REACHED"
    converged: bool        #: a stopping tolerance was met
    nevals: int            #: objective evaluations


def nlopt_minimise(fun: Callable[[FloatArray], tuple[float, FloatArray]],
                   ncon: int, x0: FloatArray, *, algorithm: str,
                   xtol_rel: float, ftol_rel: float, maxeval: int,
                   ctol: float) -> Local:
    """Minimise fun(x)[0] over x in [0, 1]^n subject to fun(x)[1] <= 0
    (ncon values), from x0.

    algorithm: "COBYLA" (constraints handled by the method itself) or
    "AUGLAG" (an augmented Lagrangian around BOBYQA, derivative-free).
    Each evaluation is cached: NLopt asks for the objective and every
    constraint at the same x, and fun evaluates them together.

    The best point is the feasible point with the smallest objective that
    NLopt evaluated (the infeasible one of smallest violation when none is
    feasible): NLopt's own returned point is that one whenever it
    converged, and is lost when it raises (roundoff, forced stop).
    """
    nlopt = _require("nlopt")
    n = x0.size
    algos = {"COBYLA": nlopt.LN_COBYLA, "AUGLAG": nlopt.LN_AUGLAG}
    opt = nlopt.opt(algos[algorithm], n)
    if algorithm == "AUGLAG":
        local = nlopt.opt(nlopt.LN_BOBYQA, n)
        local.set_xtol_rel(xtol_rel)
        local.set_ftol_rel(ftol_rel)
        opt.set_local_optimizer(local)
    opt.set_lower_bounds(np.zeros(n))
    opt.set_upper_bounds(np.ones(n))
    opt.set_xtol_rel(xtol_rel)
    opt.set_ftol_rel(ftol_rel)
    opt.set_maxeval(maxeval)
    cache: dict[bytes, tuple[float, FloatArray]] = {}
    best: dict[str, Any] = {"key": None}

    def ev(x: FloatArray) -> tuple[float, FloatArray]:
        x = np.clip(np.asarray(x, float), 0.0, 1.0)
        k = x.tobytes()
        if k not in cache:
            f, g = fun(x)
            g = np.asarray(g, float).reshape(ncon)
            cache[k] = (float(f), g)
            viol = float(g.max()) if ncon else -np.inf
            cand = (max(viol, ctol) > ctol, max(viol, 0.0) if viol > ctol else 0.0,
                    float(f))
            if best["key"] is None or cand < best["key"]:
                best.update(key=cand, x=x.copy(), f=float(f), viol=viol)
        return cache[k]

    opt.set_min_objective(lambda x, grad: ev(x)[0])
    def constraint(j: int) -> Callable[[FloatArray, FloatArray], float]:
        return lambda x, grad: float(ev(x)[1][j])

    for j in range(ncon):
        opt.add_inequality_constraint(constraint(j), ctol)
    try:
        opt.optimize(np.clip(np.asarray(x0, float), 0.0, 1.0))
        code = int(opt.last_optimize_result())
    except nlopt.RoundoffLimited:
        code = -4
    except nlopt.ForcedStop:
        code = -5
    except (RuntimeError, ValueError):
        code = -1
    names = {**NLOPT_CONVERGED, **NLOPT_NOT_CONVERGED}
    if best["key"] is None:  # not one evaluation
        return Local(np.asarray(x0, float), np.nan, np.inf,
                     names.get(code, str(code)), False, 0)
    return Local(best["x"], best["f"], best["viol"],
                 names.get(code, str(code)), code in NLOPT_CONVERGED,
                 len(cache))


@dataclass
class Front:
    """What a run of NSGA-II ends with: its non-dominated feasible set."""

    x: FloatArray          #: (k, n) scaled design variables
    f: FloatArray          #: (k, nobj) objectives, all minimised
    g: FloatArray          #: (k, ncon) constraint values, <= 0 feasible
    nevals: int            #: evaluations


def nsga2(fun: Callable[[FloatArray], tuple[FloatArray, FloatArray]],
          n: int, nobj: int, ncon: int, *, pop_size: int, n_gen: int,
          seed: int) -> Front:
    """NSGA-II (pymoo) over [0, 1]^n: fun(X) of a (k, n) population gives
    (k, nobj) objectives and (k, ncon) constraints (<= 0 feasible)."""
    _require("pymoo")
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.core.problem import Problem
    from pymoo.optimize import minimize

    class _P(Problem):
        def __init__(self) -> None:
            super().__init__(n_var=n, n_obj=nobj, n_ieq_constr=ncon,
                             xl=np.zeros(n), xu=np.ones(n))

        def _evaluate(self, X: FloatArray, out: dict[str, Any],
                      *args: Any, **kwargs: Any) -> None:
            F, G = fun(np.asarray(X, float))
            out["F"] = F
            if ncon:
                out["G"] = G

    res = minimize(_P(), NSGA2(pop_size=pop_size), ("n_gen", n_gen),
                   seed=int(seed), verbose=False, save_history=False)
    if res.X is None:  # no feasible design
        return Front(np.empty((0, n)), np.empty((0, nobj)),
                     np.empty((0, ncon)), int(res.algorithm.evaluator.n_eval))
    X = np.atleast_2d(res.X)
    F = np.atleast_2d(res.F)
    G = np.atleast_2d(res.G) if ncon else np.empty((len(X), 0))
    return Front(X, F, G, int(res.algorithm.evaluator.n_eval))


def hypervolume(f: FloatArray, ref: FloatArray) -> float:
    """The hypervolume dominated by the points f (all objectives
    minimised) up to the reference point ref (pymoo's HV indicator); 0
    for an empty front."""
    if len(f) == 0:
        return 0.0
    from pymoo.indicators.hv import HV
    keep = np.all(f < ref, axis=1)
    if not keep.any():
        return 0.0
    return float(HV(ref_point=np.asarray(ref, float))(np.asarray(f)[keep]))
