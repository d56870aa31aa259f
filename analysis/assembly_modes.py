#!/usr/bin/env python3
"""The assembly modes of the mechanism, computed here from the paper's
geometry alone (numpy, independent of the C library).

usage: assembly_modes.py OUTDIR [--alpha ALPHA]

Writes OUTDIR/assembly_modes.png (or .pdf, .svg: --format; --dpi).  Left: the (beta, z_c) plane at
alpha = ALPHA (default 0.5 rad) for Table II's mechanism, coloured by the
sign of det(df/dtheta) of each pose's own configuration (eq. (39)): +1 the
level platform's side, -1 the other; the boundary is the singular surface.
Right: the pose (0.5, 0.9, 0.2 m), beyond that surface, and the other
configuration with the same three link lengths -- the root of (8)-(10) a
solve started from the level platform reaches.  Same lengths, other
platform, other forces: why rps3_inverse's multiroot route checks its root
against (39) and rps3_fk reports the mode.
"""

import argparse
import os

import numpy as np
from rps3 import plot

R, RHO = 0.2286, 0.5           # Table II
r = RHO * R
PSI = np.array([0.0, 2 * np.pi / 3, 4 * np.pi / 3])
U = np.stack([np.cos(PSI), np.sin(PSI), 0 * PSI], axis=1)     # radial units
PINS = R * U


def balls_of_pose(alpha, beta, zc):
    """Ball joints b_i of pose (alpha, beta, z_c): (1)-(4), (15)-(17)."""
    ca, sa, cb, sb = np.cos(alpha), np.sin(alpha), np.cos(beta), np.sin(beta)
    vb = 1 - cb
    rot = np.array([[1 - vb * ca * ca, -vb * ca * sa, sb * ca],
                    [-vb * ca * sa, 1 - vb * sa * sa, sb * sa],
                    [-sb * ca, -sb * sa, cb]])
    c = np.array([-0.5 * r * vb * np.cos(2 * alpha),
                  0.5 * r * vb * np.sin(2 * alpha), zc])
    return c + (rot @ (r * U).T).T


def joints_of_balls(b):
    """Link lengths and angles (39) of ball joints b."""
    v = b - PINS
    l = np.linalg.norm(v, axis=1)
    th = np.arctan2(v[:, 2], -np.sum(v * U, axis=1))
    return l, th


def balls_of_joints(l, th):
    """(12)-(14): b_i = P_i + l_i (-cos th_i u_i + sin th_i e_z)."""
    phi = -np.cos(th)[:, None] * U + np.sin(th)[:, None] * np.array([0, 0, 1])
    return PINS + l[:, None] * phi


def det_jt(l, th):
    """det(df/dtheta) for f_k = |b_i - b_j|^2 - 3 r^2, pairs (1,2), (2,3),
    (3,1): positive for every level platform."""
    b = balls_of_joints(l, th)
    dphi = np.sin(th)[:, None] * U + np.cos(th)[:, None] * np.array([0, 0, 1])
    J = np.zeros((3, 3))
    for k in range(3):
        i, j = k, (k + 1) % 3
        D = b[i] - b[j]
        J[k, i] = 2 * l[i] * D @ dphi[i]
        J[k, j] = -2 * l[j] * D @ dphi[j]
    return np.linalg.det(J)


def solve_theta(l, th0, iters=100):
    """Newton on (8)-(10) from th0 (finite-difference Jacobian)."""
    def f(th):
        b = balls_of_joints(l, th)
        return np.array([np.sum((b[k] - b[(k + 1) % 3]) ** 2) - 3 * r * r
                         for k in range(3)])
    th = np.array(th0, float)
    for _ in range(iters):
        fv = f(th)
        if np.max(np.abs(fv)) < 1e-14 * R * R:
            break
        h = 1e-7
        J = np.stack([(f(th + h * e) - fv) / h for e in np.eye(3)], axis=1)
        th = th - np.linalg.solve(J, fv)
    return th


def mode_map(alpha, betas, zcs):
    m = np.full((len(zcs), len(betas)), np.nan)
    for iz, zc in enumerate(zcs):
        for ib, beta in enumerate(betas):
            b = balls_of_pose(alpha, beta, zc)
            if np.min(b[:, 2]) <= 0:
                continue
            l, th = joints_of_balls(b)
            m[iz, ib] = np.sign(det_jt(l, th))
    return m


def draw(ax, b, l, th, style, label):
    """Side view (X-Z) of the links and the platform triangle."""
    for i in range(3):
        ax.plot([PINS[i, 0], b[i, 0]], [PINS[i, 2], b[i, 2]], style, lw=1.5)
    tri = np.vstack([b, b[:1]])
    ax.plot(tri[:, 0], tri[:, 2], style, lw=2.5, label=label)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("outdir")
    ap.add_argument("--alpha", type=float, default=0.5)
    plot.add_output_args(ap)
    a = ap.parse_args()
    betas = np.linspace(0, 1.4, 141)
    zcs = np.linspace(0.01, 0.5, 99)
    m = mode_map(a.alpha, betas, zcs)

    fig, ax = plot.subplots(1, 2, figsize=(11, 4.6))
    ax[0].pcolormesh(betas, zcs, m, cmap="coolwarm_r", vmin=-1.5, vmax=1.5,
                     shading="nearest")
    ax[0].contour(betas, zcs, np.nan_to_num(m), levels=[0], colors="k")
    ax[0].plot([0.9], [0.2], "k*", ms=12)
    ax[0].set_xlabel("beta [rad]")
    ax[0].set_ylabel("z_c [m]")
    ax[0].set_title(f"alpha = {a.alpha:g} rad: blue +1 (level side), red -1,"
                    "\nwhite unreachable; black line: det df/dtheta = 0",
                    fontsize=9)

    # a pose beyond the singular surface, and the root a level-platform
    # start reaches
    b = balls_of_pose(0.5, 0.9, 0.2)
    l, th = joints_of_balls(b)
    th_level = np.arccos(np.clip((R - r) / l, -0.999, 0.999))
    th2 = solve_theta(l, th_level)
    b2 = balls_of_joints(l, th2)
    draw(ax[1], b, l, th, "b-",
         f"pose (0.5, 0.9, 0.2 m), mode {int(np.sign(det_jt(l, th))):+d}")
    draw(ax[1], b2, l, th2, "r--",
         f"same lengths, mode {int(np.sign(det_jt(l, th2))):+d}")
    ax[1].plot(PINS[:, 0], PINS[:, 2], "ks")
    ax[1].set_aspect("equal")
    ax[1].set_xlabel("X [m]")
    ax[1].set_ylabel("Z [m]")
    ax[1].legend(fontsize=8, loc="lower left")
    ax[1].set_title("two assembly modes of one set of link lengths "
                    f"l = ({l[0]:.4f}, {l[1]:.4f}, {l[2]:.4f}) m", fontsize=9)
    fig.tight_layout()
    os.makedirs(a.outdir, exist_ok=True)
    path = plot.save(fig, plot.output_path(a.outdir, "assembly_modes", a), a.dpi)
    print(f"theta of the pose {np.round(th, 6)}, of the level-side root "
          f"{np.round(th2, 6)}; wrote {path}")


if __name__ == "__main__":
    main()
