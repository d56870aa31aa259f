#!/usr/bin/env python3
"""Tracking of a simulated scene: figure and table from rps3-run's file.

usage: closed_loop.py SIM.h5 OUT.{pdf,svg,png} [--dpi DPI]

SIM.h5 is the file rps3-run writes for a scene with a `simulate:` section
(docs/runner.md, "Simulation"), e.g. configs/closed_loop.yaml.  Draws the
largest link error max_i |l_d,i - l_i| against time, one line per case
(its own line style and marker), labelled by what its swept keys mean
("controller's model: m/M = 0.5" for simulate.model.m_over_M; a failed
case ends where it stopped, marked x), and below it the applied forces of
the case with the largest error.  OUT's suffix chooses the format.
Prints a markdown table on stdout: per case its swept values, status,
largest error and saturated ticks.
"""

import argparse

import h5py
import numpy as np
from rps3 import h5io, plot

# what a swept key's value means in a legend: the controller's own model
# of the mechanism (simulate.model.*) is not the plant's
MODEL_SYMBOLS = {"m_over_M": "m/M", "M": "M", "payload.mass": "payload mass",
                 "friction_viscous": "viscous friction",
                 "friction_coulomb": "Coulomb friction"}


def text(value):
    """A string value as str."""
    return value.decode() if isinstance(value, bytes) else str(value)


def swept(f):
    """The swept keys of the file (dotted): [(key, values per case)]."""
    return [(k, h5io.sweep_value(f, k)) for k in h5io.sweep_keys(f)]


def case_times(f, c):
    """The times of case c's samples (the common axis, or case_time)."""
    return f["case_time"][c] if "case_time" in f else f["time"][()]


def key_label(key, value):
    """What a swept value means: "pd", "controller's model: m/M = 0.5",
    "kp = 2000"."""
    v = text(value)
    if key == "simulate.controller":
        return v
    if key.startswith("simulate.model."):
        name = key[len("simulate.model."):]
        return f"controller's model: {MODEL_SYMBOLS.get(name, name)} = {v}"
    return f"{key.split('.')[-1]} = {v}"


def label(keys, c):
    """'pd, controller's model: m/M = 0' for case c."""
    if not keys:
        return f"case {c}"
    return ", ".join(key_label(k, v[c]) for k, v in keys)


def load(path):
    """Per case: times, largest link error, applied forces, status, etc."""
    with h5py.File(path, "r") as f:
        if text(f.attrs.get("content", "")) != "simulation":
            raise SystemExit(f"{path}: not a simulation file (rps3-run on a "
                             "scene with a simulate section)")
        keys = swept(f)
        cases = []
        for c in range(len(f["case"])):
            err = np.abs(f["tracking_error"][c]).max(axis=1)
            cases.append({
                "label": label(keys, c),
                "time": case_times(f, c),
                "error": err,
                "force": f["force"][c],
                "status": int(f["status"][c]),
                "failed_at": int(f["failed_at"][c]),
                "error_max": float(f["tracking_error_max"][c]),
                "nsat": int(f["nsat"][c]),
                "message": text(f["message"][c]),
            })
        return keys, cases


def draw(cases, out, dpi=plot.DPI):
    """The figure into out (the format of its suffix)."""
    return plot.save(figure(cases), out, dpi)


def figure(cases):
    """Errors of every case (each its line style and marker); the forces
    of the worst one."""
    fig, (ax, axf) = plot.subplots(2, 1, figsize=(7.5, 7.5), sharex=True,
                                   gridspec_kw={"height_ratios": [3, 2]})
    for i, cs in enumerate(cases):
        e = np.where(cs["error"] > 0, cs["error"], np.nan)
        (line,) = ax.semilogy(cs["time"], e, linewidth=1.1,
                              label=cs["label"], **plot.curve_style(i))
        if cs["status"] != 0 and cs["failed_at"] > 0:
            k = cs["failed_at"] - 1
            ax.semilogy(cs["time"][k], e[k], "x", color=line.get_color(),
                        markersize=8)
    ax.set_ylabel(r"largest link error $\max_i |l_{d,i} - l_i|$ [m]")
    ax.grid(True, which="both", alpha=0.3)
    # beside the axes: the curves fill them
    plot.legend(ax, title="controller (the plant: the scene's "
                "manipulator)", fontsize=7, title_fontsize=7,
                loc="upper left", bbox_to_anchor=(1.01, 1.0))
    worst = max(cases, key=lambda cs: cs["error_max"])
    plot.links(axf, worst["time"], worst["force"], "$F_i$", linewidth=1.0)
    axf.set_xlabel("time $t$ [s]")
    axf.set_ylabel("applied force $F_i$ [N]")
    axf.set_title(f"forces of the largest error: {worst['label']}")
    plot.legend(axf)
    return fig


def table(keys, cases):
    """Markdown rows: swept values, status, largest error, saturated ticks."""
    head = [k for k, _ in keys] + ["status", "max error [m]", "saturated"]
    rows = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for c, cs in enumerate(cases):
        vals = [text(v[c]) for _, v in keys]
        st = "ok" if cs["status"] == 0 else f"{cs['status']}: {cs['message']}"
        rows.append("| " + " | ".join(vals + [st, f"{cs['error_max']:.3g}",
                                              str(cs["nsat"])]) + " |")
    return "\n".join(rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sim", help="rps3-run's file of a simulated scene")
    ap.add_argument("out", help="the figure: .pdf, .svg or .png")
    ap.add_argument("--dpi", type=float, default=plot.DPI,
                    help=f"resolution of png output (default {plot.DPI})")
    a = ap.parse_args()
    keys, cases = load(a.sim)
    draw(cases, a.out, a.dpi)
    print(table(keys, cases))


if __name__ == "__main__":
    main()
