#!/usr/bin/env python3
"""Slices of the workspace map of `rps3-study workspace`.

usage: workspace.py WORKSPACE.h5 OUTDIR [--alpha ALPHA]

Writes OUTDIR/workspace.png (or .pdf, .svg: --format; --dpi): for each
rho (rows), at the alpha nearest to
ALPHA (default 0.3 rad), the (beta, z_c) plane coloured by the log10 of
the force transmission (the largest actuator force per unit platform
load, dimensionless), with the unreachable region blank, the other assembly
mode hatched and the warning level 100 drawn; and the static force holding
the platform in the safe region.  Prints, per rho, the fraction of the grid
that is reachable, in the home assembly mode and below the transmission
warning level: the safe operating region.  (The condition number of the
lambda system measures lost digits, not force: it stays at 3 while a level
platform is lowered onto the base and its forces grow without bound.)
"""

import argparse
import os
import sys

import h5py
import numpy as np
from matplotlib.colors import LogNorm
from rps3 import h5io, plot

TRANS_WARN = 100.0  # opt.trans_warn, the library's default


def load(f):
    """The map and its axes, found through the dimension scales."""
    names = h5io.dims(f["condition"])
    if names != ("rho", "alpha", "beta", "z_c"):
        raise ValueError(f"condition: unexpected axes {names}")
    axes = {n: f["condition"].dims[k][0][()] for k, n in enumerate(names)}
    data = {k: f[k][()] for k in ("status", "condition", "transmission",
                                  "mode", "max_force")}
    return axes, data


def safe(data):
    """Reachable, home assembly mode, transmission below the warning level."""
    return (data["status"] == 0) & (data["mode"] == 1) & \
        (data["transmission"] < TRANS_WARN)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("h5")
    p.add_argument("outdir")
    p.add_argument("--alpha", type=float, default=0.3)
    plot.add_output_args(p)
    args = p.parse_args(argv)
    with h5py.File(args.h5, "r") as f:
        axes, data = load(f)
    ia = int(np.argmin(np.abs(axes["alpha"] - args.alpha)))
    nr = len(axes["rho"])
    fig, ax = plot.subplots(nr, 2, figsize=(12, 4 * nr), squeeze=False)
    extent = [axes["beta"][0], axes["beta"][-1], axes["z_c"][0],
              axes["z_c"][-1]]
    ok = safe(data)
    for r, rho in enumerate(axes["rho"]):
        cond = data["transmission"][r, ia].T   # [z_c, beta]
        mode = data["mode"][r, ia].T
        force = data["max_force"][r, ia].T
        im = ax[r][0].imshow(np.log10(cond), origin="lower", extent=extent,
                             aspect="auto", cmap="viridis", vmin=0, vmax=8)
        fig.colorbar(im, ax=ax[r][0], label="log10 force transmission")
        bb, zz = np.meshgrid(axes["beta"], axes["z_c"])
        ax[r][0].contourf(bb, zz, (mode == -1).astype(float), levels=[0.5, 1.5],
                          colors="none", hatches=["//"])
        ax[r][0].contour(bb, zz, np.log10(cond), levels=[np.log10(TRANS_WARN)],
                         colors="r", linewidths=1)
        ax[r][0].set_title(f"rho = {rho:g}, alpha = {axes['alpha'][ia]:.3f} "
                           "rad: transmission (hatched: other assembly "
                           "mode, red: 100)", fontsize=9)
        # log scale: the force grows like the transmission towards the
        # singular surface
        im = ax[r][1].imshow(np.where(ok[r, ia].T, force, np.nan),
                             origin="lower", extent=extent, aspect="auto",
                             cmap="magma", norm=LogNorm())
        fig.colorbar(im, ax=ax[r][1], label="max |F_i| to hold [N]")
        ax[r][1].set_title(f"rho = {rho:g}: static holding force in the safe "
                           "region", fontsize=9)
        for a in ax[r]:
            a.set_xlabel("beta [rad]")
            a.set_ylabel("z_c [m]")
        frac = ok[r].mean()
        reach = (data["status"][r] == 0).mean()
        print(f"rho = {rho:g}: reachable {reach:.1%}, safe (home mode, "
              f"transmission < 100) {frac:.1%} of the grid; max holding force in "
              f"the safe region {np.nanmax(np.where(ok[r], data['max_force'][r], np.nan)):.3g} N")
    fig.tight_layout()
    os.makedirs(args.outdir, exist_ok=True)
    out = plot.save(fig, plot.output_path(args.outdir, "workspace", args),
                    args.dpi)
    print(f"wrote {out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
