#!/usr/bin/env python3
"""What accuracy costs in time: the plot and table of `rps3-study accuracy`.

usage: accuracy_cost.py ACCURACY.h5 OUTDIR

Writes OUTDIR/accuracy_cost.png (or .pdf, .svg: --format; --dpi): for
each trajectory, the force error
against the reference vs the median time per point (log-log), one marker per
configuration coloured by the knob it turns, the Pareto fronts (no other
configuration is both faster and more accurate) over all numerical knobs,
within the multiroot theta solves and within the finite-difference rates,
drawn as step lines; the effects ladder shown apart as model error; and
a second row for the sample interval, where the cost is the time to compute
one second of trajectory.  Prints the recommended settings (the Pareto
points) as a markdown table on stdout, for docs/accuracy.md.
"""

import argparse
import os
import sys

import h5py
import numpy as np
from rps3 import h5io, plot

STUDY_STYLE = {
    "theta": ("o", "tab:blue"),
    "derivative": ("s", "tab:orange"),
    "method": ("D", "tab:green"),
    "effects": ("^", "tab:red"),
}


def load(f):
    """The accuracy file as a dict of numpy arrays, axes via dimension scales."""
    for name in ("force_error", "ns_per_point"):
        if h5io.dims(f[name]) != ("trajectory", "config"):
            raise ValueError(f"{name}: unexpected axes {h5io.dims(f[name])}")
    out = {k: f[k][()] for k in (
        "ns_per_point", "ns_per_second", "force_error", "theta_error",
        "peak_force_error", "energy_residual", "failed_samples", "status",
        "reference_floor_force", "fd_step", "tolerance", "warm_start",
        "dt_fraction")}
    for k in ("study", "label", "solver", "derivative", "method"):
        out[k] = np.array([h5io.text(x) for x in f[k][()]])
    out["trajectory"] = [h5io.text(x) for x in
                         f["force_error"].dims[0][0][()]]
    return out


def pareto(cost, err):
    """Indices of the Pareto front (min cost, min error), by rising cost."""
    order = np.lexsort((err, cost))
    front, best = [], np.inf
    for i in order:
        if err[i] < best:
            front.append(i)
            best = err[i]
    return np.array(front, dtype=int)


def plotted_error(err, floor):
    """Errors below the reference's floor are shown at the floor."""
    return np.maximum(err, floor)


# Pareto fronts: over every numerical knob (the model fixed: the paper's
# four effects), and within the routes a user may be forced onto: theta
# from measured link lengths (multiroot) and rates from measured positions
# (finite differences, or the spline of a table of poses).  The effects
# ladder changes the model, not the numerics: its "error" is the share of
# the effects left out, shown apart.
FRONTS = {
    "all numerical knobs": lambda a: np.isin(a["study"],
                                             ("theta", "derivative", "method")),
    "theta by multiroot": lambda a: (a["study"] == "theta") &
    (a["solver"] != ""),
    "rates from positions": lambda a: (a["study"] == "derivative") &
    (a["derivative"] != "exact"),
}
FRONT_STYLE = {"all numerical knobs": ("k", "-"),
               "theta by multiroot": ("tab:blue", "--"),
               "rates from positions": ("tab:orange", ":")}


def usable(a, t):
    """Configurations with every sample computed and a finite error."""
    return (a["failed_samples"][t] == 0) & np.isfinite(a["force_error"][t])


def accuracy_panel(ax, a, t):
    """Error vs ns/point for the theta, derivative, method, effects knobs."""
    floor = a["reference_floor_force"][t]
    ok = usable(a, t)
    cost = a["ns_per_point"][t]
    err = plotted_error(a["force_error"][t], floor)
    for s, (marker, color) in STUDY_STYLE.items():
        m = ok & (a["study"] == s)
        label = s if s != "effects" else "effects left out (model error)"
        ax.loglog(cost[m], err[m], marker, color=color, ms=4, alpha=0.7,
                  ls="none", mfc="none" if s == "effects" else color,
                  label=label)
    fronts = {}
    for name, pick in FRONTS.items():
        idx = np.flatnonzero(ok & pick(a))
        front = idx[pareto(cost[idx], err[idx])]
        fronts[name] = front
        color, ls = FRONT_STYLE[name]
        ax.step(cost[front], err[front], where="post", color=color, ls=ls,
                lw=1.2, label=f"Pareto front: {name}")
        ax.loglog(cost[front], err[front], "o", mfc="none", mec=color, ms=9)
    ax.axhline(floor, color="grey", ls=":", lw=1,
               label="reference floor (long double, study_ref.c)")
    ax.set_xlabel("median time per point [ns]")
    ax.set_ylabel("max |F - F_ref| / max |F_ref|")
    ax.set_title(f"{a['trajectory'][t]}: knobs at a fixed sample grid")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6, loc="upper right")
    return fronts


def dt_panel(ax, a, t):
    """Sample interval: peak force and energy residual vs ns per second."""
    for deriv, ls in (("exact", "-"), ("fd_samples", "--")):
        m = (a["study"] == "dt") & (a["derivative"] == deriv)
        cost = a["ns_per_second"][t][m]
        o = np.argsort(cost)
        ax.loglog(cost[o], np.maximum(a["peak_force_error"][t][m][o], 1e-17),
                  "o" + ls, color="tab:purple", ms=4,
                  label=f"peak |F| error, {deriv} rates")
        ax.loglog(cost[o], a["energy_residual"][t][m][o], "s" + ls,
                  color="tab:brown", ms=4,
                  label=f"work-energy residual, {deriv} rates")
    ax.set_xlabel("time to compute 1 s of trajectory [ns]")
    ax.set_ylabel("relative error")
    ax.set_title(f"{a['trajectory'][t]}: sample interval dt")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="lower left")


def table(a, fronts):
    """Markdown table of the Pareto settings per trajectory and front."""
    rows = ["| trajectory | front | setting | force error | theta error [rad] "
            "| ns/point |", "|---|---|---|---|---|---|"]
    for t, by_front in enumerate(fronts):
        for name, front in by_front.items():
            for i in front:
                rows.append(
                    f"| {a['trajectory'][t]} | {name} "
                    f"| {a['study'][i]}: {a['label'][i]} "
                    f"| {a['force_error'][t][i]:.1e} "
                    f"| {a['theta_error'][t][i]:.1e} "
                    f"| {a['ns_per_point'][t][i]:.0f} |")
    return "\n".join(rows)


def report_failures(a):
    """Say which configurations lost samples (left out of the plot and the
    fronts), so that a failing setting cannot pass for a missing one."""
    for t, traj in enumerate(a["trajectory"]):
        for j in np.flatnonzero(a["failed_samples"][t] > 0):
            print(f"warning: {traj}: {a['label'][j]}: "
                  f"{int(a['failed_samples'][t][j])} samples failed "
                  f"(first status {int(a['status'][t][j])}); left out",
                  file=sys.stderr)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("h5")
    p.add_argument("outdir")
    plot.add_output_args(p)
    args = p.parse_args(argv)
    with h5py.File(args.h5, "r") as f:
        a = load(f)
    nt = len(a["trajectory"])
    fig, axes = plot.subplots(2, nt, figsize=(6.5 * nt, 10), squeeze=False)
    fronts = []
    for t in range(nt):
        fronts.append(accuracy_panel(axes[0][t], a, t))
        dt_panel(axes[1][t], a, t)
    fig.suptitle("rps3: error against the reference vs time per point")
    fig.tight_layout()
    os.makedirs(args.outdir, exist_ok=True)
    out = plot.save(fig, plot.output_path(args.outdir, "accuracy_cost", args),
                    args.dpi)
    print(f"wrote {out}", file=sys.stderr)
    report_failures(a)
    print(table(a, fronts))
    return 0


if __name__ == "__main__":
    sys.exit(main())
