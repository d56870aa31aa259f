"""rps3-run on scenes with a `simulate:` section (runner/exec/simulate.c): each
case simulated by rps3_sim under its controller, into a file of its own
schema (docs/runner.md "Simulation").

The oracles are other routes to the same numbers: the applied forces of
the file replayed open loop through rps3_sim by tests/sim_shim.c (the same
integrator and steps: the motion must come back to rounding); the
reference motion against rps3-run's inverse-dynamics run of the same scene
without the section; the closed-loop tracking errors against
rps3-simstudy's table in docs/simulation.md (a separate program over the
library); physics for the gain sweeps; and the energy balance in the file.
"""

import ctypes
import os
import re
import subprocess
import sys

import h5py
import numpy as np
import pytest

import oracle
from conftest import ANALYSIS, run, write_scene

RPS3_EREACH = 1

PLANT = dict(R=0.2286, rho=0.5, M=0.18, m_over_M=0.5, d=0.1524,
             g=9.80665)
HEAD = """\
manipulator:
  R: 0.2286
  rho: 0.5
  M: 0.18
  m_over_M: 0.5
  d: 0.1524
  pin_friction: {viscous: 0.0137, coulomb: 0.0029, vreg: 0.001}
trajectory:
  kind: sine
  mean: [0.31, 0.21, 0.30]
  amp: [1.03, 0.083, 0.029]
  freq: [1.07, 2.03, 3.01]
  phase: [0, 0.4, 0]
  duration: 0.5
  dt: 0.001
"""


@pytest.fixture(scope="module")
def shim(tmp_path_factory):
    return oracle.build_sim_shim(tmp_path_factory.mktemp("simshim"))


def simulate(tmp_path, text, name="s", *args):
    scene = write_scene(tmp_path / f"{name}.yaml", text)
    out = tmp_path / f"{name}.h5"
    proc = run(scene, out, "-q", *args)
    return out, proc


def test_case_equals_open_loop_replay_through_rps3_sim(runner, shim,
                                                        tmp_path):
    """PD + gravity at 1 kHz on a fast sine with friction: the applied
    forces of the file, fed back open loop through rps3_sim (the same
    integrator and steps), give back the file's motion and energies."""
    h5, proc = simulate(tmp_path, HEAD + "simulate: {controller: "
                        "pd_gravity, rate: 1000, h: 0.001}\n")
    assert proc.returncode == 0, proc.stderr
    with h5py.File(h5, "r") as f:
        t = f["time"][()]
        l = f["length"][0]
        F = f["force"][0]
        T, P = f["kinetic_energy"][0], f["potential_energy"][0]
        W = f["work_actuators"][0] + f["work_friction"][0]
        pose0 = [f["alpha"][0, 0], f["beta"][0, 0], f["z_c"][0, 0]]
        resid = f["energy_residual"][0]
        assert f["status"][0] == 0 and f["failed_at"][0] == -1
        assert f["nticks"][0] == len(t) - 1
    n = len(t) - 1
    assert np.isnan(F[0]).all() and np.isfinite(F[1:]).all()
    # the trajectory's rates at t = 0 (the sine's derivative)
    amp = np.array([1.03, 0.083, 0.029])
    freq = np.array([1.07, 2.03, 3.01])
    phase = np.array([0, 0.4, 0])
    dpose0 = amp * 2 * np.pi * freq * np.cos(phase)
    p = np.array([PLANT["R"], PLANT["rho"], PLANT["M"], 0.09, PLANT["d"], 0,
                  PLANT["g"], 0, 0, 0, 0, 0, 0, 0, 0.0137, 0.0029, 0, 0,
                  0.001])  # shim_model.h's order, then vreg
    effects = 0b101111  # the paper's four and pin friction
    lr = np.zeros((n + 1, 3))
    Tr, Pr, Wr = (np.zeros(n + 1) for _ in range(3))
    err = ctypes.create_string_buffer(256)
    rc = shim.rps3_shim_sim(p, effects, 0, 1e-3, 1e-9,
                            np.array(pose0), dpose0, n, 1e-3,
                            np.ascontiguousarray(F[1:]), lr, Tr, Pr, Wr,
                            err, 256)
    assert rc == 0, err.value
    # the same arithmetic but for the controller: rounding, amplified by
    # 0.5 s of an open-loop unstable plant (~1e3): 1e-12 m is far below
    # a wrong force (1e-2 N moves a link by ~1e-4 m here)
    assert np.abs(l - lr).max() <= 1e-12
    assert np.abs(T - Tr).max() <= 1e-12
    assert np.abs(P - Pr).max() <= 1e-12
    assert np.abs(W - Wr).max() <= 1e-12
    # the energy balance of the file itself (rk4 at 1 ms: 1e-8 J of a
    # scale of ~1 J, docs/simulation.md)
    assert np.abs(T + P - T[0] - P[0] - W - resid).max() <= 1e-14
    assert np.abs(resid).max() <= 1e-8


def test_reference_is_the_inverse_dynamics_run(runner, tmp_path):
    """length_ref, the reference pose and the open-loop feedforward equal
    rps3-run's inverse dynamics of the same scene, a separate route."""
    text = HEAD.replace("dt: 0.001", "dt: 0.01")
    inv, proc = simulate(tmp_path, text, "inv")
    assert proc.returncode == 0, proc.stderr
    sim, proc = simulate(tmp_path, text + "simulate: {controller: open_loop,"
                         " rate: 100}\n", "sim")
    assert proc.returncode in (0, 1), proc.stderr
    with h5py.File(inv, "r") as a, h5py.File(sim, "r") as b:
        assert np.array_equal(a["time"][()], b["time"][()])
        k = b["failed_at"][0] if b["failed_at"][0] >= 0 else len(a["time"])
        assert np.abs(a["length"][0] - b["length_ref"][0]).max() <= 1e-15
        assert np.abs(a["length_rate"][0]
                      - b["length_rate_ref"][0]).max() <= 1e-14
        for name in ("alpha", "beta", "z_c", "x_c", "y_c"):
            assert np.abs(a[name][0] - b[name + "_ref"][0]).max() <= 1e-15
        # open loop at 100 Hz: the force over (t_k-1, t_k] is the inverse
        # dynamics at t_k-1 (forces_only: equal to ~1e-15 of the scale)
        F = a["force"][0][: k - 1]
        assert np.abs(b["force"][0][1:k] - F).max() <= 1e-12 * np.abs(F).max()
        # the sample 0 is on the trajectory
        assert np.abs(b["tracking_error"][0][0]).max() == 0


def test_closed_loop_config_agrees_with_simstudy(config_runs):
    """configs/closed_loop.yaml gives rps3-simstudy's tracking table
    (docs/simulation.md: helix rows, sampled there at 1 ms, here 10 ms)."""
    h5, proc = config_runs["closed_loop"]
    assert proc.returncode == 0, proc.stderr
    table = {("pd", 0.5): 3.6e-4, ("pd", 0.0): 3.6e-4,
             ("pd_gravity", 0.5): 6.9e-8, ("pd_gravity", 0.0): 3.7e-5,
             ("computed_torque", 0.5): 5.7e-7,
             ("computed_torque", 0.0): 3.4e-3}
    with h5py.File(h5, "r") as f:
        assert (f["status"][()] == 0).all()
        for kind, mm, e in zip(f["simulate__controller"][()].astype(str),
                               f["simulate__model__m_over_M"][()],
                               f["tracking_error_max"][()]):
            # the table's two digits
            assert e == pytest.approx(table[(kind, mm)], rel=0.05), (kind, mm)


def test_gain_and_model_sweeps_are_monotone(runner, tmp_path):
    """PD on the plant's weight: the error is the weight over the gain
    (e ~ G / kp), so doubling kp halves it; PD + gravity whose model
    misses link mass: the error grows with the missing mass."""
    h5, proc = simulate(tmp_path, HEAD + "simulate: {controller: pd}\n"
                        "sweep:\n  simulate.kp: [500, 1000, 2000, 4000]\n",
                        "kp")
    assert proc.returncode == 0, proc.stderr
    with h5py.File(h5, "r") as f:
        e = f["tracking_error_max"][()]
        # pd's gain: a force per metre (computed_torque's: 1/s^2)
        assert f["simulate__kp"].attrs["units"] == "N/m"
    assert (np.diff(e) < 0).all(), e
    assert (e[:-1] / e[1:] > 1.5).all() and (e[:-1] / e[1:] < 2.5).all(), e
    h5, proc = simulate(tmp_path, HEAD + "simulate: {controller: "
                        "pd_gravity}\nsweep:\n  simulate.model.m_over_M: "
                        "[0.5, 0.4, 0.25, 0]\n", "mm")
    assert proc.returncode == 0, proc.stderr
    with h5py.File(h5, "r") as f:
        e = f["tracking_error_max"][()]
    assert (np.diff(e) > 0).all(), e


def test_saturating_controller_ends_cleanly(runner, tmp_path):
    """Actuators at 0.5 N cannot hold the platform (about 1.5 N a link):
    it falls until the theta solve fails; status, failed_at and message
    say so, the samples before are kept and those after are NaN."""
    h5, proc = simulate(tmp_path, HEAD + "simulate: {controller: "
                        "pd_gravity, fmax: 0.5}\n")
    assert proc.returncode == 1, proc.stderr
    with h5py.File(h5, "r") as f:
        st, k = f["status"][0], f["failed_at"][0]
        msg = f["message"][0].decode()
        F, Fc = f["force"][0], f["force_cmd"][0]
        l = f["length"][0]
        assert st > 0 and 0 < k < len(f["time"])
        assert f["failed_time"][0] <= f["time"][k]
        assert f["failed_time"][0] > f["time"][k - 1]
        assert re.match(r"t = [0-9.]+ s \(before sample \d+\): ", msg), msg
        assert np.isfinite(l[:k]).all() and np.isnan(l[k:]).all()
        assert np.nanmax(np.abs(F)) == 0.5
        assert np.nanmax(np.abs(Fc)) > 0.5
        assert f["nsat"][0] > 0
    # stderr names it too, once, as the run's first failure
    assert proc.stderr.count("rps3-run: first failure: case 0: " + msg) == 1


def test_plant_driven_towards_the_base_stops_at_the_stroke(runner, tmp_path):
    """Open loop with a controller that believes the platform weighs
    10 g: too little force, the platform sinks towards the base until a
    link leaves the stroke (l_min): RPS3_EREACH at the time it did."""
    h5, proc = simulate(tmp_path, HEAD + "simulate:\n  controller: "
                        "open_loop\n  l_min: 0.25\n  model: {M: 0.01, "
                        "m_over_M: 0}\n")
    assert proc.returncode == 1, proc.stderr
    with h5py.File(h5, "r") as f:
        assert f["status"][0] == RPS3_EREACH
        k = f["failed_at"][0]
        assert "left the stroke [0.25, inf]" in f["message"][0].decode()
        z = f["z_c"][0][:k]
        assert z[-1] < z[0] - 0.01
        assert np.nanmin(f["length"][0]) >= 0.25


def test_resolved_scene_reruns_bitwise(runner, tmp_path):
    """scene_resolved of a swept case, run alone, gives the same file
    values: every simulate key the case used is in it."""
    h5, proc = simulate(tmp_path, HEAD + "simulate:\n  controller: pd\n"
                        "  noise_l: 1e-6\n  model: {m_over_M: 0.2}\n"
                        "sweep:\n  simulate.kd: [20, 40]\n", "sw")
    assert proc.returncode == 0, proc.stderr
    with h5py.File(h5, "r") as f:
        text = f["scene_resolved"][1].decode()
        l1 = f["length"][1]
    assert "kd: 40" in text and "m_over_M: 0.2" in text
    one, proc = simulate(tmp_path, text, "one")
    assert proc.returncode == 0, proc.stderr
    with h5py.File(one, "r") as f:
        assert np.array_equal(f["length"][0], l1)


def test_file_conventions_and_refusals(runner, tmp_path):
    h5, proc = simulate(tmp_path, HEAD + "simulate: {}\n", "conv")
    assert proc.returncode == 0, proc.stderr
    with h5py.File(h5, "r") as f:
        assert f.attrs["content"] == "simulation"
        for name, ds in f.items():
            assert "units" in ds.attrs, name
            if ds.chunks and ds.dtype.kind != "O":
                assert ds.fletcher32, name
        assert f["length"].dims[0][0].name == "/case"
        assert f["length"].dims[1][0].name == "/time"
    scene = tmp_path / "conv.yaml"
    proc = run(scene, None, "--check")
    assert proc.returncode == 0 and "simulated: 1 case" in proc.stdout
    assert re.search(r"run time about .* on 1 thread \(an estimate: .* s a "
                     r"simulated second, timed on .* simulated s, 400 "
                     r"samples\)", proc.stdout)
    proc = run(scene, tmp_path / "p.h5", "--shard", "0/2")
    assert proc.returncode == 2
    assert "a simulated scene runs as one process" in proc.stderr
    assert not (tmp_path / "p.h5").exists()
    proc = subprocess.run([runner, "merge", str(tmp_path / "m.h5"), str(h5)],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    assert "a simulation file" in proc.stderr and "nothing to merge" in \
        proc.stderr
    assert [p.name for p in tmp_path.iterdir() if ".tmp." in p.name] == []


def test_continuous_open_loop_round_trip(runner, tmp_path):
    """The inverse dynamics fed forward as a continuous force law (rate 0)
    reproduce the trajectory: rk8pd at 1e-10 over a 0.05 s window, where
    the open-loop instability has not yet grown (docs/simulation.md: each
    window within 1e-9 m), with friction in plant and controller."""
    h5, proc = simulate(tmp_path, HEAD + "simulate: {controller: open_loop,"
                        " rate: 0, integrator: rk8pd, tolerance: 1e-10, "
                        "duration: 0.05}\n")
    assert proc.returncode == 0, proc.stderr
    with h5py.File(h5, "r") as f:
        assert len(f["time"]) == 51 and f["time"][-1] == 0.05
        assert f["tracking_error_max"][0] <= 1e-9
        assert f["nticks"][0] == 0
        # with rate 0 the force is that of the last evaluation: finite
        assert np.isfinite(f["force"][0][1:]).all()


def test_noise_and_quantisation_are_seeded(runner, tmp_path):
    text = HEAD + ("simulate: {controller: pd_gravity, noise_l: 2e-6, "
                   "noise_dl: 1e-4, quant_l: 1e-6}\nsweep:\n"
                   "  simulate.seed: [7, 7, 8]\n")
    h5, proc = simulate(tmp_path, text, "noise")
    assert proc.returncode == 0, proc.stderr
    clean, proc = simulate(tmp_path, HEAD + "simulate: {controller: "
                           "pd_gravity}\n", "clean")
    with h5py.File(h5, "r") as f, h5py.File(clean, "r") as g:
        l = f["length"][()]
        assert np.array_equal(l[0], l[1])          # the same seed
        assert np.abs(l[0] - l[2]).max() > 1e-9    # another seed
        assert np.abs(l[0] - g["length"][0]).max() > 1e-9  # noise acts


def test_time_grid_differing_by_case(runner, tmp_path):
    """Durations differ by case: the samples' dimension is `sample`, an
    index (a CF time axis would need one grid), case_time holds
    each case's times, NaN past a case's end (the case is not failed)."""
    h5, proc = simulate(tmp_path, HEAD.replace("dt: 0.001", "dt: 0.01") +
                        "simulate: {controller: pd}\nsweep:\n"
                        "  simulate.duration: [0.2, 0.3]\n", "grid", "--gzip",
                        "4")
    assert proc.returncode == 0, proc.stderr
    with h5py.File(h5, "r") as f:
        assert "time" not in f
        assert f["sample"].attrs["units"] == "1" and len(f["sample"]) == 31
        ct = f["case_time"][()]
        assert np.allclose(ct[1], np.arange(31) * 0.01, rtol=0, atol=1e-15)
        assert ct[0][20] == 0.2 and np.isnan(ct[0][21:]).all()
        assert np.isnan(f["length"][0][21:]).all()
        assert (f["status"][()] == 0).all()
        assert f["length"].compression == "gzip" and f["length"].fletcher32


def test_xarray_dimensions_from_the_sweep(config_runs):
    """The Python package opens a simulation like any sweep: the swept keys
    are dimensions."""
    import rps3
    ds = rps3.open_dataset(str(config_runs["closed_loop"][0]))
    e = ds["tracking_error_max"]
    assert set(e.dims) == {"controller", "m_over_M"}
    assert float(e.sel(controller="computed_torque", m_over_M=0.0)) > \
        100 * float(e.sel(controller="computed_torque", m_over_M=0.5))
    assert ds["length"].dims[-2:] == ("time", "link")


def test_threads_give_the_same_file(runner, tmp_path):
    """-j 2: cases of more than one window (8001 samples), one that fails
    (saturated), written in whatever order the threads finish: the same
    datasets as one thread."""
    text = HEAD.replace("dt: 0.001", "dt: 0.00005") + (
        "simulate: {controller: pd_gravity, duration: 0.4}\nsweep:\n"
        "  simulate.fmax: [0.5, 0, 3]\n  simulate.kp: [1000, 3000]\n")
    one, proc = simulate(tmp_path, text, "one")
    assert proc.returncode == 1, proc.stderr
    two, proc = simulate(tmp_path, text, "two", "-j", "2")
    assert proc.returncode == 1, proc.stderr
    with h5py.File(one, "r") as a, h5py.File(two, "r") as b:
        assert sorted(a) == sorted(b)
        assert a["length"].shape == (6, 8001, 3)
        assert (a["status"][:2] > 0).all() and (a["status"][2:] == 0).all()
        for name in a:
            x, y = np.asarray(a[name][()]), np.asarray(b[name][()])
            if x.dtype.kind == "f":
                assert np.array_equal(x, y, equal_nan=True), name
            else:
                assert np.array_equal(x, y), name


OFFSET = """\
manipulator: {R: 0.2286, rho: 0.5, M: 0.18, m_over_M: 0.5, d: 0.1524}
trajectory: {kind: helix, radius: 0.000266, pitch: 0.03048, z0: 0.3048,
             period: 10, blend: 1, dt: 0.001}
simulate: {controller: computed_torque, kp: 400, kd: 40, duration: 0.5,
           start_offset: [0, 0, 0.002], rate: RATE, h: STEP}
"""


def test_computed_torque_error_decays_as_its_closed_form(runner, tmp_path):
    """Started 2 mm above the helix, computed torque with the exact model
    makes each link error obey e'' + kd e' + kp e = 0: with kp = 400 1/s^2,
    kd = 40 1/s (critically damped, w = 20 rad/s) e(t) = (e0 + (de0 +
    w e0) t) exp(-w t).  The control rate's zero-order hold delays the law
    by half a period: the deviation is first order in it (measured 3.8e-3
    e0 at 1 kHz, 3.8e-4 at 10 kHz)."""
    dev = {}
    for rate, step in ((1000, 1e-3), (10000, 1e-4)):
        h5, proc = simulate(tmp_path, OFFSET.replace("RATE", str(rate))
                            .replace("STEP", str(step)), f"r{rate}")
        assert proc.returncode == 0, proc.stderr
        with h5py.File(h5, "r") as f:
            t = f["time"][()][:, None]
            e = f["tracking_error"][0]
            de0 = f["length_rate_ref"][0, 0] - f["length_rate"][0, 0]
        e0, w = e[0], 20.0
        assert (np.abs(e0) > 1.8e-3).all()   # the offset is an error
        closed = (e0 + (de0 + w * e0) * t) * np.exp(-w * t)
        dev[rate] = np.abs(e - closed).max() / np.abs(e0).max()
    assert dev[1000] <= 5e-3 and dev[10000] <= 5e-4, dev
    assert 8 < dev[1000] / dev[10000] < 12, dev


def test_unreachable_start_fails_at_the_first_sample(runner, tmp_path):
    h5, proc = simulate(tmp_path, OFFSET.replace("RATE", "1000")
                        .replace("STEP", "0.001")
                        .replace("[0, 0, 0.002]", "[0, 0, -0.5]"), "down")
    assert proc.returncode == 1, proc.stderr
    with h5py.File(h5, "r") as f:
        assert f["status"][0] == RPS3_EREACH and f["failed_at"][0] == 0
        assert f["failed_time"][0] == 0
        assert np.isnan(f["length"][0]).all()
        assert f["message"][0].decode().startswith("t = 0 s (before sample 0)")


def test_closed_loop_figure_and_table(config_runs, tmp_path):
    """analysis/closed_loop.py draws any simulated scene's file: a PNG and
    one table row per case with its swept values."""
    h5 = config_runs["closed_loop"][0]
    png = tmp_path / "cl.png"
    proc = subprocess.run([sys.executable, os.path.join(ANALYSIS,
                                                        "closed_loop.py"),
                           str(h5), str(png)], capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rows = proc.stdout.strip().splitlines()
    assert len(rows) == 2 + 6
    assert rows[-1].startswith("| computed_torque | 0.0 | ok | 0.00338 |")


@pytest.mark.parametrize("threads", ["1", "2"])
def test_file_size_limit_exits_3_and_leaves_nothing(runner, tmp_path,
                                                    threads):
    """ulimit -f 1 MiB under a 4 MB simulation: the write fails with
    EFBIG, exit 3, no file and no temporary."""
    import resource

    def limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (1 << 20, 1 << 20))
    scene = write_scene(tmp_path / "big.yaml", HEAD + "simulate: "
                        "{controller: pd, duration: 0.5}\nsweep:\n"
                        "  simulate.kp: {from: 1000, to: 2000, num: 10}\n")
    proc = run(scene, tmp_path / "x.h5", "-q", "-j", threads,
               preexec_fn=limit)
    assert proc.returncode == 3, proc.stderr
    assert "file too large" in proc.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["big.yaml"]


def test_a_signal_removes_the_temporary(runner, tmp_path):
    """SIGTERM during a long simulation: the process dies of it and its
    temporary file is gone."""
    import signal
    import time

    from conftest import run_tmp
    scene = write_scene(tmp_path / "long.yaml", HEAD.replace(
        "duration: 0.5", "duration: 500") + "simulate: {controller: pd}\n")
    out = tmp_path / "out.h5"
    p = subprocess.Popen([runner, str(scene), "-o", str(out), "-q"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    tmp = run_tmp(out, p.pid)
    deadline = time.time() + 20
    while not tmp.exists() and time.time() < deadline:
        time.sleep(0.005)
    assert tmp.exists()
    p.send_signal(signal.SIGTERM)
    p.wait(timeout=30)
    assert p.returncode == -signal.SIGTERM
    assert sorted(x.name for x in tmp_path.iterdir()) == ["long.yaml"]


def test_check_estimate_is_bounded_whatever_the_rate(runner, tmp_path):
    """--check times a pilot within a fixed budget of control periods and
    CPU time and extrapolates by simulated time: at 100 kHz over 100 s
    (1e7 control periods, minutes of run) it answers in seconds; a typo
    such as rate 1e9 is refused (exit 2) before any simulation."""
    import time

    def check(duration, rate):
        scene = write_scene(
            tmp_path / f"r{rate:g}_{duration:g}.yaml",
            HEAD.replace("duration: 0.5", "duration: 0.5\n  dt: 0.1")
                .replace("  dt: 0.001\n", "")
            + f"simulate:\n  rate: {rate}\n  duration: {duration}\n")
        t0 = time.monotonic()
        proc = run(scene, None, "--check", timeout=60)
        return proc, time.monotonic() - t0

    proc, wall = check(100.0, 1e5)
    assert proc.returncode == 0, proc.stderr
    assert wall < 15, wall
    m = re.search(r"an estimate: ([0-9.e+-]+) s a simulated second, timed "
                  r"on ([0-9.e+-]+) simulated s", proc.stdout)
    assert m, proc.stdout
    # the pilot covers at most its budget of 20000 periods: 0.2 s here
    assert float(m.group(2)) <= 0.2 + 1e-9
    proc, wall = check(1e3, 1e9)
    assert proc.returncode == 2
    assert "simulate.rate: rate = 1e+09" in proc.stderr
    assert wall < 15
