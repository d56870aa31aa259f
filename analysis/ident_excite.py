#!/usr/bin/env python3
"""The exciting trajectories of two general layouts (`make ident-excite`,
docs/identification.md "A general layout"): rps3.ident_paper.design with
its default optimiser settings, seeds 1-5, for identical legs with
prismatic friction (17 base parameters) and legs each (37), against ten
random Fourier series (seeds 10-19) of the amplitude asked for and of the
optimised series' own peak excursion.

usage: ident_excite.py [--seeds 1 2 3 4 5] [--out out/ident_excite.md]

Writes a Markdown table (the optimised condition number, on the design's
samples and on a grid four times finer, the random medians and the
factors, evaluations, CPU and wall time per design, the optimiser's
status) and prints it, after a line per design with the optimiser's
message, each limit's margin on the fine grid and the peak excursion.
The CPU time is the one to read on a shared machine.  Exits 1 when a
design is infeasible or below the factor 5 against the random series of
the amplitude asked for.
"""

import argparse
import os
import sys
import time
import warnings

import numpy as np
from rps3 import ident, ident_paper

AMPLITUDE = (1.5, 0.12, 0.03)
F0, HARMONICS = 0.2, 6
FACTOR = 5.0            # the requirement against random series of the amplitude
LAYOUTS = (("legs identical, prismatic friction",
            ident.Layout(legs="identical", friction=("prismatic",))),
           ("legs each, prismatic and pin friction", ident.Layout(legs="each")))


def row(name, lay, seed):
    t0, c0 = time.perf_counter(), time.process_time()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", RuntimeWarning)
        ex = ident_paper.design(layout=lay, f0=F0, harmonics=HARMONICS, amplitude=AMPLITUDE,
                                seed=seed)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    at_amp_all = ident_paper.unoptimised(ex, amplitude=AMPLITUDE)
    at_amp = float(np.median(at_amp_all))
    own = float(np.median(ident_paper.unoptimised(ex)))
    fine = ident_paper.condition(ex.fourier, layout=lay, samples=480)
    return {"name": name, "n": len(ex.base_names), "seed": seed, "start": ex.cond_start,
            "cond": ex.cond, "fine": fine, "at_amp": at_amp, "own": own, "at_amp_all": at_amp_all,
            "nfev": ex.nfev, "cpu": cpu, "wall": wall, "converged": ex.converged,
            "message": ex.message, "warned": bool(caught), "feasible": ex.feasible,
            "margin": min(ex.margins.values()), "margins": ex.margins,
            "excursion": ident_paper.excursion(ex.fourier)}


def table(rows):
    out = ["| layout (base parameters) | seed | start | optimised (fine grid) "
           "| random at the amplitude | random at its excursion | evaluations "
           "| CPU, wall time | converged |",
           "|---|---|---|---|---|---|---|---|---|"]
    last = None
    for r in rows:
        lay = f"{r['name']} ({r['n']})" if r["name"] != last else ""
        last = r["name"]
        out.append(f"| {lay} | {r['seed']} | {r['start']:.0f} | {r['cond']:.1f} ({r['fine']:.1f}) "
                   f"| {r['at_amp']:.0f} ({r['at_amp'] / r['cond']:.1f}×) "
                   f"| {r['own']:.0f} ({r['own'] / r['cond']:.1f}×) | {r['nfev']} "
                   f"| {r['cpu']:.1f} s, {r['wall']:.1f} s | {'yes' if r['converged'] else 'no'} |")
    return "\n".join(out)


def rand_range(rows):
    """The range of the random series' condition numbers at the amplitude
    asked for, per layout (their medians are in the table)."""
    out = []
    for name, _ in LAYOUTS:
        r = next((r for r in rows if r["name"] == name), None)
        if r is not None:
            c = r["at_amp_all"]
            out.append(f"{r['n']} parameters {c.min():.0f}-{c.max():.0f}")
    return ", ".join(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3, 4, 5])
    ap.add_argument("--out", default="out/ident_excite.md")
    a = ap.parse_args(argv)
    rows = []
    for name, lay in LAYOUTS:
        for seed in a.seeds:
            r = row(name, lay, seed)
            rows.append(r)
            print(f"{name}, seed {seed}: {r['cond']:.4g} (fine {r['fine']:.4g}), random "
                  f"{r['at_amp']:.4g} / {r['own']:.4g}, {r['nfev']} evaluations, "
                  f"{r['cpu']:.1f} s CPU, {r['wall']:.1f} s wall; {r['message']}; "
                  f"margins {', '.join(f'{k} {v:.3g}' for k, v in r['margins'].items())}; "
                  f"excursion {np.round(r['excursion'], 4).tolist()}",
                  flush=True)
    bad = [r for r in rows if not r["feasible"] or r["at_amp"] < FACTOR * r["cond"]]
    text = (table(rows) + "\n\n"
            f"amplitude {AMPLITUDE}, f0 {F0} Hz, {HARMONICS} harmonics; "
            f"factor {FACTOR:g} against the amplitude's random series and feasible: "
            f"{'every row' if not bad else f'{len(bad)} rows fail'}; "
            f"not converged: {sum(not r['converged'] for r in rows)}; "
            f"random series at the amplitude: {rand_range(rows)}; "
            f"load average {os.getloadavg()[0]:.2f}\n")
    os.makedirs(os.path.dirname(a.out) or ".", exist_ok=True)
    with open(a.out, "w", encoding="utf-8") as fh:
        fh.write(text)
    print(text)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
