"""rps3-run end to end: the HDF5 layout, xarray, sweeps, failing cases,
reruns of single cases, interrupts, exit codes, progress and memory."""

import datetime
import itertools
import os
import pty
import re
import resource
import signal
import subprocess
import sys
import time

import h5py
import numpy as np
import pytest
import xarray as xr
import yaml

from rps3 import h5io
from conftest import CONFIGS, ROOT, RUNNER, failing_sine, run, write_scene, run_tmp

PER_POINT = ["force", "length", "length_rate", "length_accel", "theta",
             "alpha", "beta", "z_c", "x_c", "y_c", "lambda",
             "energy_residual", "energy_scale", "condition", "solve_resid"]


# ------------------------------------------------------------------ layout

def test_root_attributes_and_scene(paper_h5):
    with h5py.File(paper_h5, "r") as f:
        a = {k: h5io.text(v) for k, v in f.attrs.items()}
        with open(os.path.join(ROOT, "include", "rps3.h")) as h:
            version = re.search(r'#define RPS3_VERSION_STRING "([^"]+)"',
                                h.read()).group(1)
        assert a["rps3_version"] == version
        assert a["gsl_version"].count(".") >= 1
        assert a["hdf5_version"].startswith("1.")
        assert "configs/paper.yaml" in a["command_line"]
        when = datetime.datetime.strptime(a["created_utc"], "%Y-%m-%dT%H:%M:%SZ")
        assert abs((datetime.datetime.utcnow() - when).total_seconds()) < 600
        with open(os.path.join(CONFIGS, "paper.yaml")) as g:
            assert h5io.text(f["scene"][()]) == g.read()
        assert f["scene"].shape == ()


def test_every_dataset_has_units_and_description(paper_h5):
    with h5py.File(paper_h5, "r") as f:
        for name, ds in f.items():
            assert "units" in ds.attrs, name
            assert len(h5io.text(ds.attrs["description"])) > 10, name


def test_dimensions(paper_h5):
    with h5py.File(paper_h5, "r") as f:
        expect = {
            "force": ("case", "time", "link"),
            "force_by_effect": ("case", "time", "effect", "link"),
            "length": ("case", "time", "link"),
            "lambda": ("case", "time", "constraint"),
            "alpha": ("case", "time"),
            "energy_residual": ("case", "time"),
            "status": ("case",),
            "message": ("case",),
            "failed_at": ("case",),
            "scene_resolved": ("case",),
            "manipulator__m_over_M": ("case",),
        }
        for name, dims in expect.items():
            assert h5io.dims(f[name]) == dims, name
        assert list(f["link"][()]) == [1, 2, 3]
        assert h5io.effects(f) == ["platform_gravity", "link_gravity",
                                     "platform_inertia", "link_inertia"]
        assert f["time"][0] == 0 and f["time"][-1] == 10.0
        assert f["force"].chunks[0] >= 1 and f["force"].chunks[1] == 1001
        coords = h5io.text(f["force"].attrs["coordinates"])
        # the swept key's variable has a CF name, the key in scene_key
        assert coords == "manipulator__m_over_M"
        assert h5io.text(f["manipulator__m_over_M"].attrs["scene_key"]) == \
            "manipulator.m_over_M"


def test_xarray_opens_with_named_dimensions(paper_h5):
    # time in seconds (its CF units name a nominal date: docs/hdf5.md)
    with xr.open_dataset(paper_h5, engine="h5netcdf",
                         decode_times=False) as ds:
        assert ds["force"].dims == ("case", "time", "link")
        assert ds["force_by_effect"].dims == ("case", "time", "effect", "link")
        assert ds["lambda"].dims == ("case", "time", "constraint")
        assert set(ds.sizes) == {"case", "time", "link", "effect", "constraint"}
        assert "manipulator__m_over_M" in ds["force"].coords
        # select by parameter value
        by_mass = ds.swap_dims(case="manipulator__m_over_M")
        f4 = by_mass["force"].sel(manipulator__m_over_M=0.5)
        with h5py.File(paper_h5, "r") as f:
            np.testing.assert_array_equal(f4.values, f["force"][1])
        assert float(ds["force"].sel(time=5.0, link=2)[0]) == pytest.approx(
            float(ds["force"][0, 500, 1]), rel=0, abs=0)


def test_xarray_with_differing_time_grids(config_runs):
    h5, proc = config_runs["period"]
    assert proc.returncode == 0
    with xr.open_dataset(h5, engine="h5netcdf") as ds:
        # the dimension along the samples is `sample` (an index): the time
        # of each sample is case_time
        assert ds["case_time"].dims == ("case", "sample")
        assert ds["force"].dims == ("case", "sample", "link")
        assert "case_time" in ds["force"].coords
        assert "case_time" not in ds["status"].coords
        t = ds["case_time"].values
        np.testing.assert_array_equal(t[:, -1],
                                      ds["trajectory__period"].values)
        assert np.all(np.diff(t, axis=1) > 0)


# ------------------------------------------------------------------ sweeps

def test_sweep_order_is_row_major_last_key_fastest(config_runs):
    h5, proc = config_runs["grid"]
    assert proc.returncode == 0
    with h5py.File(h5, "r") as f:
        keys = h5io.sweep_keys(f)
        assert keys == ["manipulator.m_over_M", "manipulator.rho",
                        "trajectory.pitch"]
        scene = yaml.safe_load(h5io.text(f["scene"][()]))
        grid = list(itertools.product(*(scene["sweep"][k] for k in keys)))
        got = list(zip(*(h5io.sweep_value(f, k) for k in keys)))
        assert got == grid
        np.testing.assert_array_equal(f["case"][()], np.arange(len(grid)))


def test_range_forms(config_runs):
    with h5py.File(config_runs["mass_ratio"][0], "r") as f:
        v = f["manipulator__m_over_M"][()]
        assert len(v) == 11 and v[0] == 0 and v[-1] == 1.0
        np.testing.assert_allclose(v, np.arange(11) / 10, rtol=0, atol=1e-15)
    with h5py.File(config_runs["rho"][0], "r") as f:
        v = f["manipulator__rho"][()]
        np.testing.assert_allclose(v, np.linspace(0.2, 0.9, 8), rtol=1e-15)
        assert v[-1] == 0.9


def test_each_case_reruns_alone_identically(runner, config_runs, tmp_path):
    """scene_resolved of a case, run alone, gives the same numbers bit for
    bit: nothing (the multiroot warm start included) leaks between cases."""
    for name, case in (("grid", 29), ("sine", 1), ("period", 4),
                       ("general_bodies", 2)):
        h5 = config_runs[name][0]
        with h5py.File(h5, "r") as f:
            text = h5io.text(f["scene_resolved"][case])
            want = {k: f[k][case] for k in PER_POINT}
        assert "sweep" not in yaml.safe_load(text)
        alone = write_scene(tmp_path / f"{name}.yaml", text)
        out = tmp_path / f"{name}.h5"
        proc = run(alone, out, "-q")
        assert proc.returncode == 0, proc.stderr
        with h5py.File(out, "r") as g:
            for k in PER_POINT:
                np.testing.assert_array_equal(g[k][0], want[k], err_msg=k)


def test_failing_case_keeps_the_others(runner, tmp_path):
    scene = write_scene(tmp_path / "f.yaml", failing_sine(theta="multiroot"))
    out = tmp_path / "f.h5"
    proc = run(scene, out)
    assert proc.returncode == 1, proc.stderr
    assert "3/3 cases (1 failed)" in proc.stderr
    with h5py.File(out, "r") as f:
        # the platform sinks to the base: one sample before it is
        # unreachable (status 1), the multiroot solve reaches another root
        # than the pose's own (status 7, RPS3_EMODE), never a success
        np.testing.assert_array_equal(f["status"][()], [0, 7, 0])
        fa = f["failed_at"][()]
        assert fa[0] == -1 and fa[2] == -1 and 0 < fa[1] < 200
        msg = h5io.text(f["message"][1])
        assert msg.startswith(f"t = ") and f"(sample {fa[1]})" in msg
        assert "another assembly mode" in msg
        assert h5io.text(f["message"][0]) == ""
        for k in PER_POINT:
            assert np.isnan(f[k][1]).all(), k
            assert not np.isnan(f[k][[0, 2]]).any(), k
        assert (f["solve_niter"][1] == -1).all()
        # the cases after the failure are those of a run without it
        good = f["force"][2]
        ok_scene = h5io.text(f["scene_resolved"][2])
    out2 = tmp_path / "ok.h5"
    assert run(write_scene(tmp_path / "ok.yaml", ok_scene), out2).returncode == 0
    with h5py.File(out2, "r") as g:
        np.testing.assert_array_equal(g["force"][0], good)


def test_long_case_in_windows(runner, tmp_path):
    """A case longer than a tile is written in windows; a failure in a late
    window turns the windows already written into NaN."""
    scene = write_scene(tmp_path / "w.yaml",
                        failing_sine(samples=40001, theta="multiroot"))
    out = tmp_path / "w.h5"
    proc = run(scene, out, "-q")
    assert proc.returncode == 1
    with h5py.File(out, "r") as f:
        # 40001 samples in 3 even windows (chunks) of 13334
        assert f["force"].chunks[:2] == (1, 13334)
        fa = f["failed_at"][()]
        assert fa[1] > 16384
        assert np.isnan(f["force"][1]).all()
        assert not np.isnan(f["force"][0]).any()
        # multiroot theta, warm-started across windows, against the pose
        with_closed = f["theta"][0]
    closed = write_scene(tmp_path / "c.yaml", failing_sine(samples=40001))
    out2 = tmp_path / "c.h5"
    run(closed, out2, "-q")
    with h5py.File(out2, "r") as g:
        np.testing.assert_allclose(g["theta"][0], with_closed, rtol=0,
                                   atol=1e-12)


def test_lambda_is_nan_under_newton_euler(config_runs):
    h5, proc = config_runs["sine"]
    assert proc.returncode == 0
    with h5py.File(h5, "r") as f:
        method = [h5io.text(m) for m in f["solver__method"][()]]
        assert method == ["lagrange", "newton_euler"]
        assert not np.isnan(f["lambda"][0]).any()
        assert np.isnan(f["lambda"][1]).all()
        assert "NaN under newton_euler" in h5io.text(
            f["lambda"].attrs["description"])


# --------------------------------------------------------------- processes

def big_scene(tmp_path, ncase, samples=1001):
    text = open(os.path.join(CONFIGS, "paper.yaml")).read()
    text = text.replace("samples: 1001", f"samples: {samples}")
    text = text.replace("manipulator.m_over_M: [0, 0.5]",
                        f"manipulator.m_over_M: {{from: 0, to: 1, num: {ncase}}}")
    return write_scene(tmp_path / "big.yaml", text)


@pytest.mark.parametrize("sig,threads", [(signal.SIGINT, 1),
                                         (signal.SIGTERM, 1),
                                         (signal.SIGINT, 2)])
def test_interrupted_run_leaves_no_file(runner, tmp_path, sig, threads):
    scene = big_scene(tmp_path, 20000)
    out = tmp_path / "big.h5"
    p = subprocess.Popen([RUNNER, str(scene), "-o", str(out), "-q",
                          "-j", str(threads)], stderr=subprocess.PIPE)
    tmp = run_tmp(tmp_path / "big.h5", p.pid)
    deadline = time.time() + 20
    while not tmp.exists() and time.time() < deadline:
        time.sleep(0.01)
    assert tmp.exists()
    time.sleep(0.3)
    p.send_signal(sig)
    p.wait(timeout=20)
    assert p.returncode == -sig
    assert sorted(x.name for x in tmp_path.iterdir()) == ["big.yaml"]


def test_exit_codes(runner, tmp_path):
    paper = os.path.join(CONFIGS, "paper.yaml")
    assert run(paper).returncode == 2                    # no -o
    assert run(paper, tmp_path / "x.h5", "--bogus").returncode == 2
    assert run(paper, tmp_path / "x.h5", "--gzip", "12").returncode == 2
    proc = run(paper, tmp_path / "no" / "dir" / "x.h5")
    assert proc.returncode == 2                          # refused up front
    assert "No such file or directory" in proc.stderr
    assert not (tmp_path / "no").exists()
    proc = run(paper, None, "--check")
    assert proc.returncode == 0
    assert "2 cases, 2002 samples" in proc.stdout
    assert "output about 801 kB uncompressed" in proc.stdout
    assert subprocess.run([RUNNER, "--help"], capture_output=True).returncode == 0


def test_check_estimates_the_run_time(runner, tmp_path):
    """--check times a few samples of a few cases and states the run time
    as an estimate (never asserted against a clock: only its form, what it
    counts and how it scales with what it is told)."""
    paper = os.path.join(CONFIGS, "paper.yaml")

    def said(*args, scene=paper):
        proc = run(scene, None, "--check", *args)
        assert proc.returncode == 0, proc.stderr
        line = [x for x in proc.stdout.splitlines()
                if x.startswith("run time")]
        assert len(line) == 1, proc.stdout
        return line[0]

    line = said()
    m = re.match(r"run time about ([0-9.e+-]+) (s|min|h|days) on 1 thread "
                 r"\(an estimate: ([0-9.e+-]+) us a sample computing, timed "
                 r"on (\d+) samples of 2 cases, \+ ([0-9.e+-]+) us writing\)$",
                 line)
    assert m, line
    # both cases, all of their 1001 samples (up to 6000 in all)
    assert int(m.group(4)) == 2002
    assert float(m.group(3)) > 0 and float(m.group(5)) > 0
    # deflating costs more than writing
    gz = re.search(r"\+ ([0-9.e+-]+) us writing \+ ([0-9.e+-]+) us "
                   r"deflating\)$", said("--gzip", "1"))
    assert gz and float(gz.group(2)) > float(gz.group(1))
    # one job (both cases in one tile): -j 2 has one thread at work
    assert " on 1 thread " in said("-j", "2")
    # three long cases are three jobs: -j 2 runs on 2 threads
    many = write_scene(tmp_path / "many.yaml", failing_sine(samples=20001))
    assert "timed on 6000 samples of 3 cases" in said(scene=many)
    assert " on 2 threads " in said("-j", "2", scene=many)
    # a case that fails at its first sample is timed on that sample
    text = failing_sine().replace("[0.05, 0.2, 0.1]", "[0.2]")
    text = text.replace("mean: [0, 0.05, 0.15]", "mean: [0, 0.05, -0.15]")
    dead = write_scene(tmp_path / "dead.yaml", text)
    assert "timed on 1 samples of 1 case" in said(scene=dead)


def test_gzip_gives_the_same_numbers(runner, tmp_path, paper_h5):
    out = tmp_path / "z.h5"
    assert run(os.path.join(CONFIGS, "paper.yaml"), out, "--gzip", "4",
               "-q").returncode == 0
    with h5py.File(out, "r") as f, h5py.File(paper_h5, "r") as g:
        assert f["force"].compression == "gzip"
        for k in PER_POINT:
            np.testing.assert_array_equal(f[k][()], g[k][()], err_msg=k)


def test_progress_lines_quiet_and_bar(runner, tmp_path):
    paper = os.path.join(CONFIGS, "paper.yaml")
    proc = run(paper, tmp_path / "a.h5")
    assert proc.returncode == 0
    first, last = proc.stderr.splitlines()
    assert first.startswith("rps3-run: 2 cases, 2002 samples: ")
    # the size, and the run time estimated from a few timed samples
    size, when = first.split("a.h5 about ")[1].split(", about ")
    assert size == "801 kB"
    assert when.endswith(" s on 1 thread") and float(when.split()[0]) > 0
    assert last.startswith("rps3-run: 2/2 cases (0 failed), 2002 samples")
    proc = run(paper, tmp_path / "b.h5", "--quiet")
    assert proc.returncode == 0 and proc.stderr == ""
    # on a terminal: a bar redrawn with \r
    scene = big_scene(tmp_path, 1000)
    master, slave = pty.openpty()
    p = subprocess.Popen([RUNNER, str(scene), "-o", str(tmp_path / "c.h5")],
                         stderr=slave, stdout=subprocess.DEVNULL)
    os.close(slave)
    chunks = []
    while True:
        try:
            data = os.read(master, 4096)
        except OSError:
            break
        if not data:
            break
        chunks.append(data)
    p.wait(timeout=30)
    os.close(master)
    screen = b"".join(chunks).decode()
    assert p.returncode == 0
    assert "\r[" in screen and "cases/s" in screen and "ETA" in screen
    assert "1000/1000 cases (0 failed)" in screen


def on_a_terminal(args, columns=50):
    """stderr of rps3-run ARGS on a pseudo-terminal COLUMNS wide."""
    import fcntl
    import struct
    import termios
    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ,
                struct.pack("HHHH", 24, columns, 0, 0))
    p = subprocess.Popen([RUNNER] + [str(a) for a in args], stderr=slave,
                         stdout=subprocess.DEVNULL)
    os.close(slave)
    chunks = []
    while True:
        try:
            data = os.read(master, 4096)
        except OSError:
            break
        if not data:
            break
        chunks.append(data)
    p.wait(timeout=60)
    os.close(master)
    return p.returncode, b"".join(chunks).decode()


def test_the_bar_fits_the_terminal_and_clears_its_line(runner, tmp_path):
    code, screen = on_a_terminal([big_scene(tmp_path, 1000), "-o",
                                  tmp_path / "c.h5"], columns=50)
    assert code == 0
    bars = [b.split("\033[K")[0] for b in screen.split("\r")[1:]]
    bars = [b for b in bars if b.startswith("[")]
    assert bars, screen
    # each redraw is cut to the width (49 columns: the cursor stays on the
    # line) and clears what a longer previous one left
    assert all(len(b) <= 49 for b in bars), bars
    assert screen.count("\033[K") >= len(bars)
    # the summary replaces the bar: it starts its own line
    assert "\r\033[Krps3-run: 1000/1000 cases (0 failed)" in screen


def test_the_bar_moves_inside_one_long_case(runner, tmp_path):
    """One case of 3 M samples: the bar moves by samples, not by cases."""
    text = open(os.path.join(CONFIGS, "paper.yaml")).read()
    text = text.replace("samples: 1001", "samples: 3000001")
    text = text.replace("manipulator.m_over_M: [0, 0.5]",
                        "manipulator.m_over_M: [0.5]")
    scene = write_scene(tmp_path / "one.yaml", text)
    code, screen = on_a_terminal([scene, "-o", tmp_path / "one.h5",
                                  "--fields", "force"], columns=120)
    assert code == 0
    bars = [b for b in screen.split("\r") if b.startswith("[")]
    # some redraw before the end shows part of the bar filled while the
    # only case is still running (0/1 cases)
    partial = [b for b in bars if " 0/1 cases" in b and "#" in b]
    assert partial, bars


def test_quiet_still_names_the_first_failure(runner, tmp_path):
    scene = write_scene(tmp_path / "f.yaml", failing_sine())
    for extra in (["-q"], []):
        proc = run(scene, tmp_path / "f.h5", *extra)
        assert proc.returncode == 1
        lines = [ln for ln in proc.stderr.splitlines() if "first failure" in ln]
        assert len(lines) == 1, proc.stderr
        assert lines[0].startswith("rps3-run: first failure: case 1 "
                                   "(trajectory.amp[2] = 0.2): t = ")
        assert "unreachable" in lines[0]
    assert proc.stderr.splitlines()[-1].startswith("rps3-run: 3/3 cases "
                                                   "(1 failed)")


def child_maxrss_kib(args):
    """Peak RSS of rps3-run with these arguments, in a fresh process."""
    code = ("import resource, subprocess, sys; "
            "subprocess.run(sys.argv[1:], check=True); "
            "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)")
    out = subprocess.run([sys.executable, "-c", code] + args,
                         capture_output=True, text=True, check=True)
    return int(out.stdout)


def test_memory_stays_flat(runner, tmp_path):
    """Ten times the cases (both runs fill whole tiles): the file grows ten
    times, the peak memory by less than 8 MiB (HDF5's bounded metadata
    cache; the tiles and the chunks are the same size)."""
    rss = []
    for ncase in (3000, 30000):
        scene = big_scene(tmp_path, ncase, samples=11)
        out = tmp_path / f"m{ncase}.h5"
        rss.append(child_maxrss_kib([RUNNER, str(scene), "-o", str(out),
                                     "-q"]))
        out.unlink()
    assert rss[1] < rss[0] + 8 * 1024, rss


# ------------------------------------------------------------ command line

def _cli(*args):
    return subprocess.run([RUNNER, *map(str, args)], capture_output=True,
                          text=True, timeout=60)


def test_getopt_forms_give_the_same_file(runner, tmp_path):
    """--output=F, -oF, -o F, -j2, --jobs 2, --gzip=1, bundled -qo F and
    options after the scene or before it: getopt_long's forms, one file."""
    paper = os.path.join(CONFIGS, "paper.yaml")
    forms = {"a": ["-o", "{}", paper, "-q"],
             "b": [paper, "--output={}", "-q", "-j2"],
             "c": [paper, "-o{}", "--jobs", "2", "--quiet"],
             "d": ["-qo", "{}", "--jobs=1", paper],
             "e": [paper, "--out", "{}", "-q", "--gzip=1"]}
    for name, args in forms.items():
        out = tmp_path / f"{name}.h5"
        p = _cli(*[a.replace("{}", str(out)) for a in args])
        assert p.returncode == 0, (args, p.stderr)
    with h5py.File(tmp_path / "a.h5", "r") as ref:
        for name in "bcde":
            with h5py.File(tmp_path / f"{name}.h5", "r") as f:
                np.testing.assert_array_equal(f["force"][()],
                                              ref["force"][()])
    with h5py.File(tmp_path / "e.h5", "r") as f:
        assert f["force"].compression == "gzip"
    assert sorted(os.listdir(tmp_path)) == [f"{n}.h5" for n in "abcde"]


@pytest.mark.parametrize("args,said", [
    (["--bogus"], "rps3-run: unknown option '--bogus'"),
    (["-Z"], "rps3-run: unknown option '-Z'"),
    (["-j"], "rps3-run: -j needs a value"),
    (["--gzip"], "rps3-run: --gzip needs a value"),
    (["-j0"], "rps3-run: -j needs a whole number 1-1024, got '0'"),
    (["--jobs=2x"], "rps3-run: -j needs a whole number 1-1024, got '2x'"),
    (["--gzip=10"], "rps3-run: --gzip needs a whole number 0-9, got '10'")])
def test_getopt_errors_name_the_option(runner, tmp_path, args, said):
    out = tmp_path / "x.h5"
    p = _cli(os.path.join(CONFIGS, "paper.yaml"), "-o", out, *args)
    assert p.returncode == 2
    assert said in p.stderr, p.stderr
    assert os.listdir(tmp_path) == []


def test_help_lists_every_option_of_the_table(runner):
    p = _cli("--help")
    assert p.returncode == 0
    for opt in ("-o, --output OUT.h5", "-q, --quiet", "--gzip LEVEL",
                "--fields LIST", "--check", "-j, --jobs N", "--shard K/N",
                "--resume", "--failed-ok", "--copy", "--keys", "--schema",
                "--sim-schema", "--version", "-h, --help"):
        assert opt in p.stdout, opt
    assert _cli("-h").stdout == p.stdout


def test_subcommands_parse_their_own_options(runner, tmp_path):
    p = _cli("merge", tmp_path / "m.h5", "--bogus")
    assert p.returncode == 2
    assert "rps3-run merge: unknown option '--bogus'" in p.stderr
    p = _cli("--clean", tmp_path / "m.h5", "--bogus")
    assert p.returncode == 2 and "unknown option '--bogus'" in p.stderr
    p = _cli("--clean", tmp_path / "m.h5", "--force")
    assert p.returncode == 0, p.stderr


def test_study_and_simstudy_share_the_parser(runner, tmp_path):
    study = os.path.join(os.path.dirname(RUNNER), "rps3-study")
    sim = os.path.join(os.path.dirname(RUNNER), "rps3-simstudy")
    out = tmp_path / "ws.h5"
    p = subprocess.run([study, "--quick", f"--output={out}", "workspace"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert out.exists()
    p = subprocess.run([study, "accuracy", f"-o{out}", "--samples=9"],
                       capture_output=True, text=True, timeout=60)
    assert p.returncode == 2
    assert "--samples needs a whole number 10-1000000, got '9'" in p.stderr
    for prog in (study, sim):
        p = subprocess.run([prog, "-o"], capture_output=True, text=True)
        assert p.returncode == 2 and "-o needs a value" in p.stderr
        p = subprocess.run([prog, "--bogus"], capture_output=True, text=True)
        assert p.returncode == 2 and "unknown option '--bogus'" in p.stderr
        p = subprocess.run([prog, "--help"], capture_output=True, text=True)
        assert p.returncode == 0 and "-o, --output OUT.h5" in p.stdout
