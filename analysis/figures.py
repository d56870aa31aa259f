#!/usr/bin/env python3
"""The paper's Figs. 2-4 from an rps3-run file of configs/paper.yaml.

usage: figures.py OUT.h5 OUTDIR [--format pdf|svg|png] [--dpi DPI]

Writes OUTDIR/fig2.FORMAT (actuating lengths vs time), fig3.FORMAT
(actuating forces, m = 0) and fig4.FORMAT (actuating forces, m/M = 0.5).
Figs. 3 and 4 share their force axis, so that the effect of link mass shows
at a glance; samples past trans_warn are marked (rps3.plot.mark_warned).
"""

import argparse
import os
import sys

import h5py
import numpy as np
from rps3 import h5io, plot


def paper_cases(f):
    """Case indices of m/M = 0 and m/M = 0.5."""
    return (h5io.case_where(f, manipulator__m_over_M=0.0),
            h5io.case_where(f, manipulator__m_over_M=0.5))


def fig_lengths(f, case, path, dpi):
    """Fig. 2: the three link lengths along the helix."""
    t = h5io.times(f)[case]
    fig, ax = plot.subplots()
    plot.links(ax, t, f["length"][case], r"$l_i$")
    plot.legend(ax)
    ax.set_xlabel("time $t$ [s]")
    ax.set_ylabel("actuating length $l_i$ [m]")
    ax.set_title("Fig. 2: actuating lengths along the helix")
    plot.save(fig, path, dpi)


def fig_forces(f, case, ylim, title, path, dpi):
    """Figs. 3-4 into path."""
    plot.save(forces_figure(f, case, ylim, title), path, dpi)


def forces_figure(f, case, ylim, title):
    """Figs. 3-4: the three actuating forces of one case, warned samples
    marked."""
    t = h5io.times(f)[case]
    fig, ax = plot.subplots()
    force = f["force"][case]
    plot.links(ax, t, force, r"$F_i$")
    if plot.mark_warned(ax, t, force, f["warn"][case]) is not None:
        plot.note(fig, plot.WARNED_NOTE)
    plot.legend(ax)
    ax.set_ylim(*ylim)
    ax.set_xlabel("time $t$ [s]")
    ax.set_ylabel("actuating force $F_i$ [N] (> 0 extends)")
    ax.set_title(title)
    return fig


def make_figures(h5path, outdir, fmt="png", dpi=plot.DPI):
    """Write fig2, fig3 and fig4 (format fmt) into outdir; return their
    paths."""
    os.makedirs(outdir, exist_ok=True)
    paths = [os.path.join(outdir, f"fig{n}.{fmt}") for n in (2, 3, 4)]
    with h5py.File(h5path, "r") as f:
        bad = h5io.failed(f)
        if bad:
            raise SystemExit(f"{h5path}: failed cases {bad}")
        c0, c1 = paper_cases(f)
        force = f["force"][()]
        lo, hi = np.nanmin(force[[c0, c1]]), np.nanmax(force[[c0, c1]])
        pad = 0.1 * (hi - lo)
        ylim = (lo - pad, hi + pad)
        fig_lengths(f, c0, paths[0], dpi)
        fig_forces(f, c0, ylim, "Fig. 3: actuating forces, $m = 0$",
                   paths[1], dpi)
        m = float(h5io.sweep_value(f, "manipulator.m_over_M")[c1])
        fig_forces(f, c1, ylim,
                   f"Fig. 4: actuating forces, $m/M = {m:g}$", paths[2], dpi)
    return paths


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("h5", help="rps3-run output of configs/paper.yaml")
    ap.add_argument("outdir", help="directory for fig2, fig3, fig4")
    plot.add_output_args(ap)
    args = ap.parse_args(argv)
    for p in make_figures(args.h5, args.outdir, args.format, args.dpi):
        print(p)
    return 0


if __name__ == "__main__":
    sys.exit(main())
