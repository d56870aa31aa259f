#!/usr/bin/env python3
"""The shipped "measured motion" (configs/measured.csv): how it was made, and
what its forces are worth.

usage: measured.py generate CSV
       measured.py generate-path CSV
       measured.py figure RUN.h5 OUTDIR

`generate` writes the table configs/measured.csv holds: a smooth motion of
the pose (motion() below, a slow sweep of the tilt azimuth alpha with a
varying tilt beta and a heave of z_c, the kind of motion a hand-guided or
motion-captured platform makes) sampled at 50 Hz for 8 s with a timestamp
jitter of +-0.5 ms, plus Gaussian measurement noise of 2e-5 rad on the
angles and 2e-6 m on z_c (an 18-bit encoder's count is 2.4e-5 rad), from a
fixed seed, written with 9 significant digits.  Run again it writes the
same bytes (tests/test_measured.py checks this).

`generate-path` writes configs/path_table.csv: a path of the platform
centre (x, y, z) as a CAM program or a path planner would export it, a
figure-eight beside the Z axis (centre_path() below) every 10 ms for 6 s,
without noise; configs/path_table.yaml runs it as a path of shape table.

`figure` draws OUTDIR/measured.png from a run of configs/measured.yaml: the
rows against the smooth motion they were sampled from, and the forces the
runner computed from the rows (the not-a-knot spline's rates and
accelerations) against the forces of the smooth motion itself (computed
here through the rps3 package from motion()'s exact derivatives).  The
difference is what the noise costs: the spline passes through every noisy
row, and its acceleration amplifies noise of size e by ~e / h^2.  It prints
the largest force error, absolute and relative to the largest force.
"""

import argparse
import os
import sys

import numpy as np

SPAN, RATE = 8.0, 50.0       # [s], [Hz]
JITTER = 0.5e-3              # timestamp jitter, uniform +- [s]
NOISE = (2e-5, 2e-5, 2e-6)   # measurement noise sigma [rad, rad, m]
SEED = 20260522


def motion(t):
    """The smooth motion: pose, rate, acceleration at times t, each (n, 3)
    [rad, rad, m] and their derivatives."""
    t = np.asarray(t, dtype=float)
    w = (0.25 * np.pi, 1.3, 0.9, 0.7)
    q = np.stack([0.6 * np.sin(w[0] * t) + 0.1 * np.sin(w[1] * t),
                  0.09 + 0.04 * np.sin(w[2] * t + 0.3),
                  0.30 + 0.015 * np.sin(w[3] * t)], axis=1)
    dq = np.stack([0.6 * w[0] * np.cos(w[0] * t) + 0.1 * w[1] * np.cos(w[1] * t),
                   0.04 * w[2] * np.cos(w[2] * t + 0.3),
                   0.015 * w[3] * np.cos(w[3] * t)], axis=1)
    ddq = np.stack([-0.6 * w[0] ** 2 * np.sin(w[0] * t)
                    - 0.1 * w[1] ** 2 * np.sin(w[1] * t),
                    -0.04 * w[2] ** 2 * np.sin(w[2] * t + 0.3),
                    -0.015 * w[3] ** 2 * np.sin(w[3] * t)], axis=1)
    return q, dq, ddq


def samples():
    """The rows: jittered times and noisy poses (deterministic)."""
    rng = np.random.default_rng(SEED)
    n = int(round(SPAN * RATE)) + 1
    t = np.arange(n) / RATE
    t[1:-1] += rng.uniform(-JITTER, JITTER, n - 2)
    q = motion(t)[0] + rng.normal(0.0, 1.0, (n, 3)) * np.array(NOISE)
    return t, q


def generate(path):
    t, q = samples()
    with open(path, "w") as f:
        f.write("# A measured motion of the platform (docs/trajectories.md):\n"
                "# written by `analysis/measured.py generate` from a smooth\n"
                f"# motion sampled at {RATE:g} Hz with +-{JITTER * 1e3:g} ms "
                "timestamp jitter\n"
                f"# and noise of {NOISE[0]:g} rad, {NOISE[1]:g} rad, "
                f"{NOISE[2]:g} m (seed {SEED}).\n"
                "# t [s], alpha [rad], beta [rad], z_c [m]\n"
                "t, alpha, beta, z_c\n")
        for ti, qi in zip(t, q):
            f.write(f"{ti:.6f}, {qi[0]:.9g}, {qi[1]:.9g}, {qi[2]:.9g}\n")


def centre_path(t):
    """The figure-eight of the centre [m] at times t, (n, 3): 1 to 3 mm
    from the Z axis (tilts of 11 to 19 degrees: the centre's x and y cost
    tilt, (3)-(4)), well inside r/2 = 57 mm."""
    t = np.asarray(t, dtype=float)
    w = 2 * np.pi / 6.0
    return np.stack([0.002 + 0.001 * np.sin(w * t),
                     0.0012 * np.sin(2 * w * t),
                     0.30 + 0.005 * (1 - np.cos(w * t))], axis=1)


def generate_path(path):
    t = np.arange(601) / 100.0
    c = centre_path(t)
    with open(path, "w") as f:
        f.write("# A path of the platform centre (docs/trajectories.md):\n"
                "# written by `analysis/measured.py generate-path`, a\n"
                "# figure-eight beside the Z axis every 10 ms for 6 s.\n"
                "# t [s], x [m], y [m], z [m]\n"
                "t, x, y, z\n")
        for ti, ci in zip(t, c):
            f.write(f"{ti:.2f}, {ci[0]:.9g}, {ci[1]:.9g}, {ci[2]:.9g}\n")


def truth_forces(f):
    """Forces of the smooth motion at the run's times, for the run's model
    (read from its resolved scene), through the rps3 package."""
    import yaml
    from rps3 import Model, h5io
    scene = yaml.safe_load(h5io.text(f["scene_resolved"][0]))
    man = scene["manipulator"]
    keys = {k: man[k] for k in ("R", "rho", "M", "d", "g") if k in man}
    keys.update({k: man[k] for k in ("m_over_M", "m") if k in man})
    model = Model(effects=scene["effects"], **keys)
    t = h5io.times(f)[0]
    # the first row is at t = 0 (no jitter there): the case's time is the
    # motion's
    q, dq, ddq = motion(t)
    return model.inverse(q, dq, ddq).force


def figure(h5, outdir, fmt="png", dpi=None):
    import h5py
    from rps3 import h5io, plot
    with h5py.File(h5, "r") as f:
        t = h5io.times(f)[0]
        force = f["force"][0]
        warn = f["warn"][0]
        want = truth_forces(f)
    rows_t, rows_q = samples()
    smooth = motion(rows_t)[0]
    err = np.abs(force - want)
    scale = np.abs(want).max()
    fig, axs = plot.subplots(3, 1, figsize=(9.6, 9.0), sharex=True)
    ax = axs[0]
    for k, (name, f_) in enumerate((("alpha", 1.0), ("beta", 10.0),
                                    ("z_c", 10.0))):
        ax.plot(rows_t, f_ * rows_q[:, k], ".", ms=2.5, label=f"{name} rows"
                + ("" if f_ == 1 else f" x{f_:g}"))
        ax.plot(rows_t, f_ * smooth[:, k], "k-", lw=0.6)
    ax.set_ylabel("pose [rad, m]")
    ax.set_title("configs/measured.csv: rows (dots) and the smooth motion "
                 "they sample (lines)")
    ax.legend(loc="best", fontsize=8)
    ax.grid(True, alpha=0.3)
    ax = axs[1]
    for i, style in enumerate(("-", "--", ":")):
        ax.plot(t, force[:, i], "k" + style, lw=1.0, label=f"$F_{i + 1}$ "
                "from the table")
        ax.plot(t, want[:, i], style, color="tab:red", lw=1.0,
                label=f"$F_{i + 1}$ of the smooth motion")
    if plot.mark_warned(ax, t, force, warn) is not None:
        plot.note(fig, plot.WARNED_NOTE)
    ax.set_ylabel("force [N]")
    ax.legend(loc="best", fontsize=8)
    ax.grid(True, alpha=0.3)
    ax = axs[2]
    for i, style in enumerate(("-", "--", ":")):
        ax.plot(t, err[:, i], "k" + style, lw=0.8, label=f"$F_{i + 1}$")
    ax.set_ylabel("|F(table) - F(smooth)| [N]")
    ax.set_xlabel("time $t$ [s]")
    ax.set_title(f"what the noise costs: at most {err.max():.3g} N "
                 f"({100 * err.max() / scale:.2g} % of the largest force)")
    ax.legend(loc="best", fontsize=8)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    path = plot.save(fig, os.path.join(outdir, f"measured.{fmt}"), dpi)
    print(f"{path}: largest force error {err.max():.3g} N, "
          f"{err.max() / scale:.3g} of the largest force {scale:.3g} N")
    return err.max() / scale


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    g = sub.add_parser("generate", help="write the table")
    g.add_argument("csv")
    gp = sub.add_parser("generate-path", help="write the centre's table")
    gp.add_argument("csv")
    fg = sub.add_parser("figure", help="draw OUTDIR/measured.FORMAT")
    fg.add_argument("h5")
    fg.add_argument("outdir")
    fg.add_argument("--format", choices=("pdf", "svg", "png"), default="png")
    fg.add_argument("--dpi", type=float, default=None,
                    help="resolution of png output (default rps3.plot.DPI)")
    a = ap.parse_args(argv)
    if a.cmd == "generate":
        generate(a.csv)
    elif a.cmd == "generate-path":
        generate_path(a.csv)
    else:
        figure(a.h5, a.outdir, a.format, a.dpi)
    return 0


if __name__ == "__main__":
    sys.exit(main())
