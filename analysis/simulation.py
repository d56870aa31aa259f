#!/usr/bin/env python3
"""Closed-loop tracking and simulation accuracy: figures of rps3-simstudy.

usage: simulation.py SIMSTUDY.h5 OUTDIR [--format pdf|svg|png] [--dpi DPI]

Writes OUTDIR/tracking_helix.png and OUTDIR/tracking_fast_sine.png (or
.pdf, .svg: --format): the
largest link length error |l - l_d| against time for PD, PD + gravity and
computed torque, each with the exact model (solid) and a model without link
mass (dashed, the paper's case 1); and OUTDIR/simulation_accuracy.png: the
error against a tight reference versus CPU time per simulated second, one
marker per integrator, filled for the theta tolerance 1e-12 and open for
1e-8, with the Pareto front.  Prints two markdown tables on stdout (the
largest tracking error of every run; the Pareto settings), for
docs/simulation.md.
"""

import argparse
import os

import h5py
import numpy as np
from rps3 import plot

INTEGRATORS = ("rk4", "rkf45", "rk8pd", "msbdf", "rk4imp")
COLOURS = ("tab:blue", "tab:orange", "tab:green")
MARKERS = {"rk4": "o", "rkf45": "s", "rk8pd": "D", "msbdf": "^", "rk4imp": "v"}


def text(value):
    """A string attribute as str."""
    return value.decode() if isinstance(value, bytes) else str(value)


def names(attr):
    """A comma-separated name list attribute as a list."""
    return [n.strip() for n in text(attr).split(",")]


def load_tracking(f, path):
    """time [n], error [ctrl, model, n], status, controller and model names."""
    g = f["tracking"][path]
    return {
        "time": g["time"][()],
        "error": g["error"][()],
        "status": g["status"][()],
        "controllers": names(g.attrs["controllers"]),
        "models": names(g.attrs["models"]),
    }


def plot_tracking(tr, title, out, dpi=plot.DPI):
    """Error against time for every controller and model."""
    fig, ax = plot.subplots(figsize=(7.5, 4.5))
    for a, ctrl in enumerate(tr["controllers"]):
        for b, model in enumerate(tr["models"]):
            e = np.where(tr["error"][a, b] > 0, tr["error"][a, b], np.nan)
            # the model is the controller's own: the plant is exact
            ax.semilogy(tr["time"], e, color=COLOURS[a],
                        linestyle="-" if b == 0 else "--", linewidth=1.2,
                        marker="os^"[a], markevery=0.1, markersize=4,
                        markerfacecolor="none" if b else COLOURS[a],
                        label=f"{ctrl}, controller's model: "
                              f"{model.replace('_', ' ')}")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("max_i |l_i - l_d,i| [m]")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    plot.save(fig, out, dpi)


def pareto(cost, err):
    """Indices of the points no other point beats in both cost and error."""
    order = np.argsort(cost)
    front, best = [], np.inf
    for i in order:
        if np.isfinite(err[i]) and err[i] < best:
            front.append(i)
            best = err[i]
    return front


def plot_accuracy(f, out, dpi=plot.DPI):
    """Error versus CPU per simulated second; returns the Pareto rows."""
    g = f["accuracy"]
    integ = g["integrator"][()]
    htol = g["h_or_tol"][()]
    ttol = g["theta_tol"][()]
    err = g["error"][()]
    cpu = g["cpu_per_sim_s"][()]
    fig, ax = plot.subplots(figsize=(7.5, 4.5))
    rows: list[tuple] = []
    for c in range(len(integ)):
        name = INTEGRATORS[integ[c]]
        for j, tt in enumerate(ttol):
            ax.loglog(cpu[c, j], max(err[c, j], 1e-16), MARKERS[name],
                      color=COLOURS[INTEGRATORS.index(name) % 3],
                      markerfacecolor="none" if j else None,
                      label=name if j == 0 and name not in
                      [r[0] for r in rows] else None)
            rows.append((name, htol[c], tt, err[c, j], cpu[c, j]))
    flat_cost = np.array([r[4] for r in rows])
    flat_err = np.array([max(r[3], 1e-16) for r in rows])
    front = pareto(flat_cost, flat_err)
    ax.step(flat_cost[front], flat_err[front], where="post", color="k",
            linewidth=0.8, label="Pareto front")
    ax.set_xlabel("CPU time per simulated second [s/s]")
    ax.set_ylabel("max |l - l_ref| [m]")
    dur = float(g.attrs["duration"][0])
    ax.set_title(f"computed torque, 1 kHz, fast sine ({dur:g} s): "
                 "filled theta tol 1e-12, open 1e-8")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    plot.save(fig, out, dpi)
    return [rows[i] for i in front]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("simstudy")
    ap.add_argument("outdir")
    plot.add_output_args(ap)
    args = ap.parse_args()
    os.makedirs(args.outdir, exist_ok=True)

    with h5py.File(args.simstudy, "r") as f:
        print("| path | controller | model | max \\|l - l_d\\| [m] |")
        print("|---|---|---|---|")
        for path, title in (("helix", "the paper's helix (Table II)"),
                            ("fast_sine", "a fast sine")):
            tr = load_tracking(f, path)
            plot_tracking(tr, f"tracking at 1 kHz, RK4: {title}",
                          plot.output_path(args.outdir, f"tracking_{path}",
                                           args), args.dpi)
            for a, ctrl in enumerate(tr["controllers"]):
                for b, model in enumerate(tr["models"]):
                    e = tr["error"][a, b]
                    worst = np.nanmax(e) if np.isfinite(e).any() else np.nan
                    print(f"| {path} | {ctrl} | {model} | {worst:.3g} |")
        front = plot_accuracy(
            f, plot.output_path(args.outdir, "simulation_accuracy", args),
            args.dpi)
    print()
    print("| integrator | h [s] or tol | theta tol | error [m] | "
          "CPU per simulated s |")
    print("|---|---|---|---|---|")
    for name, ht, tt, e, c in front:
        print(f"| {name} | {ht:g} | {tt:g} | {e:.3g} | {c:.3g} |")


if __name__ == "__main__":
    main()
