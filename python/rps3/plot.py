"""Figures of rps3 results, fit for a paper: one style, vector output,
warned samples marked, legends that say what a curve is.

The analysis scripts (analysis/*.py) draw with these::

    from rps3 import plot
    fig, ax = plot.subplots()
    plot.links(ax, t, force, r"$F_i$")          # one style per link
    plot.mark_warned(ax, t, force, warn)       # samples past trans_warn
    plot.legend(ax)
    plot.save(fig, "out/fig3.pdf")             # the format from the suffix

``atlas``, ``mark`` and ``front`` draw the design study's performance
atlas and Pareto fronts (docs/design-optimisation.md).

``save`` writes PDF, SVG or PNG as the file's suffix says (``dpi`` is the
raster resolution: of a PNG, and of any image inside a PDF or SVG);
``add_output_args`` and ``output_path`` give every script the same
``--format`` and ``--dpi`` options.
"""

from __future__ import annotations

import argparse
import os
from collections.abc import Sequence
from typing import Any

# no backend is chosen here: importing rps3 leaves an interactive
# session's; without a display matplotlib falls back to Agg
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

#: the formats ``save`` writes, by file suffix
FORMATS = ("pdf", "svg", "png")
#: the default raster resolution [dots per inch]
DPI = 150
#: warn bit of a sample whose force transmission exceeds trans_warn
#: (RPS3_WARN_TRANS, include/rps3.h; the ``warn`` variable of a file)
WARN_TRANS = 8
#: legend text and artist id of the marked warned samples
WARNED_LABEL = "transmission warning"
WARNED_GID = "rps3-transmission-warning"
#: why a sample is marked, for a caption or a figure note
WARNED_NOTE = ("grey x: transmission warning, the force per unit platform "
               "load above trans_warn (100): near a singular pose, where the "
               "forces are large and sensitive")

#: distinguishable curves without colour: line styles and markers by index
LINE_STYLES = ("-", "--", ":", "-.")
MARKERS = ("o", "s", "^", "D", "v", "x")
#: the three links, in the paper's order
LINK_STYLES = LINE_STYLES[:3]

_RC: dict[str, Any] = {
    "figure.figsize": (6.4, 4.2),
    "font.size": 10,
    "axes.titlesize": 10,
    "axes.labelsize": 10,
    "legend.fontsize": 8,
    "legend.framealpha": 0.85,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "lines.linewidth": 1.2,
    # text stays text in vector output: searchable, editable
    "pdf.fonttype": 42,
    "svg.fonttype": "none",
}


def style() -> None:
    """The figures' matplotlib settings (sizes, grid, fonts kept as text
    in PDF and SVG)."""
    plt.style.use(_RC)


def subplots(*args: Any, **kwargs: Any) -> tuple[Figure, Any]:
    """``plt.subplots`` in the figures' style."""
    style()
    return plt.subplots(*args, **kwargs)


def figure(**kwargs: Any) -> Figure:
    """``plt.figure`` in the figures' style."""
    style()
    return plt.figure(**kwargs)


def fmt_of(path: str | os.PathLike[str]) -> str:
    """The format of an output file by its suffix (pdf, svg or png)."""
    ext = os.path.splitext(str(path))[1].lower().lstrip(".")
    if ext not in FORMATS:
        raise ValueError(f"{path}: the suffix must be one of "
                         f"{', '.join('.' + f for f in FORMATS)}")
    return ext


def save(fig: Figure, path: str | os.PathLike[str], dpi: float | None = None,
         close: bool = True) -> str:
    """Write fig to path, in the format of its suffix (.pdf, .svg, .png),
    at dpi dots per inch for raster output (default DPI); return the
    path."""
    fmt = fmt_of(path)
    d = DPI if dpi is None else float(dpi)
    if not d > 0:
        raise ValueError(f"dpi must be positive, not {dpi}")
    # tight here, not in the style: rcParams are the user's session's too
    fig.savefig(path, format=fmt, dpi=d, bbox_inches="tight",
                metadata={"Creator": "rps3"} if fmt != "png" else None)
    if close:
        plt.close(fig)
    return str(path)


def add_output_args(ap: argparse.ArgumentParser, default: str = "png") -> None:
    """--format FORMAT and --dpi DPI, the same in every script."""
    ap.add_argument("--format", choices=FORMATS, default=default,
                    help=f"figure format (default {default}; pdf and svg "
                         "are vector)")
    ap.add_argument("--dpi", type=float, default=DPI,
                    help=f"raster resolution of png output [dots per inch] "
                         f"(default {DPI})")


def output_path(outdir: str | os.PathLike[str], stem: str,
                args: argparse.Namespace) -> str:
    """OUTDIR/STEM.FORMAT for the --format of args."""
    return os.path.join(str(outdir), f"{stem}.{args.format}")


def links(ax: Axes, t: np.ndarray, y: np.ndarray, label: str,
          color: str = "k", **kwargs: Any) -> list:
    """Three curves, one per link (the last axis of y), told apart by
    their line styles; labels "LABEL, link i"."""
    out = []
    for i in range(y.shape[-1]):
        (line,) = ax.plot(t, y[:, i], LINK_STYLES[i % len(LINK_STYLES)],
                          color=color, label=f"{label}, link {i + 1}",
                          **kwargs)
        out.append(line)
    return out


def curve_style(i: int) -> dict[str, Any]:
    """Line style and marker of curve i, so that curves that overlap stay
    apart (markers a few per curve: markevery)."""
    return {"linestyle": LINE_STYLES[i % len(LINE_STYLES)],
            "marker": MARKERS[i % len(MARKERS)], "markevery": 0.1,
            "markersize": 4, "markerfacecolor": "none"}


def warned(warn: np.ndarray, bit: int = WARN_TRANS) -> np.ndarray:
    """Mask of the samples whose warn has bit set (-1: missing, not set)."""
    w = np.asarray(warn)
    return (w >= 0) & ((w & bit) != 0)


def mark_warned(ax: Axes, t: np.ndarray, y: np.ndarray, warn: np.ndarray,
                bit: int = WARN_TRANS, label: str = WARNED_LABEL):
    """Grey markers on the samples of y (1-D, or [time, link]) whose warn
    has bit set; one legend entry, label.  Returns the artist (gid
    WARNED_GID), or None when no sample is warned."""
    mask = warned(warn, bit)
    if not mask.any():
        return None
    yy = np.asarray(y)
    tt = np.asarray(t)
    if yy.ndim == 2:
        ts = np.repeat(tt[mask], yy.shape[1])
        ys = yy[mask].ravel()
    else:
        ts, ys = tt[mask], yy[mask]
    (art,) = ax.plot(ts, ys, linestyle="none", marker="x", color="0.55",
                     markersize=5, zorder=5, label=label)
    art.set_gid(WARNED_GID)
    return art


def legend(ax: Axes, handles: Sequence | None = None,
           labels: Sequence[str] | None = None, title: str | None = None,
           **kwargs: Any):
    """A legend in the figures' style (best place, a title when the
    entries need one)."""
    kwargs.setdefault("loc", "best")
    if handles is not None:
        return ax.legend(handles, list(labels or []), title=title, **kwargs)
    return ax.legend(title=title, **kwargs)


def note(fig: Figure, text: str) -> None:
    """A line of text under the axes: what the figure marks and why."""
    # below the figure: save's tight bounding box takes it in
    fig.text(0.01, -0.01, text, fontsize=7, color="0.3", ha="left",
             va="top", wrap=True)


def warned_samples(ax: Axes) -> list:
    """The warned-sample artists of ax (gid WARNED_GID): for tests."""
    return [a for a in ax.get_lines() if a.get_gid() == WARNED_GID]


# ------------------------------------------------------------------ design
# (docs/design-optimisation.md) an index over two design parameters, a
# Pareto front, designs marked on either

#: the good-transmission threshold Liu et al. use (LTI >= 0.7: the
#: pressure angle below about 45.6 degrees)
LTI_GOOD = 0.7


def atlas(ax: Axes, x: np.ndarray, y: np.ndarray, values: np.ndarray,
          label: str, *, levels: Sequence[float] | None = None,
          cmap: str = "viridis", colorbar: bool = True) -> Any:
    """A performance atlas: values[j, i] of the design at (x[i], y[j])
    as filled colours with labelled contour lines; NaN cells (no design,
    or an empty workspace) stay white.  label: what the colour is, with
    its unit.  Returns the filled-contour set (its colorbar beside)."""
    vals = np.ma.masked_invalid(np.asarray(values, float))
    filled = ax.contourf(x, y, vals, levels=12 if levels is None else levels,
                         cmap=cmap)
    lines = ax.contour(x, y, vals, levels=np.asarray(filled.levels)[::2], colors="k",
                       linewidths=0.6)
    ax.clabel(lines, fontsize=7, fmt="%.3g")
    if colorbar:
        ax.figure.colorbar(filled, ax=ax, label=label)
    filled.set_gid("rps3-atlas")
    return filled


def mark(ax: Axes, x: float, y: float, label: str, i: int = 0) -> Any:
    """One design on an atlas or a front: a marker of style i, in the
    legend as label."""
    (art,) = ax.plot([x], [y], linestyle="none", marker=MARKERS[i % len(MARKERS)],
                     markersize=8, markerfacecolor="white", markeredgecolor="k",
                     markeredgewidth=1.5, label=label, zorder=6)
    return art


def front(ax: Axes, x: np.ndarray, y: np.ndarray, label: str, i: int = 0) -> Any:
    """A Pareto front (points sorted along x, joined as a staircase of the
    non-dominated set), in curve style i."""
    order = np.argsort(np.asarray(x))
    st = curve_style(i)
    st["markevery"] = 1
    (art,) = ax.plot(np.asarray(x)[order], np.asarray(y)[order], color="k",
                     label=label, drawstyle="steps-post", **st)
    return art
