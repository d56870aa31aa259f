#!/usr/bin/env python3
"""The design study of docs/design-optimisation.md (`make design`).

usage: design.py -o OUTDIR [--docs IMGDIR] [--quick] [--format png] [--dpi DPI]

For the paper's helix carrying a 0.5 kg payload:

- the performance atlas: over the platform ratio rho and the stroke ratio
  l_max / l_min (R and l_min of Table II), the workspace volume, the
  global transmission index GTI, the good-transmission volume (LTI >= 0.7)
  and the helix's peak actuator force: OUTDIR/design_atlas.png;
- the worked answer: the geometry (rho, l_min, l_max) of smallest peak
  actuator force that reaches every pose Table II's design reaches (and at
  least its volume), by NLopt's COBYLA, checked against a dense grid
  around it, with the platform's mass fixed and growing as r^2;
- the Pareto front of peak force against workspace volume by NSGA-II,
  five seeds, and the spread of their hypervolumes:
  OUTDIR/design_pareto.png;
- the chosen design drawn beside Table II's: OUTDIR/design_robots.png.

Writes OUTDIR/design.md (the numbers of the page) and prints it.  With
--docs, small PNG copies of the figures go to IMGDIR (docs/img).
--quick: coarse grids and short runs, for a check that it runs.
"""

import argparse
import os
import sys
import time
import warnings

import numpy as np
import rps3
from rps3 import design, plot

PAYLOAD = 0.5          # kg, the question's
SEEDS = (1, 2, 3, 4, 5)
LTI_GOOD = plot.LTI_GOOD


def setup(quick):
    """The paper's design with the payload, the grid of poses, its
    reachable poses (the workspace every candidate must cover), the helix."""
    paper = design.Design(payload=PAYLOAD)
    grid = design.grid(paper, n=(8, 6, 8) if quick else (12, 8, 12))
    ev = design.evaluate(paper, grid)
    covers = grid.poses[ev["reachable"].values.ravel()]
    helix = rps3.trajectory.helix(samples=51 if quick else 201)
    return paper, grid, ev, covers, helix


def atlas(paper, grid, helix, quick):
    """Indices over (rho, stroke ratio), l_min = R fixed, Table II's M:
    with the stroke as the only limit (ball joints free: the workspace of
    a transmission atlas), and with Table II's ball joints (pi/4)."""
    rhos = np.linspace(0.2, 1.5, 8 if quick else 27)
    ratios = np.linspace(1.2, 3.0, 6 if quick else 19)
    keys = ("volume", "gti", "good_volume", "gti_ball", "volume_ball", "peak_force")
    out = {k: np.full((len(ratios), len(rhos)), np.nan) for k in keys}
    for j, k in np.ndindex(len(ratios), len(rhos)):
        ds = paper.replace(rho=rhos[k], l_max=ratios[j] * paper.l_min)
        free = design.summarise(ds.replace(ball_max=np.pi), grid)
        ball = design.summarise(ds, grid)
        out["volume"][j, k] = free.volume
        out["volume_ball"][j, k] = ball.volume
        if not free.empty:
            out["gti"][j, k] = free.gti
            out["good_volume"][j, k] = free.volume * free.good_fraction
        if not ball.empty:
            out["gti_ball"][j, k] = ball.gti
        try:
            out["peak_force"][j, k] = design.task(ds, helix).peak_force
        except rps3.errors.ReachError:
            pass
    return rhos, ratios, out


ATLAS_PANELS = (
    ("gti", "GTI, mean LTI [-]: stroke the only limit"),
    ("good_volume", "good-transmission volume (LTI >= 0.7) [m rad^2]: stroke only"),
    ("gti_ball", "GTI [-]: stroke and ball joints (pi/4)"),
    ("peak_force", "helix, 0.5 kg payload: peak force [N]"))


def draw_atlas(rhos, ratios, a, path, dpi):
    fig, axes = plot.subplots(2, 2, figsize=(10, 7.5), sharex=True, sharey=True)
    for ax, (key, label) in zip(axes.ravel(), ATLAS_PANELS):
        plot.atlas(ax, rhos, ratios, a[key], "[" + label.split("[")[1].split("]")[0] + "]")
        plot.mark(ax, 0.5, 2.0, "Table II")
        ax.set_title(label, fontsize=8)
    for ax in axes[1]:
        ax.set_xlabel(r"platform ratio $\rho = r/R$ [-]")
    for ax in axes[:, 0]:
        ax.set_ylabel(r"stroke ratio $l_{max}/l_{min}$ [-]")
    plot.legend(axes[0, 0], loc="upper right")
    plot.note(fig, "R = 0.2286 m and l_min = R (Table II's design); poses "
              "alpha in [-pi, pi], beta in [0, pi/3], z_c in [0, 2R]; blank: no "
              "reachable pose, or the helix leaves the workspace")
    return plot.save(fig, path, dpi)


VARIABLES = {"rho": (0.2, 1.5), "l_min": (0.1, 0.4), "l_max": (0.3, 0.8)}


def worked(paper, grid, ev, covers, helix, quick):
    """Smallest peak force covering Table II's workspace, two mass models."""
    rows = {}
    for pm in ("fixed", "area"):
        t0 = time.time()
        with warnings.catch_warnings():
            warnings.simplefilter("error", design.ConvergenceWarning)
            opt = design.optimise(
                VARIABLES, "peak_force", base=paper, trajectory=helix, grid=grid,
                covers=covers, volume_min=float(ev["volume"]), platform_mass=pm,
                maxeval=200 if quick else 600, seed=1)
        best, _, count = design.neighbourhood(opt, half_width=0.02,
                                              n=3 if quick else 7)
        rows[pm] = dict(opt=opt, grid_best=best, grid_count=count,
                        seconds=time.time() - t0)
    return rows


def describe(ds, grid, helix):
    s = design.summarise(ds, grid)
    t = design.task(ds, helix)
    return dict(rho=ds.rho, l_min=ds.l_min, l_max=ds.l_max, M=ds.M,
                F=t.peak_force, F_rms=t.rms_force, P=t.peak_power,
                volume=s.volume, gti=s.gti, good=s.good_fraction,
                lti_task=t.lti_min, xc=s.xc_max, spin=s.spin_max,
                cond=s.cond_h_max)


def fronts(paper, grid, covers, helix, quick):
    out = []
    for seed in SEEDS[:2] if quick else SEEDS:
        t0 = time.time()
        f = design.pareto(VARIABLES, ("peak_force", "volume"), base=paper,
                          trajectory=helix, grid=grid, lti_min=LTI_GOOD,
                          platform_mass="area", pop_size=16 if quick else 40,
                          n_gen=8 if quick else 60, seed=seed)
        out.append((f, time.time() - t0))
    return out


def draw_fronts(fr, ref, paper_pt, path, dpi):
    fig, ax = plot.subplots()
    for i, (f, _) in enumerate(fr):
        plot.front(ax, f.objectives[:, 0], f.objectives[:, 1],
                   f"NSGA-II, seed {f.seed}", i)
    plot.mark(ax, paper_pt[0], paper_pt[1], "Table II's design", 0)
    ax.axvline(ref["peak_force"], color="0.5", lw=0.8, ls=":")
    ax.set_xlabel("helix with a 0.5 kg payload: peak actuator force [N]")
    ax.set_ylabel("workspace volume [m rad^2]")
    plot.legend(ax)
    plot.note(fig, "variables rho, l_min, l_max (R = 0.2286 m); platform mass "
              "as r^2; constraints: the helix reachable with LTI >= 0.7; "
              "dotted: the hypervolume's reference force")
    return plot.save(fig, path, dpi)


def draw_robots(paper, chosen, helix, path, dpi):
    from rps3 import view
    fig = plot.figure(figsize=(11, 4.6))
    for k, (ds, title) in enumerate(((paper, "Table II"), (chosen, "chosen"))):
        ax = fig.add_subplot(1, 2, k + 1, projection="3d")
        ax.view_init(elev=18, azim=-60)
        view.draw(ds.model(), helix.pose[0], ax=ax)
        ax.set_title(f"{title}: rho = {ds.rho:.3g}, stroke [{ds.l_min:.3g}, "
                     f"{ds.l_max:.3g}] m", fontsize=9)
        if k == 0:
            ax.get_legend().remove()
    return plot.save(fig, path, dpi)


def table(rows, header):
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(out)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("-o", "--outdir", required=True)
    p.add_argument("--docs", help="also write small PNGs into this directory")
    p.add_argument("--quick", action="store_true")
    plot.add_output_args(p)
    args = p.parse_args(argv)
    os.makedirs(args.outdir, exist_ok=True)
    t0 = time.time()
    paper, grid, ev, covers, helix = setup(args.quick)
    rhos, ratios, a = atlas(paper, grid, helix, args.quick)
    figs = {"design_atlas": lambda path, dpi: draw_atlas(rhos, ratios, a, path, dpi)}
    opt = worked(paper, grid, ev, covers, helix, args.quick)
    base = describe(paper, grid, helix)
    fr = fronts(paper, grid, covers, helix, args.quick)
    ref = {"peak_force": round(1.05 * base["F"], 2), "volume": 0.0}
    hv = np.array([f.hypervolume(ref) for f, _ in fr])
    figs["design_pareto"] = lambda path, dpi: draw_fronts(
        fr, ref, (base["F"], base["volume"]), path, dpi)
    chosen = opt["fixed"]["opt"].design
    figs["design_robots"] = lambda path, dpi: draw_robots(paper, chosen, helix, path, dpi)
    for stem, draw in figs.items():
        draw(plot.output_path(args.outdir, stem, args), args.dpi)
        if args.docs:
            draw(os.path.join(args.docs, f"{stem}.png"), 80)

    # ---------------------------------------------------------- the numbers
    lines = [f"# Design study ({'quick' if args.quick else 'full'}), "
             f"{time.time() - t0:.0f} s", ""]
    lines += [f"grid {grid.n} poses, cell {grid.cell_volume:.4g} m rad^2; helix "
              f"{len(helix.t)} samples; payload {PAYLOAD} kg; Table II reaches "
              f"{len(covers)} poses", ""]
    cols = ["design", "M [kg]", "rho", "l_min [m]", "l_max [m]", "peak F [N]",
            "RMS F [N]", "peak P [W]", "volume [m rad^2]", "GTI", "LTI >= 0.7",
            "least LTI, helix", "max x_c [mm]", "max spin [deg]"]

    def design_row(name, d):
        return [name, f"{d['M']:.3f}", f"{d['rho']:.4f}", f"{d['l_min']:.4f}",
                f"{d['l_max']:.4f}", f"{d['F']:.4f}", f"{d['F_rms']:.4f}",
                f"{d['P']:.3g}", f"{d['volume']:.4f}", f"{d['gti']:.3f}",
                f"{d['good']:.3f}", f"{d['lti_task']:.3f}", f"{1e3 * d['xc']:.1f}",
                f"{np.degrees(d['spin']):.1f}"]

    rows = [design_row("Table II", base)]
    for pm, r in opt.items():
        rows.append(design_row(f"optimum, platform mass {pm}",
                               describe(r["opt"].design, grid, helix)))
    lines += ["## Worked answer", "", table(rows, cols), ""]
    for pm, r in opt.items():
        o = r["opt"]
        lines.append(
            f"- platform mass {pm}: NLopt {o.algorithm} {o.status} after "
            f"{o.nevals} designs ({r['seconds']:.0f} s), converged {o.converged}, "
            f"feasible {o.feasible}; constraints "
            + ", ".join(f"{k} {v:.3g}" for k, v in o.constraints.items())
            + f"; best of {r['grid_count']} feasible designs of a grid of +-2 % "
            f"around it: {r['grid_best']:.6f} N (optimum {o.value:.6f} N)")
    w = (PAYLOAD + paper.M) * paper.g / 3
    lines += ["", f"static floor (M + payload) g / 3 = {w:.4f} N", ""]
    lines += ["## Pareto fronts (NSGA-II)", "",
              f"reference point {ref}; hypervolume per seed:", ""]
    lines += [table([[str(f.seed), str(len(f.designs)), str(f.nevals),
                      f"{h:.5f}", f"{s:.0f}"] for (f, s), h in zip(fr, hv)],
                    ["seed", "designs on the front", "evaluations",
                     "hypervolume [N m rad^2]", "time [s]"]), ""]
    lines.append(f"spread (max - min) / mean = {(hv.max() - hv.min()) / hv.mean():.2e}")
    f0 = fr[0][0]
    lines += ["", "front of the first seed (every 4th design):", "",
              table([[f"{x[0]:.4f}", f"{x[1]:.4f}", f"{x[2]:.4f}", f"{o[0]:.4f}",
                      f"{o[1]:.4f}"] for x, o in zip(f0.variables[::4],
                                                     f0.objectives[::4])],
                    ["rho", "l_min [m]", "l_max [m]", "peak F [N]",
                     "volume [m rad^2]"]), ""]
    # the atlas's ridge: the rho of the best GTI for each stroke ratio
    lines += ["## Atlas", "", "per stroke ratio, the rho of the best of each "
              "index (stroke the only limit, and with the ball joints):", ""]
    arows = []
    for j, q in enumerate(ratios):
        row = [f"{q:.2f}"]
        for key in ("gti", "volume", "good_volume", "gti_ball", "volume_ball"):
            v = a[key][j]
            if np.all(np.isnan(v)):
                row += ["-", "-"]
                continue
            k = int(np.nanargmax(v))
            row += [f"{rhos[k]:.2f}", f"{v[k]:.3f}"]
        arows.append(row)
    lines += [table(arows, ["l_max/l_min", "rho", "GTI", "rho", "volume", "rho",
                            "good volume", "rho", "GTI, ball", "rho",
                            "volume, ball"]), ""]
    text = "\n".join(lines)
    with open(os.path.join(args.outdir, "design.md"), "w") as fh:
        fh.write(text + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
