"""The identification's command line, ``python -m rps3.ident``
(docs/identification.md, "Command line"): fit a measured table, or run
the Monte Carlo study."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from rps3 import ident as _id
from rps3 import ident_paper as _ip
from rps3.ident_io import CUTOFF, DataError, fit, load
from rps3.ident_scene import manipulator_yaml
from rps3.ident_write import parameter_units, write_results


def _parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(
        prog="python -m rps3.ident",
        description="Identify the paper model's parameters, or a general "
                    "layout's bodies (--layout), from measured data "
                    "(docs/identification.md).  Exit codes: 0 done, 1 the fit "
                    "failed (data not exciting, or not consistent with --strict), "
                    "2 bad arguments or a refused data file.")
    sub = ap.add_subparsers(dest="command", required=True)
    f = sub.add_parser("fit", help="fit parameters to a data table")
    f.add_argument("data", help="CSV or HDF5 table: t, l1..l3, [l1_dot.., l1_ddot..], F1..F3")
    f.add_argument("-o", "--output", required=True, help="results, HDF5")
    f.add_argument("--yaml", help="also write a manipulator: section here")
    f.add_argument("--layout", choices=("each", "identical"),
                   help="fit a general layout's bodies (legs each their own, or "
                        "identical) instead of the paper model's parameters")
    f.add_argument("--friction", default=None,
                   help="with --layout: the friction kinds, comma separated, or none "
                        "(default prismatic,pin)")
    f.add_argument("--friction-per-leg", choices=("yes", "no"),
                   help="with --layout: friction coefficients per leg or shared "
                        "(default: per leg for each, shared for identical)")
    f.add_argument("--payload", action="store_true", help="identify a payload (paper model)")
    f.add_argument("--no-friction", action="store_true", help="no pin friction (paper model)")
    f.add_argument("--method", choices=("ols", "wls"), default="ols")
    f.add_argument("--cutoff", type=float, default=CUTOFF,
                   help=f"filter cut-off for differentiated rates [Hz] (default {CUTOFF:g})")
    for k, v in (("R", 0.2286), ("rho", 0.5), ("d", 0.1524), ("g", 9.80665),
                 ("vreg", 0.0)):
        f.add_argument(f"--{k}", type=float, default=v, help=f"(default {v:g})")
    f.add_argument("--vreg-prismatic", type=float, default=None,
                   help="the prismatic friction's Coulomb regularisation [m/s] (general "
                        "layouts; default --vreg)")
    f.add_argument("--M", type=float, default=None,
                   help="platform mass kept when a payload is identified (paper model; "
                        "default 0.18)")
    f.add_argument("--strict", action="store_true",
                   help="exit 1 when the fit is not physically consistent")
    st = sub.add_parser("study", help="the Monte Carlo study on simulated data: per "
                        "parameter error and coverage; the consistent fit's share of "
                        "consistent draws and its held-out NRMSE over WLS's")
    st.add_argument("--runs", type=int, default=200, help="fits per case (default 200)")
    st.add_argument("--seed", type=int, default=1, help="(default 1)")
    st.add_argument("--out", default="out", help="directory of the summary and figure")
    st.add_argument("--layout", choices=("each", "identical"),
                    help="the general layout's study instead (rps3.ident_sim."
                         "study_general: 10 s at 1 kHz, with the consistent fits and "
                         "a held-out motion; the summary on stdout)")
    return ap


def _model_arguments(args: argparse.Namespace) -> dict[str, Any]:
    """fit's model arguments: the paper set, or with --layout the general
    layout (the paper set's options refused with it)."""
    if args.layout is None:
        for opt, given in (("--friction", args.friction is not None),
                           ("--friction-per-leg", args.friction_per_leg is not None),
                           ("--vreg-prismatic", args.vreg_prismatic is not None)):
            if given:
                raise ValueError(f"{opt}: a general layout's option; give --layout "
                                 "each|identical")
        return dict(pset=_ip.PaperSet(payload=args.payload, friction=not args.no_friction),
                    M=0.18 if args.M is None else args.M)
    for opt, given in (("--payload", args.payload), ("--no-friction", args.no_friction),
                       ("--M", args.M is not None)):
        if given:
            raise ValueError(f"{opt}: the paper model's option, not read with --layout "
                             "(a general layout's platform holds any payload; "
                             "--friction none for no friction)")
    text = "prismatic,pin" if args.friction is None else args.friction
    kinds = tuple(k.strip() for k in text.split(",") if k.strip())
    if kinds == ("none",):
        kinds = ()
    elif not kinds:
        raise ValueError(f"--friction: expected kinds (prismatic, pin) or none, "
                         f"got {text!r}")
    per_leg = None if args.friction_per_leg is None else args.friction_per_leg == "yes"
    try:
        lay = _id.Layout(legs=args.layout, friction=kinds, friction_per_leg=per_leg)
    except ValueError as exc:
        raise ValueError(f"--friction: {exc}") from None
    if len(set(kinds)) != len(kinds):
        raise ValueError(f"--friction: a kind given twice in {text!r}")
    return dict(layout=lay)


def main(argv: list[str] | None = None) -> int:
    """``python -m rps3.ident fit DATA -o OUT.h5``: 0 done, 1 the fit
    failed, 2 bad arguments or data; ``python -m rps3.ident study``: the
    Monte Carlo study (``make ident``)."""
    try:
        args = _parser().parse_args(argv)
    except SystemExit as exc:
        return 0 if exc.code == 0 else 2
    if args.command == "study":
        from rps3 import ident_sim

        if args.runs < 2:
            print("rps3.ident: --runs: expected at least 2", file=sys.stderr)
            return 2
        if args.layout is not None:
            print(ident_sim.study_general(args.runs, args.seed, args.layout), end="")
            return 0
        print(ident_sim.study(args.runs, args.seed, args.out), end="")
        return 0
    try:
        geo = _ip.Geometry(R=args.R, rho=args.rho, d=args.d, g=args.g, vreg=args.vreg,
                           vreg_prismatic=args.vreg_prismatic)
        geo.model()
        model = _model_arguments(args)
        data = load(args.data)
    except (DataError, ValueError, OSError) as exc:
        print(f"rps3.ident: {exc}", file=sys.stderr)
        return 2
    try:
        res = fit(data, geometry=geo, method=args.method, cutoff=args.cutoff, **model)
    except DataError as exc:
        print(f"rps3.ident: {exc}", file=sys.stderr)
        return 2
    except (_id.NotExcitingError, ValueError) as exc:
        print(f"rps3.ident: {args.data}: {exc}", file=sys.stderr)
        return 1
    write_results(args.output, res, data)
    if args.yaml:
        with open(args.yaml, "w", encoding="utf-8") as fh:
            fh.write(manipulator_yaml(res))
    est = res.estimate
    for n, th, ci, u in zip(est.names, est.theta, est.ci95, parameter_units(res)):
        print(f"{n:12s} {th: .6g} +- {(ci[1] - ci[0]) / 2:.3g} {u}")
    print(res.consistency)
    cf = res.consistent_fit
    if cf is not None and not cf.converged:
        print(f"rps3.ident: warning: the consistent fit stopped short of its optimality "
              f"test ({cf.message})", file=sys.stderr)
    if not res.consistent:
        print(f"rps3.ident: warning: {res.mapping or 'not physically consistent'}",
              file=sys.stderr)
        if args.strict:
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
