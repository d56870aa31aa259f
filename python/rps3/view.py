"""Pictures of the manipulator: a 3-D drawing of one pose, an animation along
a trajectory (GIF, MP4) and a self-contained interactive HTML page.

    import rps3
    from rps3 import view
    model = rps3.Model()
    fig = view.draw(model, [0.3, 0.1, 0.3], path="pose.pdf")   # or .svg, .png
    traj = rps3.trajectory.helix()
    view.animate(model, traj.pose[::20], "helix.gif", times=traj.time[::20])
    view.html(model, traj.pose[::10], "helix.html", times=traj.time[::10])

    python -m rps3.view out/paper.h5 --case 1 -o paper.gif

What is drawn (docs/visualisation.md): the base triangle through the pin
joints P_i, each pin's revolute axis, each link as a barrel (cylinder) from
its pin and a piston from the barrel to its ball joint b_i, the ball joints,
and the platform triangle through them.  Every position is the library's:
rps3_ik from the pose (c, rot, b_i, l_i, theta_i, the link directions
phi_i), the pins and axes from the validated model.  The barrel's length is
a drawing choice (the library's links are a mass at d, not a shape): R by
default, never longer than the link.

matplotlib (mplot3d) draws the figures and the GIF/MP4 frames, imported
only when one of these functions is called; MP4 needs an ``ffmpeg``
program on the PATH.  The HTML page needs nothing: its script and data are
written into the page.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import sys
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from rps3._core import FloatArray, IntArray, strerror
from rps3._rps3 import lib
from rps3._view_page import _PAGE
from rps3.model import Model
from rps3.view_run import model_from_scene, read_run  # noqa: F401 (rps3.view.model_from_scene)

# colours of the parts, shared by the figures and the HTML page
COLOURS = {"base": "#4d4d4d", "pin": "#111111", "barrel": "#1f5fa8",
           "piston": "#8fb8e8", "ball": "#c0392b", "platform": "#e6a23c",
           "reference": "#2e8b57"}


@dataclass(frozen=True)
class Geometry:
    """Positions of every part, per frame (leading axis n), base frame [m].

    A frame whose pose the library refuses (status != 0) holds NaN.
    """

    pin: FloatArray        #: pin joints P_i, (3, 3): row i is P_i [m]
    axis: FloatArray       #: pin axes, (3, 3), unit
    ball: FloatArray       #: ball joints b_i, (n, 3, 3) [m]
    centre: FloatArray     #: platform centre c, (n, 3) [m]
    rot: FloatArray        #: platform orientation, (n, 3, 3), axes as columns
    l: FloatArray          #: link lengths, (n, 3) [m]
    theta: FloatArray      #: link angles, (n, 3) [rad]
    phi: FloatArray        #: unit vector along each link, pin to ball, (n, 3, 3)
    pose: FloatArray       #: (alpha, beta, z_c) per frame, (n, 3)
    status: IntArray       #: rps3 status per frame, 0 = ok (rps3.strerror)

    @property
    def ok(self) -> np.ndarray:
        """Boolean mask of the frames the library computed."""
        return np.asarray(self.status) == 0

    def barrel_end(self, barrel: float) -> FloatArray:
        """End of each link's barrel, (n, 3, 3): barrel [m] along the link
        from its pin, at most the link's length."""
        s = np.minimum(barrel, self.l)[..., None]
        return self.pin[None] + s * self.phi


def geometry(model: Model, pose: ArrayLike | None = None, *,
             lengths: ArrayLike | None = None) -> Geometry:
    """Every part's position at the poses (or link lengths) given.

    Args:
        model: the manipulator.
        pose: (n, 3) or (3,) array of (alpha, beta, z_c) [rad, rad, m].
        lengths: instead of pose, (n, 3) or (3,) link lengths [m] (e.g. a
            simulation's output): the pose is the library's forward
            kinematics (Model.fk), warm-started along the frames.

    Returns:
        Geometry with a leading axis n (1 for one point).

    Raises:
        ValueError: neither or both of pose and lengths, or a bad shape.
    """
    if (pose is None) == (lengths is None):
        raise ValueError("pose: give pose or lengths, not both or neither")
    if lengths is not None:
        fk = model.fk(np.atleast_2d(np.asarray(lengths, float)))
        poses = np.where(fk.ok[:, None], fk.pose, np.nan)
    else:
        poses = np.asarray(pose, float)
        if poses.ndim == 1:
            poses = poses[None, :]
        if poses.ndim != 2 or poses.shape[1] != 3:
            raise ValueError(f"pose: expected shape (n, 3) or (3,), got {poses.shape}")
    n = len(poses)
    c = model._c
    d = model._workspace()
    out = {k: np.full((n, 3, 3), np.nan) for k in ("ball", "rot", "phi")}
    out.update({k: np.full((n, 3), np.nan) for k in ("centre", "l", "theta")})
    status = np.zeros(n, np.int32)
    for k, p in enumerate(poses):
        d.pose[0:3] = [float(x) for x in p]
        s = lib.rps3_ik(c, d)
        status[k] = s
        if s != lib.RPS3_OK:
            continue
        out["ball"][k] = [list(d.b[i]) for i in range(3)]
        out["rot"][k] = [list(d.rot[i]) for i in range(3)]
        out["phi"][k] = [list(d.phi[i]) for i in range(3)]
        out["centre"][k] = list(d.c)
        out["l"][k] = list(d.l)
        out["theta"][k] = list(d.theta)
    pin = np.array([list(c.pin[i]) for i in range(3)])
    axis = np.array([list(c.axis[i]) for i in range(3)])
    return Geometry(pin=pin, axis=axis, pose=poses, status=status, **out)


def _sizes(model: Model, barrel: float | None) -> dict[str, float]:
    """Drawing sizes [m], in proportion to the base radius."""
    R = model.R
    b = R if barrel is None else float(barrel)
    if not (math.isfinite(b) and b > 0):
        raise ValueError(f"barrel: expected a length > 0 m, got {barrel!r}")
    return {"barrel": b, "pin": 0.12 * R}


def _lines(g: Geometry, k: int, sizes: dict[str, float],
           ref: Geometry | None = None) -> dict[str, FloatArray]:
    """Polylines (m x 3 points) of frame k, by artist name."""
    pin, ax = g.pin, g.axis
    end = g.barrel_end(sizes["barrel"])[k]
    out = {"base": np.vstack([pin, pin[:1]])}
    for i in range(3):
        out[f"pin_{i}"] = np.array([pin[i] - sizes["pin"] * ax[i],
                                    pin[i] + sizes["pin"] * ax[i]])
        out[f"barrel_{i}"] = np.array([pin[i], end[i]])
        out[f"piston_{i}"] = np.array([end[i], g.ball[k, i]])
    out["balls"] = g.ball[k]
    out["platform_edge"] = np.vstack([g.ball[k], g.ball[k, :1]])
    if ref is not None:
        out["reference"] = np.vstack([ref.ball[k], ref.ball[k, :1]])
    return out


def _limits(g: Geometry, ref: Geometry | None = None) -> tuple[FloatArray, float]:
    """Centre and half-width of a cube holding every frame."""
    more = [] if ref is None else [ref.ball[ref.ok].reshape(-1, 3)]
    pts = np.vstack([g.pin, g.ball[g.ok].reshape(-1, 3), *more, np.zeros((1, 3))])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    return (lo + hi) / 2, max(float(np.max(hi - lo)) / 2, 1e-9) * 1.05


def _title(g: Geometry, k: int, t: float | None) -> str:
    a, b, z = g.pose[k]
    head = "" if t is None else f"t = {t:.3f} s   "
    if not g.ok[k]:
        return f"{head}NOT COMPUTED: {strerror(int(g.status[k]))}"
    return (f"{head}alpha = {math.degrees(a):.1f} deg, beta = "
            f"{math.degrees(b):.1f} deg, z_c = {z * 1e3:.1f} mm")


class _Scene:
    """The artists of one axes, updated frame by frame."""

    def __init__(self, ax: Any, g: Geometry, sizes: dict[str, float],
                 ref: Geometry | None = None) -> None:
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection
        self.ax, self.g, self.sizes, self.ref = ax, g, sizes, ref
        lines = _lines(g, 0, sizes, ref)
        style = {"base": dict(color=COLOURS["base"], lw=2.0, label="base (pins P_i)"),
                 "balls": dict(color=COLOURS["ball"], ls="none", marker="o", ms=7,
                               label="ball joints b_i"),
                 "platform_edge": dict(color=COLOURS["platform"], lw=2.0,
                                       label="platform"),
                 "reference": dict(color=COLOURS["reference"], lw=1.5, ls="--",
                                   label="reference platform")}
        for i in range(3):
            style[f"pin_{i}"] = dict(color=COLOURS["pin"], lw=4.0, solid_capstyle="butt",
                                     label="pin axes" if i == 0 else None)
            style[f"barrel_{i}"] = dict(color=COLOURS["barrel"], lw=7.0,
                                        solid_capstyle="butt",
                                        label="links: cylinder" if i == 0 else None)
            style[f"piston_{i}"] = dict(color=COLOURS["piston"], lw=3.0,
                                        label="links: piston" if i == 0 else None)
        self.artists: dict[str, Any] = {}
        for name, pts in lines.items():
            (art,) = ax.plot(pts[:, 0], pts[:, 1], pts[:, 2], **style[name])
            art.set_gid(name)
            self.artists[name] = art
        base = Poly3DCollection([g.pin], facecolor=COLOURS["base"], alpha=0.15)
        base.set_gid("base_plate")
        ax.add_collection3d(base)
        self.plate = Poly3DCollection([g.ball[0]], facecolor=COLOURS["platform"],
                                      alpha=0.45)
        self.plate.set_gid("platform")
        ax.add_collection3d(self.plate)
        mid, half = _limits(g, ref)
        ax.set_xlim(mid[0] - half, mid[0] + half)
        ax.set_ylim(mid[1] - half, mid[1] + half)
        ax.set_zlim(max(mid[2] - half, -0.05 * half), mid[2] + half)
        ax.set_box_aspect((1, 1, (ax.get_zlim()[1] - ax.get_zlim()[0]) / (2 * half)))
        from matplotlib.ticker import MaxNLocator
        for axis, name in ((ax.xaxis, "X"), (ax.yaxis, "Y"), (ax.zaxis, "Z")):
            axis.set_major_locator(MaxNLocator(4))
            axis.set_label_text(f"{name} [m]")
        # beside the drawing, never over it
        ax.legend(loc="center left", bbox_to_anchor=(1.08, 0.5), fontsize="small",
                  frameon=False)

    def update(self, k: int, t: float | None) -> list[Any]:
        for name, pts in _lines(self.g, k, self.sizes, self.ref).items():
            self.artists[name].set_data_3d(pts[:, 0], pts[:, 1], pts[:, 2])
        self.plate.set_verts([self.g.ball[k]] if self.g.ok[k] else [])
        title = self.ax.set_title(_title(self.g, k, t), fontsize="medium",
                                  color="black" if self.g.ok[k] else "red")
        return [*self.artists.values(), self.plate, title]


def _figure(figsize: tuple[float, float], dpi: float) -> tuple[Any, Any]:
    from matplotlib.figure import Figure
    _positive(dpi, "dpi")
    if len(figsize) != 2:
        raise ValueError(f"figsize: expected (width, height) in inches, got {figsize!r}")
    for x in figsize:
        _positive(x, "figsize")
    fig = Figure(figsize=figsize, dpi=dpi, layout="tight")
    ax = fig.add_subplot(projection="3d")
    ax.view_init(elev=22, azim=-60)
    return fig, ax


def draw(model: Model, pose: ArrayLike | None = None, *,
         lengths: ArrayLike | None = None, ax: Any = None,
         path: str | os.PathLike[str] | None = None, dpi: float = 150,
         figsize: tuple[float, float] = (7.0, 4.5),
         barrel: float | None = None, reference: ArrayLike | None = None) -> Any:
    """Draw the manipulator at one pose in 3-D.

    Args:
        model: the manipulator.
        pose: (alpha, beta, z_c) [rad, rad, m].
        lengths: instead of pose, the three link lengths [m] (forward
            kinematics).
        ax: a matplotlib 3-D axes to draw into; None: a new figure.
        path: write the figure there; the format is the suffix's (.pdf and
            .svg are vector, .png raster at dpi).
        dpi: resolution of raster output [dots per inch].
        figsize: size of a new figure [inch].
        barrel: length of each link's cylinder [m]; None: R.
        reference: a second pose whose platform is drawn dashed (e.g. a
            simulation's reference beside the plant's pose).

    Returns:
        The matplotlib Figure.  Its artists carry gids: ``base`` (closed
        triangle P_0 P_1 P_2 P_0), ``pin_i``, ``barrel_i``, ``piston_i``,
        ``balls`` (b_0, b_1, b_2), ``platform_edge``, ``platform``,
        ``reference`` (its closed triangle).

    Raises:
        ValueError: the pose is not one point, or the library refuses it
            (unreachable: the message says why).
    """
    _positive(dpi, "dpi")
    g = geometry(model, pose, lengths=lengths)
    if len(g.status) != 1:
        raise ValueError(f"pose: draw takes one pose, got {len(g.status)}; "
                         f"animate takes many")
    if not g.ok[0]:
        what = "lengths" if lengths is not None else "pose"
        value = lengths if lengths is not None else pose
        raise ValueError(f"{what}: {np.asarray(value).tolist()}: "
                         f"{strerror(int(g.status[0]))}")
    if ax is None:
        fig, ax = _figure(figsize, dpi)
    else:
        fig = ax.figure
    ref = _reference(model, reference, 1)
    _Scene(ax, g, _sizes(model, barrel), ref).update(0, None)
    if path is not None:
        with _atomic(path) as tmp:
            fig.savefig(tmp, dpi=dpi)
    return fig


def animate(model: Model, poses: ArrayLike | None = None,
            path: str | os.PathLike[str] | None = None, *,
            lengths: ArrayLike | None = None, times: ArrayLike | None = None,
            fps: float = 20, dpi: float = 80, figsize: tuple[float, float] = (7.0, 4.5),
            barrel: float | None = None, reference: ArrayLike | None = None) -> int:
    """Write an animation of the manipulator along a trajectory.

    Args:
        model: the manipulator.
        poses: (n, 3) poses (alpha, beta, z_c), one per frame.
        path: the file; ``.gif`` (Pillow), ``.mp4`` (ffmpeg) or ``.html``
            (the page of ``html``).
        lengths: instead of poses, (n, 3) link lengths [m], e.g. a
            simulation's, through the forward kinematics.
        times: (n,) time of each frame [s], shown in the title.
        fps: frames per second of the file.
        dpi, figsize: size of each frame (dpi x figsize pixels).
        barrel: length of each link's cylinder [m]; None: R.
        reference: (n, 3) poses whose platform is drawn dashed in each
            frame, e.g. a simulation's reference (``read_run``).

    Returns:
        The number of frames written.  Frames the library refuses are
        written with the base alone and the reason in red.

    Raises:
        ValueError: a bad argument, an unknown suffix, or no frame at all.
        RuntimeError: MP4 asked for and no ffmpeg program found.
    """
    if path is None:
        raise ValueError("path: the file to write (.gif, .mp4 or .html)")
    path = os.fspath(path)
    suffix = os.path.splitext(path)[1].lower()
    if suffix == ".html":
        return html(model, poses, path, lengths=lengths, times=times, fps=fps,
                    barrel=barrel, reference=reference)
    if suffix not in (".gif", ".mp4"):
        raise ValueError(f"path: {path}: unknown suffix {suffix!r}; "
                         f"expected .gif, .mp4 or .html")
    _positive(fps, "fps")
    g = geometry(model, poses, lengths=lengths)
    t = _times(times, len(g.status))
    if not g.ok.any():
        raise ValueError(f"poses: no frame could be computed "
                         f"({strerror(int(g.status[0]))} at frame 0)")
    ref = _reference(model, reference, len(g.status))
    from matplotlib import animation
    if suffix == ".mp4":
        if not animation.writers.is_available("ffmpeg"):
            raise RuntimeError(f"{path}: MP4 needs the ffmpeg program, not found "
                               f"on the PATH (Debian: apt-get install ffmpeg); "
                               f"write a .gif or .html instead")
        writer: Any = animation.FFMpegWriter(fps=fps)  # type: ignore[arg-type]
    else:
        writer = animation.PillowWriter(fps=fps)  # type: ignore[arg-type]
    fig, ax = _figure(figsize, dpi)
    scene = _Scene(ax, g, _sizes(model, barrel), ref)
    n = len(g.status)
    with _atomic(path) as tmp:
        with writer.saving(fig, tmp, dpi):
            for k in range(n):
                scene.update(k, None if t is None else float(t[k]))
                writer.grab_frame()
    return n


@contextlib.contextmanager
def _atomic(path: str | os.PathLike[str]) -> Iterator[str]:
    """A temporary name beside path (same suffix: writers go by it), renamed
    to path when the block succeeds, removed when it fails: no partial
    file looks complete."""
    path = os.fspath(path)
    root, suffix = os.path.splitext(path)
    tmp = f"{root}.part{suffix}"
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.remove(tmp)
        raise


def _reference(model: Model, reference: ArrayLike | None, n: int) -> Geometry | None:
    """The reference poses' geometry, one per frame (refused ones NaN)."""
    if reference is None:
        return None
    ref = geometry(model, reference)
    if len(ref.status) != n:
        raise ValueError(f"reference: {len(ref.status)} poses for {n} frames")
    return ref


def _positive(x: Any, name: str) -> None:
    try:
        ok = math.isfinite(float(x)) and float(x) > 0
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ValueError(f"{name}: expected a number > 0, got {x!r}")


def _times(times: ArrayLike | None, n: int) -> FloatArray | None:
    if times is None:
        return None
    t = np.asarray(times, float).reshape(-1)
    if t.size != n:
        raise ValueError(f"times: {t.size} values for {n} frames")
    return t


def _r(a: np.ndarray) -> Any:
    """Numbers for the page: 9 significant digits (0.1 um at 1 m)."""
    return json.loads(json.dumps(np.asarray(a).tolist(),
                                 default=float), parse_float=lambda s: float(f"{float(s):.9g}"))


def html(model: Model, poses: ArrayLike | None = None,
         path: str | os.PathLike[str] | None = None, *,
         lengths: ArrayLike | None = None, times: ArrayLike | None = None,
         fps: float = 20, barrel: float | None = None,
         reference: ArrayLike | None = None,
         title: str = "rps3: 3-RPS manipulator") -> int:
    """Write a self-contained interactive HTML page: the manipulator along
    the frames, drawn on a canvas by a script in the page (no library, no
    network), with play/pause, a frame slider and a view turned by dragging.

    Arguments as ``animate``.  Returns the number of frames.  The page's
    data (``<script id="rps3-data">``, JSON) holds the positions drawn
    [m]: ``pin``, ``axis``, and per frame ``ball``, ``end`` (barrel ends),
    ``ok`` and ``text``, and ``ref`` (the reference platform's corners)
    when a reference is given.
    """
    if path is None:
        raise ValueError("path: the .html file to write")
    _positive(fps, "fps")
    g = geometry(model, poses, lengths=lengths)
    t = _times(times, len(g.status))
    if not g.ok.any():
        raise ValueError(f"poses: no frame could be computed "
                         f"({strerror(int(g.status[0]))} at frame 0)")
    ref = _reference(model, reference, len(g.status))
    sizes = _sizes(model, barrel)
    ends = g.barrel_end(sizes["barrel"])
    mid, half = _limits(g, ref)
    frames = []
    for k in range(len(g.status)):
        ok = bool(g.ok[k])
        frames.append({"ok": ok, "text": _title(g, k, None),
                       "ball": _r(g.ball[k]) if ok else None,
                       "end": _r(ends[k]) if ok else None})
        if ref is not None:
            frames[-1]["ref"] = _r(ref.ball[k]) if ref.ok[k] else None
    data = {"pin": _r(g.pin), "axis": _r(g.axis), "pinlen": sizes["pin"],
            "centre": _r(mid), "half": half, "fps": fps, "colours": COLOURS,
            "times": None if t is None else _r(t), "frames": frames}
    legend = "".join(f'<span style="color:{COLOURS[k]}">&#9632; {v}</span>'
                     for k, v in (("base", "base"), ("pin", "pin axes"),
                                  ("barrel", "link cylinders"),
                                  ("piston", "pistons"), ("ball", "ball joints"),
                                  ("platform", "platform"))
                     + ((("reference", "reference platform (dashed)"),)
                        if ref is not None else ()))
    text = (_PAGE.replace("__TITLE__", _escape(title))
            .replace("__LEGEND__", legend)
            # "</" cannot end the data's script element early
            .replace("__DATA__", json.dumps(data).replace("</", "<\\/")))
    with _atomic(path) as tmp, open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    return len(frames)


def _escape(s: str) -> str:
    return s.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m rps3.view FILE.h5 -o OUT``: a picture or an animation of
    one case of an rps3-run file."""
    ap = argparse.ArgumentParser(
        prog="python -m rps3.view",
        description="Draw or animate one case of an rps3-run HDF5 file.")
    ap.add_argument("file", help="rps3-run output (.h5)")
    ap.add_argument("-o", "--output", required=True,
                    help="OUT.gif, OUT.mp4 or OUT.html (animation); OUT.png, "
                         "OUT.pdf or OUT.svg (one frame, see --at)")
    ap.add_argument("-c", "--case", type=int, default=0, help="case index (default 0)")
    ap.add_argument("--stride", type=int, default=1, help="every STRIDE-th sample (default 1)")
    ap.add_argument("--fps", type=float, default=20, help="frames per second (default 20)")
    ap.add_argument("--dpi", type=float, default=80, help="dots per inch (default 80)")
    ap.add_argument("--at", type=float, default=None,
                    help="time [s] of the frame of a still picture (default: the first)")
    ap.add_argument("--reference", action="store_true",
                    help="a simulation's file: draw the reference platform too (dashed)")
    a = ap.parse_args(argv)
    try:
        if a.stride < 1:
            raise ValueError(f"--stride: expected an integer >= 1, got {a.stride}")
        model, pose, t = read_run(a.file, a.case)
        ref = read_run(a.file, a.case, reference=True)[1] if a.reference else None
        if len(t) == 0:
            raise ValueError(f"{a.file}: case {a.case} has no sample")
        suffix = os.path.splitext(a.output)[1].lower()
        if suffix in (".png", ".pdf", ".svg"):
            k = 0 if a.at is None else int(np.argmin(np.abs(t - a.at)))
            draw(model, pose[k], path=a.output, dpi=a.dpi,
                 reference=None if ref is None else ref[k])
            print(f"{a.output}: t = {t[k]:.6g} s")
        else:
            n = animate(model, pose[::a.stride], a.output, times=t[::a.stride],
                        fps=a.fps, dpi=a.dpi,
                        reference=None if ref is None else ref[::a.stride])
            print(f"{a.output}: {n} frames")
    except (OSError, ValueError, RuntimeError) as e:
        print(f"python -m rps3.view: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
