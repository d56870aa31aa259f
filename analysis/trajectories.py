#!/usr/bin/env python3
"""One figure per trajectory run (waypoints, path): the motion asked for
and the forces it takes.

usage: trajectories.py OUTDIR RUN.h5 [RUN.h5 ...] [--format F] [--dpi DPI]

For each RUN.h5 (case 0) writes OUTDIR/traj_NAME.FORMAT, NAME the file's
stem:
top left the platform centre seen from above (x_c, y_c), top right the pose
(alpha, beta in degrees, z_c in mm) against time, bottom the three actuating
forces against time, samples past trans_warn marked with grey x (a note
under the figure says why).  `make trajectories` runs the shipped configs
(pick_place, circle, line, paper_path) and draws them.
"""

import argparse
import os

import h5py
import numpy as np
from rps3 import h5io, plot


def figure(h5, path, dpi=plot.DPI):
    """Draw run h5 into path (the format of its suffix)."""
    return plot.save(draw(h5), path, dpi)


def draw(h5):
    """The figure of run h5 (case 0)."""
    with h5py.File(h5, "r") as f:
        t = h5io.times(f)[0]
        x, y, z = (f[k][0] for k in ("x_c", "y_c", "z_c"))
        a, b = f["alpha"][0], f["beta"][0]
        force = f["force"][0]
        warn = f["warn"][0]
        kind = h5io.text(f["scene_resolved"][0]).split("kind:")[1].split()[0]
    fig = plot.figure(figsize=(9.6, 7.2))
    ax = fig.add_subplot(2, 2, 1)
    ax.plot(1e3 * x, 1e3 * y, "k-", lw=1.2)
    ax.plot(1e3 * x[0], 1e3 * y[0], "ko", label="start")
    ax.plot(1e3 * x[-1], 1e3 * y[-1], "ks", mfc="none", label="end")
    ax.plot(0, 0, "k+", ms=10, label="Z axis")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("$x_c$ [mm]")
    ax.set_ylabel("$y_c$ [mm]")
    ax.set_title(f"platform centre from above ({kind})")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    ax = fig.add_subplot(2, 2, 2)
    ax.plot(t, np.degrees(a), "k-", lw=1.2, label=r"$\alpha$ [deg]")
    ax.plot(t, np.degrees(b), "k--", lw=1.2, label=r"$\beta$ [deg]")
    ax2 = ax.twinx()
    ax2.plot(t, 1e3 * z, "k:", lw=1.2, label="$z_c$ [mm]")
    ax2.set_ylabel("$z_c$ [mm]")
    ax.set_xlabel("time $t$ [s]")
    ax.set_ylabel("angle [deg]")
    ax.set_title("pose")
    ax.grid(True, alpha=0.3)
    lines = ax.get_legend_handles_labels()
    lines2 = ax2.get_legend_handles_labels()
    ax.legend(lines[0] + lines2[0], lines[1] + lines2[1], loc="best",
              fontsize=8)
    ax = fig.add_subplot(2, 1, 2)
    plot.links(ax, t, force, "$F_i$")
    if plot.mark_warned(ax, t, force, warn) is not None:
        plot.note(fig, plot.WARNED_NOTE)
    ax.set_xlabel("time $t$ [s]")
    ax.set_ylabel("actuating force $F_i$ [N]")
    plot.legend(ax)
    fig.tight_layout()
    return fig


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("outdir")
    p.add_argument("runs", nargs="+")
    plot.add_output_args(p)
    args = p.parse_args(argv)
    os.makedirs(args.outdir, exist_ok=True)
    for h5 in args.runs:
        name = os.path.splitext(os.path.basename(h5))[0]
        out = plot.output_path(args.outdir, f"traj_{name}", args)
        figure(h5, out, args.dpi)
        print(out)


if __name__ == "__main__":
    main()
