#!/usr/bin/env python3
"""Tracking of a simulated scene: figure and table from rps3-run's file.

usage: closed_loop.py SIM.h5 OUT.png

SIM.h5 is the file rps3-run writes for a scene with a `simulate:` section
(docs/runner.md, "Simulation"), e.g. configs/closed_loop.yaml.  Draws the
largest link error max_i |l_d,i - l_i| against time, one line per case,
labelled by its swept keys (a failed case ends where it stopped, marked
x), and below it the applied forces of the case with the largest error.
Prints a markdown table on stdout: per case its swept values, status,
largest error and saturated ticks.
"""

import argparse

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def text(value):
    """A string value as str."""
    return value.decode() if isinstance(value, bytes) else str(value)


def swept(f):
    """The swept keys of the file: [(name, values per case)]."""
    coords = text(f["length"].attrs.get("coordinates", "")).split()
    return [(k, f[k][()]) for k in coords if k != "case_time"]


def case_times(f, c):
    """The times of case c's samples (the common axis, or case_time)."""
    return f["case_time"][c] if "case_time" in f else f["time"][()]


def label(keys, c):
    """'controller=pd, m_over_M=0' for case c (the last part of each key)."""
    if not keys:
        return f"case {c}"
    return ", ".join(f"{k.split('.')[-1]}={text(v[c])}" for k, v in keys)


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


def plot(cases, out):
    """Errors of every case; the forces of the worst one."""
    fig, (ax, axf) = plt.subplots(2, 1, figsize=(7.5, 7), sharex=True,
                                  gridspec_kw={"height_ratios": [3, 2]})
    for cs in cases:
        e = np.where(cs["error"] > 0, cs["error"], np.nan)
        (line,) = ax.semilogy(cs["time"], e, linewidth=1.1,
                              label=cs["label"])
        if cs["status"] != 0 and cs["failed_at"] > 0:
            k = cs["failed_at"] - 1
            ax.semilogy(cs["time"][k], e[k], "x", color=line.get_color())
    ax.set_ylabel("max_i |l_d,i - l_i| [m]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    worst = max(cases, key=lambda cs: cs["error_max"])
    for i in range(3):
        axf.plot(worst["time"], worst["force"][:, i], linewidth=1.0,
                 label=f"F{i + 1}")
    axf.set_xlabel("time [s]")
    axf.set_ylabel("applied force [N]")
    axf.set_title(f"forces of {worst['label']}", fontsize=9)
    axf.grid(True, alpha=0.3)
    axf.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


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
    ap.add_argument("out", help="the figure (PNG)")
    a = ap.parse_args()
    keys, cases = load(a.sim)
    plot(cases, a.out)
    print(table(keys, cases))


if __name__ == "__main__":
    main()
