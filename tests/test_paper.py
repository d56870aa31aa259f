"""The configs, the paper's figures and checks, and physics the files must
obey whatever the scene: energy balance, the sum of the effects, symmetry,
two formulations agreeing."""

import math
import os
import re
import subprocess
import sys

import h5py
import numpy as np
import pytest

from rps3 import h5io
from conftest import ANALYSIS, CONFIGS, STUDY_CONFIGS, script

check_paper = script("check_paper")
figures = script("figures")

# configs with a simulate section write a simulation (test_sim_runner.py);
# a study's config is run by its make target
CONFIG_NAMES = sorted(
    f[:-5] for f in os.listdir(CONFIGS) if f.endswith(".yaml")
    and f not in STUDY_CONFIGS
    and not re.search(r"^simulate:", open(os.path.join(CONFIGS, f)).read(),
                      re.M))


def test_the_configs_exist():
    for name in ("paper", "mass_ratio", "rho", "pitch", "grid", "period"):
        assert name in CONFIG_NAMES


@pytest.mark.parametrize("name", CONFIG_NAMES)
def test_config_runs_clean(config_runs, name):
    h5, proc = config_runs[name]
    assert proc.returncode == 0, proc.stderr
    with h5py.File(h5, "r") as f:
        if f.attrs.get("content") == "identification":
            # one fit, no cases: the noise-free forces of the scene's model
            # give its parameters back, to 1e-9 of each or, for a truth of
            # zero (a general body's product of inertia), of the largest
            # parameter in the same unit
            theta, truth = f["theta"][()], f["truth"][()]
            units = np.array([u.decode() if isinstance(u, bytes) else u
                              for u in f["parameter_units"][()]])
            scale = np.array([np.abs(truth[units == u]).max() for u in units])
            err = np.abs(theta - truth)
            assert np.all(err <= 1e-9 * np.maximum(np.abs(truth), scale)), \
                dict(zip(units, err))
            return
        assert not h5io.failed(f)
        if f.attrs.get("content") == "design":
            check_design_file(f)
            return
        force = f["force"][()]
        assert np.isfinite(force).all()
        # energy: actuator power = d(T + P)/dt, up to rounding
        res = np.abs(f["energy_residual"][()])
        scale = np.nanmax(f["energy_scale"][()], axis=1)
        assert (res.max(axis=1) <= 1e-12 * scale).all()
        # the shares of the effects sum to the force
        err = np.abs(f["force_by_effect"][()].sum(axis=2) - force).max()
        assert err <= 1e-12 * np.abs(force).max()


def check_design_file(f):
    """A design study's file: every design evaluated, its summaries finite
    and in range, the task's forces finite wherever the task was done."""
    assert (f["status"][()] == 0).all()
    vol, frac = f["volume"][()], f["reach_fraction"][()]
    assert np.isfinite(vol).all() and (vol >= 0).all()
    assert ((frac >= 0) & (frac <= 1)).all() and (f["nreach"][()] > 0).any()
    gti = f["gti"][()]
    assert ((gti >= 0) & (gti <= 1)).all()
    ok = f["task_status"][()] == 0
    assert ok.any()
    assert np.isfinite(f["task_F_peak"][()][ok]).all()


def test_figures_are_written(paper_h5, tmp_path):
    proc = subprocess.run([sys.executable, os.path.join(ANALYSIS, "figures.py"),
                           str(paper_h5), str(tmp_path)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    for n in (2, 3, 4):
        png = tmp_path / f"fig{n}.png"
        data = png.read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n"
        assert len(data) > 20000, png


def test_check_paper_passes(paper_h5, config_runs):
    link_mass = config_runs["link_mass"][0]
    proc = subprocess.run([sys.executable,
                           os.path.join(ANALYSIS, "check_paper.py"),
                           str(paper_h5), "--sweep", str(link_mass)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert proc.stdout.rstrip().endswith(" passed, 0 failed")
    assert "paper, section VI              20.00 %" in proc.stdout


def test_check_paper_fails_on_a_wrong_force(paper_h5, tmp_path):
    """The checks can fail: a copy with one force nudged by 1e-9 N."""
    bad = tmp_path / "bad.h5"
    bad.write_bytes(paper_h5.read_bytes())
    with h5py.File(bad, "r+") as f:
        f["force"][1, 500, 0] += 1e-9
    proc = subprocess.run([sys.executable,
                           os.path.join(ANALYSIS, "check_paper.py"), str(bad)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 1
    assert "FAIL: case 1: effects sum to the force" in proc.stdout
    assert "FAIL: the increase is the links' shares" in proc.stdout


def test_link_mass_increase_closed_form(paper_h5):
    """The increase is the links' weight: averaged over the three links, its
    share of F(m = 0) at every sample is the level-platform statics
    3 (m/M) (d/l_i) cos^2 theta_i up to the second order in the tilt
    beta = 5.5 deg (the first order cancels over the three links)."""
    with h5py.File(paper_h5, "r") as f:
        c0 = h5io.case_where(f, manipulator__m_over_M=0.0)
        c1 = h5io.case_where(f, manipulator__m_over_M=0.5)
        f0, f1 = f["force"][c0], f["force"][c1]
        inc = check_paper.increase(f0, f1)
        sc = check_paper.scene_of(f, c1)
        l, th = f["length"][c1], f["theta"][c1]
        level = 3 * 0.5 * sc["manipulator"]["d"] / l * np.cos(th) ** 2
        beta = f["beta"][c1, 0]
    ratio = (f1 / f0 - 1).mean(axis=1)
    assert np.abs(ratio - level.mean(axis=1)).max() <= beta**2 * level.max()
    assert 0.07 < inc["rms"] < 0.09 and 0.10 < inc["peak"] < 0.13


def test_three_forces_are_exact_copies_on_a_level_circle(config_runs):
    """pitch = 0: z_c is constant, and by the 3-fold symmetry
    F_i(t + 6 s) = F_{i+1}(t) exactly on the constant-rate segment."""
    h5 = config_runs["pitch"][0]
    with h5py.File(h5, "r") as f:
        case = h5io.case_where(f, trajectory__pitch=0.0)
        force = f["force"][case]
        t = h5io.times(f)[case]
    n = int(round(6.0 / (t[1] - t[0])))
    # t_b = 9 s itself takes the decelerating segment's acceleration
    seg = np.flatnonzero((t >= 1.0) & (t + 6.0 < 9.0))
    for i in range(3):
        np.testing.assert_allclose(force[seg + n, i], force[seg, (i + 1) % 3],
                                   rtol=1e-12, atol=0)


def test_lagrange_and_newton_euler_agree(config_runs):
    with h5py.File(config_runs["sine"][0], "r") as f:
        force = f["force"][()]
        fe = f["force_by_effect"][()]
    scale = np.abs(force).max()
    assert np.abs(force[0] - force[1]).max() <= 1e-12 * scale
    assert np.abs(fe[0] - fe[1]).max() <= 1e-12 * scale


def test_inertia_grows_as_one_over_period_squared(config_runs):
    """Every inertial term is an acceleration or a squared rate: for the same
    motion in T* seconds it scales as 1/T*^2 (blend_ratio keeps the shape)."""
    with h5py.File(config_runs["period"][0], "r") as f:
        T = h5io.sweep_value(f, "trajectory.period")
        t = h5io.times(f)
        iner = h5io.effect_sum(f, h5io.INERTIA_EFFECTS)
        grav = h5io.effect_sum(f, h5io.GRAVITY_EFFECTS)
    # the acceleration jumps at the blend corners t_a, t_b: a sample on a
    # corner takes one side or the other with the rounding of t, so skip it
    u = t / T[:, None]
    away = ((np.abs(u - 0.1) > 1e-9) & (np.abs(u - 0.9) > 1e-9)).all(axis=0)
    assert away.sum() == len(away) - 2
    for c in range(1, len(T)):
        np.testing.assert_allclose(iner[c][away] * T[c] ** 2,
                                   iner[0][away] * T[0] ** 2,
                                   rtol=1e-9, atol=1e-15)
        # the same poses, up to the rounding of t_k = k T*/(n - 1)
        np.testing.assert_allclose(grav[c], grav[0], rtol=1e-12, atol=0)


def test_helix_pose_function_matches_table_one():
    """The analysis' own Table I helper: phi(0) = 0, phi(T*) = 2 pi and a
    peak rate of 2 pi/9 rad/s for Table II."""
    tr = {"period": 10.0, "blend": 1.0}
    t = np.array([0.0, 1.0, 9.0, 10.0])
    alpha, phi = check_paper.helix_pose(tr, t)
    np.testing.assert_allclose(phi, [0, math.pi / 9, 2 * math.pi - math.pi / 9,
                                     2 * math.pi], rtol=1e-15, atol=1e-15)
    assert alpha[0] == pytest.approx(math.pi / 2)


def test_figures_module_finds_the_paper_cases(paper_h5):
    with h5py.File(paper_h5, "r") as f:
        assert figures.paper_cases(f) == (0, 1)


def test_summary_figure(config_runs, tmp_path):
    names = ["mass_ratio", "rho", "pitch", "grid", "period", "link_mass", "sine"]
    out = tmp_path / "summary.png"
    proc = subprocess.run([sys.executable, os.path.join(ANALYSIS, "summary.py"),
                           str(out)] + [str(config_runs[n][0]) for n in names],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 50000
