#!/usr/bin/env python3
"""One figure with the key numbers of every config's run.

usage: summary.py OUT.png H5 [H5 ...]

For each file (an rps3-run output of a config with one or more swept keys)
one panel: the peak actuating force max|F| over time and links, per case,
against the first swept key (one line per value of the other keys), and
the share of inertia in it on a second axis when the file has inertial
effects.  The T* sweep (configs/period.yaml) is drawn on log axes.
"""

import argparse
import math
import os
import sys

import h5py
import numpy as np
from rps3 import h5io, plot


def key_numbers(f):
    """Per case: peak |F| [N] and the peak inertial share over the peak
    gravity share (NaN for failed cases)."""
    force = f["force"][()]
    peak = np.nanmax(np.abs(force), axis=(1, 2))
    iner = np.nanmax(np.abs(h5io.effect_sum(f, h5io.INERTIA_EFFECTS)),
                     axis=(1, 2))
    grav = np.nanmax(np.abs(h5io.effect_sum(f, h5io.GRAVITY_EFFECTS)),
                     axis=(1, 2))
    with np.errstate(invalid="ignore", divide="ignore"):
        share = iner / grav
    return peak, share


def panel(ax, path):
    """Peak force against the first swept key of the file at `path`."""
    with h5py.File(path, "r") as f:
        sv = h5io.sweep_values(f)
        peak, share = key_numbers(f)
        units = {k: h5io.text(f[h5io.key_name(k)].attrs["units"])
                 for k in sv}
    name = os.path.basename(path)
    if not sv:
        ax.set_title(f"{name}: no sweep")
        return
    keys = list(sv)
    x = sv[keys[0]]
    if x.dtype.kind in "SO":
        x = np.array([h5io.text(v) for v in x])
    other = [tuple(sv[k][c] for k in keys[1:]) for c in range(len(x))]
    for combo in dict.fromkeys(other):
        sel = [c for c in range(len(x)) if other[c] == combo]
        label = ", ".join(f"{k.split('.')[-1]}={h5io.text(v) if isinstance(v, bytes) else f'{v:g}'}"
                          for k, v in zip(keys[1:], combo)) or "max|F|"
        ax.plot(x[sel], peak[sel], "o-", ms=3, lw=1, label=label)
    logx = keys[0] == "trajectory.period"
    if logx:
        ax.set_xscale("log")
        ax.set_yscale("log")
    ax.set_xlabel(f"{keys[0]} [{units[keys[0]]}]")
    ax.set_ylabel("peak |F| [N]")
    ax.set_title(name)
    ax.grid(True, alpha=0.3)
    if len(set(other)) <= 6:
        ax.legend(fontsize=6)
    if np.nanmax(share) > 0 and len(set(other)) == 1:
        ax2 = ax.twinx()
        ax2.plot(x, share, "s--", ms=3, color="tab:red", lw=1)
        ax2.set_ylabel("inertia / gravity", color="tab:red")
        if logx:
            ax2.set_yscale("log")


def make_summary(out, paths, dpi=plot.DPI):
    n = len(paths)
    cols = min(3, n)
    rows = math.ceil(n / cols)
    fig, axes = plot.subplots(rows, cols, figsize=(5.2 * cols, 3.8 * rows),
                             squeeze=False)
    for ax, path in zip(axes.flat, paths):
        panel(ax, path)
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    fig.tight_layout()
    return plot.save(fig, out, dpi)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", help="the figure: .pdf, .svg or .png")
    ap.add_argument("h5", nargs="+", help="rps3-run outputs")
    ap.add_argument("--dpi", type=float, default=plot.DPI,
                    help=f"resolution of png output (default {plot.DPI})")
    args = ap.parse_args(argv)
    print(make_summary(args.out, args.h5, args.dpi))
    return 0


if __name__ == "__main__":
    sys.exit(main())
