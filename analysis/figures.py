#!/usr/bin/env python3
"""The paper's Figs. 2-4 from an rps3-run file of configs/paper.yaml.

usage: figures.py OUT.h5 OUTDIR

Writes OUTDIR/fig2.png (actuating lengths vs time), fig3.png (actuating
forces, m = 0) and fig4.png (actuating forces, m/M = 0.5).  Figs. 3 and 4
share their force axis, so that the effect of link mass shows at a glance.
"""

import argparse
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from rps3 import h5io  # noqa: E402

LINK_STYLES = ("-", "--", ":")


def paper_cases(f):
    """Case indices of m/M = 0 and m/M = 0.5."""
    return (h5io.case_where(f, manipulator__m_over_M=0.0),
            h5io.case_where(f, manipulator__m_over_M=0.5))


def plot_links(ax, t, y, label):
    """Three curves, one per link, in the paper's order."""
    for i in range(y.shape[-1]):
        ax.plot(t, y[:, i], LINK_STYLES[i], color="k", lw=1.2,
                label=f"{label} {i + 1}")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best")


def fig_lengths(f, case, path):
    """Fig. 2: the three link lengths along the helix."""
    t = h5io.times(f)[case]
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    plot_links(ax, t, f["length"][case], r"$l_i$, link")
    ax.set_xlabel("time $t$ [s]")
    ax.set_ylabel("actuating length $l_i$ [m]")
    ax.set_title("Fig. 2: actuating lengths along the helix")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def fig_forces(f, case, ylim, title, path):
    """Figs. 3-4: the three actuating forces of one case."""
    t = h5io.times(f)[case]
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    plot_links(ax, t, f["force"][case], r"$F_i$, link")
    ax.set_ylim(*ylim)
    ax.set_xlabel("time $t$ [s]")
    ax.set_ylabel("actuating force $F_i$ [N] (> 0 extends)")
    ax.set_title(title)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def make_figures(h5path, outdir):
    """Write fig2.png, fig3.png and fig4.png into outdir; return their paths."""
    os.makedirs(outdir, exist_ok=True)
    paths = [os.path.join(outdir, f"fig{n}.png") for n in (2, 3, 4)]
    with h5py.File(h5path, "r") as f:
        bad = h5io.failed(f)
        if bad:
            raise SystemExit(f"{h5path}: failed cases {bad}")
        c0, c1 = paper_cases(f)
        force = f["force"][()]
        lo, hi = np.nanmin(force[[c0, c1]]), np.nanmax(force[[c0, c1]])
        pad = 0.1 * (hi - lo)
        ylim = (lo - pad, hi + pad)
        fig_lengths(f, c0, paths[0])
        fig_forces(f, c0, ylim, "Fig. 3: actuating forces, $m = 0$",
                   paths[1])
        m = float(f["manipulator.m_over_M"][c1])
        fig_forces(f, c1, ylim,
                   f"Fig. 4: actuating forces, $m/M = {m:g}$", paths[2])
    return paths


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("h5", help="rps3-run output of configs/paper.yaml")
    ap.add_argument("outdir", help="directory for fig2.png, fig3.png, fig4.png")
    args = ap.parse_args(argv)
    for p in make_figures(args.h5, args.outdir):
        print(p)
    return 0


if __name__ == "__main__":
    sys.exit(main())
