"""rps3.view: the 3-D drawing, the animations and the HTML page.

The drawn positions are read back from the figure's artists (by gid) and
compared with positions written here from the model's inputs alone: pins
P_i = R (cos psi_i, sin psi_i, 0), ball joints b_i = c + Rz(a) Ry(b)
Rz(-a) r_i with the centre of (3)-(4) (as tests/test_oracles.py checks the
oracle's geometry); the links must end at the ball joints with the library's
lengths.  The GIF's and MP4's frame counts are read by Pillow and ffprobe;
the HTML page runs in headless Chromium, which must run its script without
an error and ink the canvas.
"""

import json
import os
import re
import shutil
import subprocess
import sys

import numpy as np
import pytest
import rps3
from conftest import CONFIGS, run
from PIL import Image
from rps3 import view

# positions of ~0.3 m from a handful of products and sines: a few ulp
# (2e-16 m each); 1e-12 m is far below any visible or modelling error and
# far above rounding, while a wrong angle of 1e-9 rad already moves a ball
# joint by 1e-10 m
TOL_POS = 1e-12
# the HTML page's data has 9 significant digits: 5e-10 m at 1 m
TOL_PAGE = 1e-9

ENTROPY = dict(R=0.2385, rho=0.4387, M=0.2381, m=0.0917, d=0.1383)


def poses(n=6, seed=2385):
    """High-entropy poses through the workspace."""
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(-3.0, 3.0, n), rng.uniform(0.02, 0.45, n),
                            rng.uniform(0.21, 0.37, n)])


def pins(model):
    psi = 2 * np.pi * np.arange(3) / 3
    return model.R * np.column_stack([np.cos(psi), np.sin(psi), np.zeros(3)])


def balls(model, pose):
    """b_i from the model's inputs: the platform's rotation Rz(a) Ry(b)
    Rz(-a) and centre (3)-(4), written here."""
    a, b, z = pose
    r = model.rho * model.R

    def rz(x):
        return np.array([[np.cos(x), -np.sin(x), 0], [np.sin(x), np.cos(x), 0], [0, 0, 1]])
    ry = np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])
    rot = rz(a) @ ry @ rz(-a)
    c = np.array([-0.5 * r * (1 - np.cos(b)) * np.cos(2 * a),
                  0.5 * r * (1 - np.cos(b)) * np.sin(2 * a), z])
    return c + (rot @ (pins(model) * model.rho).T).T


def artists(fig):
    """{gid: (m, 3) points} of the figure's 3-D lines."""
    ax = fig.axes[0]
    return {ln.get_gid(): np.column_stack(ln.get_data_3d()) for ln in ax.get_lines()}


@pytest.mark.parametrize("kw", [{}, ENTROPY], ids=["paper", "entropy"])
def test_drawing_is_the_mechanism(kw):
    model = rps3.Model(**kw)
    for pose in poses():
        fig = view.draw(model, pose)
        a = artists(fig)
        P, b = pins(model), balls(model, pose)
        l = model.ik(pose).l
        assert np.max(np.abs(a["base"] - np.vstack([P, P[:1]]))) <= TOL_POS
        assert np.max(np.abs(a["balls"] - b)) <= TOL_POS, (pose, a["balls"], b)
        assert np.max(np.abs(a["platform_edge"] - np.vstack([b, b[:1]]))) <= TOL_POS
        for i in range(3):
            barrel, piston, pin = a[f"barrel_{i}"], a[f"piston_{i}"], a[f"pin_{i}"]
            # the link: from the pin, a barrel of min(R, l) along it, then the
            # piston to the ball joint; together the library's length
            assert np.max(np.abs(barrel[0] - P[i])) <= TOL_POS
            assert np.max(np.abs(piston[1] - b[i])) <= TOL_POS
            assert np.max(np.abs(barrel[1] - piston[0])) == 0
            along = (b[i] - P[i]) / l[i]
            end = P[i] + min(model.R, l[i]) * along
            assert np.max(np.abs(barrel[1] - end)) <= TOL_POS
            assert abs(np.linalg.norm(b[i] - P[i]) - l[i]) <= TOL_POS
            # the pin axis: centred on P_i, horizontal, normal to the radius
            assert np.max(np.abs(pin.mean(axis=0) - P[i])) <= TOL_POS
            ax = pin[1] - pin[0]
            assert abs(ax[2]) <= TOL_POS and abs(ax @ P[i]) <= TOL_POS
            # the link turns about the pin axis: normal to it
            assert abs(ax @ along) <= TOL_POS * 10


def test_drawing_from_lengths_is_the_forward_kinematics():
    model = rps3.Model(**ENTROPY)
    pose = poses(1, seed=7)[0]
    fig = view.draw(model, lengths=model.ik(pose).l)
    # forward kinematics solves to opt.tol (1e-12 of R in (8)-(10))
    assert np.max(np.abs(artists(fig)["balls"] - balls(model, pose))) <= 1e-9


@pytest.mark.parametrize("suffix,magic", [(".svg", b"<?xml"), (".pdf", b"%PDF")])
def test_vector_output(tmp_path, suffix, magic):
    path = tmp_path / ("pose" + suffix)
    view.draw(rps3.Model(), [0.3, 0.1, 0.3], path=path)
    data = path.read_bytes()
    assert data.startswith(magic)
    if suffix == ".svg":
        # vector: the artists are there by name, as paths, not an image
        text = data.decode()
        for gid in ("base", "balls", "barrel_0", "piston_2", "platform"):
            assert f'id="{gid}"' in text, gid
        assert "<image" not in text


def test_raster_output_has_the_dpi(tmp_path):
    path = tmp_path / "pose.png"
    view.draw(rps3.Model(), [0.3, 0.1, 0.3], path=path, dpi=50, figsize=(4, 3))
    with Image.open(path) as im:
        assert im.size == (200, 150)


def test_unreachable_pose_is_refused():
    with pytest.raises(ValueError, match=r"^pose: \[0\.0, 0\.1, -0\.2\]: .*unreachable"):
        view.draw(rps3.Model(), [0.0, 0.1, -0.2])
    with pytest.raises(ValueError, match="draw takes one pose"):
        view.draw(rps3.Model(), poses(2))
    with pytest.raises(ValueError, match="barrel"):
        view.draw(rps3.Model(), [0.0, 0.1, 0.3], barrel=-1)


def frames_of_gif(path):
    with Image.open(path) as im:
        return im.n_frames


def test_gif_has_one_frame_per_pose(tmp_path):
    model = rps3.Model()
    traj = rps3.trajectory.helix(samples=9)
    path = tmp_path / "helix.gif"
    assert view.animate(model, traj.pose, path, times=traj.t, dpi=40) == 9
    assert frames_of_gif(path) == 9


def test_unreachable_frames_are_kept_and_marked(tmp_path):
    p = poses(5)
    p[2, 2] = -0.1  # below the base
    g = view.geometry(rps3.Model(), p)
    assert g.ok.tolist() == [True, True, False, True, True]
    assert np.isnan(g.ball[2]).all()
    path = tmp_path / "gap.gif"
    assert view.animate(rps3.Model(), p, path, dpi=40) == 5
    assert frames_of_gif(path) == 5
    assert "unreachable" in view._title(g, 2, None).lower()
    with pytest.raises(ValueError, match="no frame could be computed"):
        view.animate(rps3.Model(), p[2:3], tmp_path / "none.gif")
    with pytest.raises(ValueError, match="unknown suffix '.avi'"):
        view.animate(rps3.Model(), p, tmp_path / "x.avi")


def test_refused_frames_in_the_page_say_why(tmp_path):
    p = poses(4)
    p[1, 2] = -0.1
    page = tmp_path / "gap.html"
    assert view.html(rps3.Model(), p, page) == 4
    frames = page_data(page)["frames"]
    assert [f["ok"] for f in frames] == [True, False, True, True]
    assert frames[1]["ball"] is None and "unreachable" in frames[1]["text"].lower()


def test_a_failed_write_leaves_no_file(tmp_path, monkeypatch):
    """An animation that fails half-way (here the third frame) leaves
    neither the file nor its temporary: nothing partial looks complete."""
    from matplotlib import animation
    grab = animation.PillowWriter.grab_frame
    count = [0]

    def failing(self, **kw):
        count[0] += 1
        if count[0] == 3:
            raise OSError("disk full")
        return grab(self, **kw)
    monkeypatch.setattr(animation.PillowWriter, "grab_frame", failing)
    path = tmp_path / "half.gif"
    with pytest.raises(OSError, match="disk full"):
        view.animate(rps3.Model(), poses(5), path, dpi=30)
    assert os.listdir(tmp_path) == []
    with pytest.raises(OSError):
        view.draw(rps3.Model(), poses(1)[0], path=tmp_path / "no" / "such.pdf")
    for kw, name in (({"dpi": 0}, "dpi"), ({"fps": -1}, "fps"),
                     ({"figsize": (4, float("nan"))}, "figsize")):
        with pytest.raises(ValueError, match=f"^{name}: expected"):
            view.animate(rps3.Model(), poses(2), tmp_path / "x.gif", **kw)
    assert os.listdir(tmp_path) == []


@pytest.mark.skipif(shutil.which("ffmpeg") is None or shutil.which("ffprobe") is None,
                    reason="MP4 needs ffmpeg and ffprobe (Debian package ffmpeg; "
                           "make check installs it as root)")
def test_mp4_has_one_frame_per_pose(tmp_path):
    path = tmp_path / "helix.mp4"
    traj = rps3.trajectory.helix(samples=11)
    assert view.animate(rps3.Model(), traj.pose, path, times=traj.t, dpi=40) == 11
    out = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-select_streams",
                          "v:0", "-show_entries", "stream=nb_read_frames", "-of",
                          "csv=p=0", str(path)], capture_output=True, text=True,
                         check=True)
    assert int(out.stdout.strip()) == 11


# ------------------------------------------------------------------ HTML

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
needs_chromium = pytest.mark.skipif(
    CHROMIUM is None, reason="the HTML page is checked in headless Chromium "
                             "(Debian package chromium; make check installs it as root)")


def chromium(page, *args):
    """Run headless Chromium on the page for 1.5 s of its time."""
    cmd = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu",
           "--hide-scrollbars", "--window-size=800,720",
           "--virtual-time-budget=1500", *args, page.as_uri()]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=120)


def body_data(dom):
    """The data-* attributes the page's script set on <body>."""
    tag = re.search(r"<body([^>]*)>", dom)
    assert tag, dom[:500]
    return dict(re.findall(r'data-([a-z]+)="([^"]*)"', tag.group(1)))


def page_data(path):
    text = path.read_text()
    m = re.search(r'<script id="rps3-data" type="application/json">(.*?)</script>',
                  text, re.S)
    return json.loads(m.group(1).replace("<\\/", "</"))


@needs_chromium
def test_html_page_runs_in_a_browser(tmp_path):
    model = rps3.Model(**ENTROPY)
    p = poses(12)
    page = tmp_path / "robot.html"
    assert view.html(model, p, page, times=np.arange(12) * 0.1) == 12
    # the data drawn is the mechanism
    data = page_data(page)
    assert np.max(np.abs(np.array(data["pin"]) - pins(model))) <= TOL_PAGE
    for k in range(12):
        assert np.max(np.abs(np.array(data["frames"][k]["ball"]) - balls(model, p[k]))) \
            <= TOL_PAGE
    # the script ran to its end without an error, inked the canvas and
    # played on (the timer advanced the frame)
    proc = chromium(page, "--dump-dom")
    assert proc.returncode == 0, proc.stderr[-2000:]
    body = body_data(proc.stdout)
    assert "error" not in body, body["error"]
    assert body.get("ready") == "1" and body["frames"] == "12", body
    assert int(body["inked"]) > 20000, body   # ~47000 on the 720 x 540 canvas
    # 1.5 s of virtual time at 20 frames/s: the timer advanced the frame
    # about 30 times (at least 20 so that a slow start cannot hide a stall)
    assert int(body["played"]) >= 20, body
    assert int(body["frame"]) == int(body["played"]) % 12, body
    # what the browser shows: the canvas holds the parts' colours
    shot = tmp_path / "shot.png"
    proc = chromium(page, f"--screenshot={shot}")
    assert proc.returncode == 0 and shot.exists(), proc.stderr[-2000:]
    with Image.open(shot) as im:
        px = np.asarray(im.convert("RGB")).reshape(-1, 3).astype(int)
    for name in ("barrel", "ball", "platform"):
        rgb = np.array([int(view.COLOURS[name][i:i + 2], 16) for i in (1, 3, 5)])
        near = np.sum(np.all(np.abs(px - rgb) <= 8, axis=1))
        assert near > 50, (name, near)


@needs_chromium
def test_a_page_with_a_script_error_is_seen(tmp_path):
    """The check above can fail: a page whose script breaks reports it."""
    page = tmp_path / "broken.html"
    view.html(rps3.Model(), poses(3), page)
    text = page.read_text().replace("slider.max = String(n - 1);",
                                    "slider.max = String(n - 1); undefinedThing();")
    page.write_text(text)
    body = body_data(chromium(page, "--dump-dom").stdout)
    assert "undefinedThing" in body.get("error", ""), body
    assert "ready" not in body


# ------------------------------------------------------------ rps3-run files

@pytest.fixture(scope="module")
def paper_run(runner, tmp_path_factory):
    out = tmp_path_factory.mktemp("view") / "paper.h5"
    proc = run(os.path.join(CONFIGS, "paper.yaml"), out, "-q")
    assert proc.returncode == 0, proc.stderr
    return out


def test_read_run_is_the_runners_mechanism(paper_run):
    import h5py
    model, pose, t = view.read_run(paper_run, case=1)
    assert model.m == pytest.approx(0.09) and len(t) == 1001
    g = view.geometry(model, pose)
    with h5py.File(paper_run) as f:
        # the runner's link lengths: the same library, the same pose
        assert np.max(np.abs(g.l - f["length"][1])) <= TOL_POS
    with pytest.raises(ValueError, match="case: 2 is out of range"):
        view.read_run(paper_run, case=2)


def test_command_line(paper_run, tmp_path):
    gif = tmp_path / "paper.gif"
    cmd = [sys.executable, "-m", "rps3.view", str(paper_run), "--case", "1",
           "--stride", "100", "--dpi", "40", "-o", str(gif)]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert frames_of_gif(gif) == 11   # samples 0, 100, ..., 1000
    png = tmp_path / "paper.png"
    proc = subprocess.run(cmd[:-1] + [str(png), "--at", "5"], capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 0 and "t = 5 s" in proc.stdout, proc.stderr
    bad = subprocess.run(cmd[:4] + ["--case", "7", "-o", str(gif)], capture_output=True,
                         text=True, timeout=300)
    assert bad.returncode == 1
    assert "case: 7 is out of range" in bad.stderr and "Traceback" not in bad.stderr
    none = subprocess.run(cmd[:3] + [str(tmp_path / "absent.h5"), "-o", str(gif)],
                          capture_output=True, text=True, timeout=300)
    assert none.returncode == 1 and "absent.h5" in none.stderr


def test_read_run_without_pose_solves_the_lengths(paper_run, tmp_path):
    """A file written with --fields length: the pose by forward kinematics."""
    out = tmp_path / "lengths.h5"
    proc = run(os.path.join(CONFIGS, "paper.yaml"), out, "-q", "--fields", "length")
    assert proc.returncode == 0, proc.stderr
    _, want, t_want = view.read_run(paper_run, case=1)
    _, got, t = view.read_run(out, case=1)
    assert np.array_equal(t, t_want)
    # the theta solve stops at max |f| <= opt.tol = 1e-12 (in units of R)
    assert np.max(np.abs(got - want)) <= 1e-9


SIM_SCENE = """\
manipulator: {R: 0.2286, rho: 0.5, M: 0.18, m_over_M: 0.5, d: 0.1524}
trajectory: {kind: helix, radius: 0.000266, pitch: 0.03048, z0: 0.3048,
             period: 10.0, blend: 1.0, samples: 101}
simulate: {controller: pd_gravity}
"""


def test_a_simulation_is_animated(runner, tmp_path):
    import h5py
    scene = tmp_path / "sim.yaml"
    scene.write_text(SIM_SCENE)
    out = tmp_path / "sim.h5"
    proc = run(scene, out, "-q")
    assert proc.returncode == 0, proc.stderr
    model, pose, t = view.read_run(out)
    g = view.geometry(model, pose)
    with h5py.File(out) as f:
        # the plant's pose gives the plant's lengths (the simulation's
        # pose is its forward kinematics, solved to opt.tol)
        assert np.max(np.abs(g.l - f["length"][0])) <= 1e-9
    # the reference is the scene's helix
    _, ref, _ = view.read_run(out, reference=True)
    helix = rps3.trajectory.helix(model=model, radius=0.000266, pitch=0.03048, z0=0.3048,
                                  period=10.0, blend=1.0, samples=101)
    assert np.max(np.abs(ref - helix.pose)) <= TOL_POS
    page = tmp_path / "sim.html"
    proc = subprocess.run([sys.executable, "-m", "rps3.view", str(out), "--reference",
                           "-o", str(page)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    frames = page_data(page)["frames"]
    assert len(frames) == 101
    for k in (0, 50, 100):
        assert np.max(np.abs(np.array(frames[k]["ref"]) - balls(model, ref[k]))) <= TOL_PAGE
        assert np.max(np.abs(np.array(frames[k]["ball"]) - balls(model, pose[k]))) <= TOL_PAGE
    # one frame with its reference, read back from the figure
    fig = view.draw(model, pose[60], reference=ref[60])
    got = artists(fig)["reference"]
    assert np.max(np.abs(got - np.vstack([balls(model, ref[60])] * 2)[:4])) <= TOL_POS


def test_reference_needs_a_simulation(paper_run, tmp_path):
    proc = subprocess.run([sys.executable, "-m", "rps3.view", str(paper_run), "--reference",
                           "-o", str(tmp_path / "x.html")], capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 1 and "no dataset 'alpha_ref'" in proc.stderr, proc.stderr
    with pytest.raises(ValueError, match="reference: 2 poses for 3 frames"):
        view.html(rps3.Model(), poses(3), tmp_path / "y.html", reference=poses(2))


def test_read_run_of_cases_on_their_own_time_grids(tmp_path):
    """A sweep whose cases have their own time grids (configs/period.yaml)
    has no `time` dataset but `case_time`: read_run takes each case's."""
    out = tmp_path / "period.h5"
    assert run(os.path.join(CONFIGS, "period.yaml"), out, "-q").returncode == 0
    import h5py
    with h5py.File(out, "r") as f:
        assert "time" not in f and "case_time" in f
        want = f["case_time"][1]
    _, pose, t = view.read_run(out, 1)
    want = want[np.isfinite(want)]
    assert np.array_equal(t, want) and pose.shape == (len(want), 3)
