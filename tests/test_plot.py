"""Figures fit for a paper (python/rps3/plot.py and the analysis scripts):
every figure written as PDF, SVG and PNG, the PNG at the dpi asked for;
warned samples marked (the artist found, on the warned samples only) with
a legend entry and a note saying why; legends that say what a curve is."""

import os
import subprocess
import sys

import h5py
import numpy as np
import pytest
from conftest import ANALYSIS, CONFIGS, ROOT, run, script, write_scene
from PIL import Image
from rps3 import h5io, plot

# the magic bytes of each format
MAGIC = {"pdf": b"%PDF", "png": b"\x89PNG", "svg": b"<?xml"}
# an odd dpi, so that a default cannot pass for it
DPI = 73


def check_file(path, fmt, dpi=DPI):
    """path is a file of format fmt; a PNG says it is at dpi."""
    with open(path, "rb") as fh:
        head = fh.read(5)
    assert head.startswith(MAGIC[fmt]), (path, head)
    if fmt == "svg":
        with open(path, encoding="utf-8") as fh:
            assert "<svg" in fh.read(2000)
    if fmt == "png":
        with Image.open(path) as im:
            # pHYs: pixels per metre, rounded by PNG to whole numbers
            assert im.info["dpi"] == pytest.approx((dpi, dpi), abs=0.05)
            return im.size
    return None


@pytest.mark.parametrize("fmt", plot.FORMATS)
def test_save_writes_the_format_of_the_suffix(tmp_path, fmt):
    fig, ax = plot.subplots()
    ax.plot([0, 1], [0, 1])
    path = plot.save(fig, tmp_path / f"a.{fmt}", DPI)
    check_file(path, fmt)


def test_png_pixels_follow_dpi(tmp_path):
    """The same figure at two dpi: pixel sizes in their ratio (the tight
    box is the same in inches), at most the figure's inches times dpi."""
    sizes = {}
    for dpi in (50, 150):
        fig, ax = plot.subplots(figsize=(4.0, 3.0))
        ax.plot([0, 1], [0, 1], label="a line")
        ax.set_xlabel("x [m]")
        plot.legend(ax)
        sizes[dpi] = check_file(plot.save(fig, tmp_path / f"d{dpi}.png", dpi),
                                "png", dpi)
    w50, h50 = sizes[50]
    w150, h150 = sizes[150]
    # a pixel of rounding at 50 dpi is three at 150, and text is hinted
    # to whole pixels: 2 % (a wrong dpi is off by its ratio)
    assert abs(w150 - 3 * w50) <= 0.02 * w150
    assert abs(h150 - 3 * h50) <= 0.02 * h150
    assert 0.8 * 4.0 * 150 <= w150 <= 4.0 * 150 + 2
    assert 0.8 * 3.0 * 150 <= h150 <= 3.0 * 150 + 2


def test_save_refuses_unknown_suffix_and_dpi(tmp_path):
    fig, _ = plot.subplots()
    with pytest.raises(ValueError, match="suffix"):
        plot.save(fig, tmp_path / "a.jpg")
    with pytest.raises(ValueError, match="dpi"):
        plot.save(fig, tmp_path / "a.png", dpi=0)
    assert not list(tmp_path.iterdir())


def test_mark_warned_marks_the_warned_samples_only():
    t = np.linspace(0, 1, 11)
    y = np.stack([t, 2 * t, 3 * t], axis=1)
    # bit 8 (transmission) on samples 2 and 7; bit 1 alone and -1
    # (missing) are not transmission warnings
    warn = np.array([0, 1, 8, 0, -1, 0, 0, 9, 0, 1, 0], dtype=np.int32)
    fig, ax = plot.subplots()
    art = plot.mark_warned(ax, t, y, warn)
    assert plot.warned_samples(ax) == [art]
    assert art.get_label() == plot.WARNED_LABEL
    xs, ys = art.get_data()
    np.testing.assert_array_equal(xs, np.repeat(t[[2, 7]], 3))
    np.testing.assert_array_equal(ys, y[[2, 7]].ravel())
    # no warned sample: nothing drawn, no legend entry
    fig2, ax2 = plot.subplots()
    assert plot.mark_warned(ax2, t, y, np.zeros(11, np.int32)) is None
    assert plot.warned_samples(ax2) == []


# ------------------------------------------------------- the scripts' figures

def legend_texts(fig):
    return [t.get_text() for ax in fig.axes if ax.get_legend()
            for t in ax.get_legend().get_texts()]


def figure_texts(fig):
    return " ".join(t.get_text() for t in fig.texts)


@pytest.fixture(scope="module")
def warned_run(runner, tmp_path_factory):
    """A circle 10 mm off the axis with a 30 mm radius: it crosses the
    near-singular tilts, where samples pass trans_warn."""
    tmp = tmp_path_factory.mktemp("warned")
    text = open(os.path.join(CONFIGS, "circle.yaml")).read()
    text = text.replace("centre: [0.008, 0, 0.30]", "centre: [0.01, 0, 0.30]")
    text = text.replace("radius: 0.004 ", "radius: 0.03 ")
    scene = write_scene(tmp / "warned.yaml", text)
    out = tmp / "warned.h5"
    proc = run(scene, out, "-q")
    assert proc.returncode == 0, proc.stderr
    with h5py.File(out, "r") as f:
        assert plot.warned(f["warn"][0]).sum() > 0
    return out


def test_trajectory_figure_marks_warned_samples(warned_run, config_runs):
    traj = script("trajectories")
    fig = traj.draw(warned_run)
    with h5py.File(warned_run, "r") as f:
        n = int(plot.warned(f["warn"][0]).sum())
        force = f["force"][0]
    marks = [a for ax in fig.axes for a in plot.warned_samples(ax)]
    assert len(marks) == 1 and len(marks[0].get_xdata()) == 3 * n
    # the spikes are the marked samples: the largest |F| is warned
    assert np.nanmax(np.abs(marks[0].get_ydata())) == np.nanmax(np.abs(force))
    assert plot.WARNED_LABEL in legend_texts(fig)
    assert "trans_warn" in figure_texts(fig)
    # the shipped circle has none: no marker, no note
    fig = traj.draw(config_runs["circle"][0])
    assert not [a for ax in fig.axes for a in plot.warned_samples(ax)]
    assert figure_texts(fig) == ""


def test_paper_force_figure_marks_warned_samples(warned_run, paper_h5):
    figures = script("figures")
    with h5py.File(warned_run, "r") as f:
        fig = figures.forces_figure(f, 0, (-3000, 3000), "warned")
    assert plot.warned_samples(fig.axes[0])
    assert plot.WARNED_LABEL in legend_texts(fig)
    with h5py.File(paper_h5, "r") as f:
        fig = figures.forces_figure(f, 1, (-1, 1), "Fig. 4")
    texts = legend_texts(fig)
    assert texts == [r"$F_i$, link 1", r"$F_i$, link 2", r"$F_i$, link 3"]
    # three distinguishable curves: three line styles
    styles = {line.get_linestyle() for line in fig.axes[0].get_lines()}
    assert len(styles) == 3


def test_closed_loop_legend_says_what_the_keys_mean(config_runs):
    closed_loop = script("closed_loop")
    keys, cases = closed_loop.load(config_runs["closed_loop"][0])
    assert [k for k, _ in keys] == ["simulate.controller",
                                    "simulate.model.m_over_M"]
    fig = closed_loop.figure(cases)
    texts = legend_texts(fig)
    assert "pd, controller's model: m/M = 0.5" in texts
    assert not any("m_over_M" in t for t in texts)
    title = fig.axes[0].get_legend().get_title().get_text()
    assert "controller" in title and "plant" in title
    # each case's curve its own line style and marker
    lines = [ln for ln in fig.axes[0].get_lines() if ln.get_label() in texts]
    looks = {(ln.get_linestyle(), ln.get_marker()) for ln in lines}
    assert len(looks) == len(cases) == 6


def run_script(*args):
    proc = subprocess.run([sys.executable, *map(str, args)],
                          capture_output=True, text=True, timeout=300,
                          cwd=ROOT)
    assert proc.returncode == 0, proc.stderr
    return proc


@pytest.mark.parametrize("fmt", plot.FORMATS)
def test_every_figure_in_every_format(fmt, config_runs, paper_h5, tmp_path):
    """The scripts `make paper`, `make trajectories` and `make
    closed-loop` run, asked for each format at DPI."""
    opts = ["--format", fmt, "--dpi", DPI]
    run_script(os.path.join(ANALYSIS, "figures.py"), paper_h5, tmp_path,
               *opts)
    for n in (2, 3, 4):
        check_file(tmp_path / f"fig{n}.{fmt}", fmt)
    runs = [config_runs[k][0] for k in ("circle", "line", "pick_place")]
    run_script(os.path.join(ANALYSIS, "trajectories.py"), tmp_path, *runs,
               *opts)
    for k in ("circle", "line", "pick_place"):
        check_file(tmp_path / f"traj_{k}.{fmt}", fmt)
    out = tmp_path / f"closed_loop.{fmt}"
    run_script(os.path.join(ANALYSIS, "closed_loop.py"),
               config_runs["closed_loop"][0], out, "--dpi", DPI)
    check_file(out, fmt)
    run_script(os.path.join(ANALYSIS, "measured.py"), "figure",
               config_runs["measured"][0], tmp_path, *opts)
    check_file(tmp_path / f"measured.{fmt}", fmt)
    run_script(os.path.join(ANALYSIS, "summary.py"),
               tmp_path / f"summary.{fmt}", paper_h5, "--dpi", DPI)
    check_file(tmp_path / f"summary.{fmt}", fmt)


def test_study_figures_in_a_vector_format(tmp_path):
    """The workspace and assembly-mode figures as SVG and PDF."""
    study = os.path.join(ROOT, "build", "rps3-study")
    ws = tmp_path / "ws.h5"
    proc = subprocess.run([study, "workspace", "-o", str(ws), "--quick"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    run_script(os.path.join(ANALYSIS, "workspace.py"), ws, tmp_path,
               "--format", "svg")
    check_file(tmp_path / "workspace.svg", "svg")
    run_script(os.path.join(ANALYSIS, "assembly_modes.py"), tmp_path,
               "--format", "pdf")
    check_file(tmp_path / "assembly_modes.pdf", "pdf")


def test_h5io_reads_the_keys_the_figures_label(config_runs):
    with h5py.File(config_runs["closed_loop"][0], "r") as f:
        assert h5io.sweep_keys(f) == ["simulate.controller",
                                      "simulate.model.m_over_M"]


def test_tracking_legend_in_the_svg_text(tmp_path):
    """simulation.py's tracking figure: the legend names the controller's
    model; SVG keeps the text as text, so a reader finds it."""
    simulation = script("simulation")
    t = np.linspace(0, 1, 50)
    tr = {"time": t, "error": np.full((2, 2, 50), 1e-4) * (1 + t),
          "status": np.zeros((2, 2)), "controllers": ["pd", "pd_gravity"],
          "models": ["exact", "no_link_mass"]}
    out = tmp_path / "tracking.svg"
    simulation.plot_tracking(tr, "tracking", out, DPI)
    check_file(out, "svg")
    svg = out.read_text(encoding="utf-8")
    assert svg.count("model: no link mass") == 2
    assert svg.count("model: exact") == 2
