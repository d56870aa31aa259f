"""Identification through rps3-run (docs/identification.md, "Through the
runner"): a scene's identify section fits the paper model's parameters to
the inverse dynamics along its trajectory, or to a measured table; its
Monte Carlo of force noise runs on the runner's threads and shards, and
merges like a sweep.  The oracles: the model's parameters from Python's
own rps3.ident_paper.paper_parameters, Python's rps3.ident_io.fit of the
same table, and the draws' summary recomputed here from the draws."""

import hashlib
import os
import subprocess

import h5py
import numpy as np
import pytest
from conftest import RUNNER, run, write_scene
from test_cf import offline  # noqa: F401
from test_scale import assert_same_content

pytest.importorskip("scipy")
from rps3 import ident_io, ident_paper, ident_sim  # noqa: E402
from scipy import stats  # noqa: E402

#: noise-free forces: the fit returns the scene's parameters to rounding of
#: the regressor (1e-13 of a column) through a condition number of ~10
TOL_TRUTH = 1e-9
#: the same table, the same library calls in C and Python (rps3_regressor
#: vs the effects' inverse dynamics): estimates to rounding
TOL_PYTHON = 1e-9
#: the Monte Carlo's coverage band: the two-sided 99.9 % binomial band of
#: N draws around 95 % (a correct interval fails it once in 1000 runs)
BAND = 0.999

MANIP = """\
manipulator:
  R: 0.2286
  rho: 0.5
  M: 0.18
  m: 0.09
  d: 0.1524
  link_Ic: 0.0002
  pin_friction: {viscous: 0.002, coulomb: 0.001, vreg: 0.05}
"""

SINE = """\
trajectory:
  kind: sine
  mean: [0.0, 0.08, 0.30]
  amp: [1.0, 0.05, 0.03]
  freq: [0.5, 1.0, 2.0]
  phase: [0.0, 0.0, 1.5708]
  duration: 2.0
  dt: 0.002
"""

PARAMS = ["M", "md", "Ipin", "pin.fv", "pin.fc"]


def scene(tmp_path, identify, name="s.yaml", traj=SINE, manip=MANIP):
    return write_scene(tmp_path / name, manip + traj + "identify:\n" + identify)


def names(f):
    return [n.decode() for n in f["parameter"][()]]


def truth_oracle():
    """The scene's parameters by Python's paper_parameters (M, m, d,
    link_Ic, friction), in the order of PARAMS."""
    th = ident_paper.paper_parameters(M=0.18, m=0.09, d=0.1524, link_Ic=2e-4,
                                      friction={"viscous": 0.002, "coulomb": 0.001})
    return dict(zip(ident_paper.PaperSet().names, th))


# --------------------------------------------------------------- the fit

def test_noise_free_fit_recovers_the_scene(tmp_path):
    """Forces of the inverse dynamics along an exciting sine: the fit is the
    scene's parameters (Python's paper_parameters of its manipulator), the
    consistent fit too; every dataset has units, the file is CF's."""
    s = scene(tmp_path, f"  parameters: [{', '.join(PARAMS)}]\n  consistent: true\n")
    out = tmp_path / "fit.h5"
    proc = run(s, out, "-q")
    assert proc.returncode == 0, proc.stderr
    ref = truth_oracle()
    with h5py.File(out, "r") as f:
        assert names(f) == PARAMS
        want = np.array([ref[n] for n in PARAMS])
        np.testing.assert_allclose(f["truth"][()], want, rtol=1e-14)
        np.testing.assert_allclose(f["theta"][()], want, rtol=TOL_TRUTH)
        np.testing.assert_allclose(f["consistent_theta"][()], want, rtol=1e-6)
        assert f["consistent"][()] == 1 and f["rank"][()] == 5
        assert f["residual_rms"][()] < 1e-12 * f["force_rms"][()].max()
        assert f.attrs["Conventions"] == "CF-1.10"
        assert f.attrs["content"] == "identification"
        assert "scene" in f and f.attrs["method"] == "wls"
        units = [u.decode() for u in f["parameter_units"][()]]
        assert units == ["kg", "kg m", "kg m^2", "N m s/rad", "N m"]
        for n, u in zip(PARAMS, units):
            assert f["parameters"][n].attrs["units"] == u
            assert f["parameters"][n][()] == pytest.approx(ref[n], rel=TOL_TRUTH)

        def has_units(name, obj):
            if isinstance(obj, h5py.Dataset):
                assert "units" in obj.attrs, name
        f.visititems(has_units)


def test_default_parameters_follow_the_effects(tmp_path):
    """No parameters key: those the effects fill (the paper's four effects:
    M, md, Ipin; pin friction adds pin.fv, pin.fc)."""
    no_fric = MANIP.replace("  pin_friction: {viscous: 0.002, coulomb: 0.001, vreg: 0.05}\n", "")
    for manip, want in ((no_fric, PARAMS[:3]), (MANIP, PARAMS)):
        s = scene(tmp_path, "  method: ols\n", manip=manip)
        out = tmp_path / "d.h5"
        proc = run(s, out, "-q")
        assert proc.returncode == 0, proc.stderr
        with h5py.File(out, "r") as f:
            assert names(f) == want
            assert f.attrs["method"] == "ols"


def monte_carlo(tmp_path, runs, name="mc.yaml", extra=""):
    """runs draws along the sine sampled at 1 kHz (2001 samples: Ipin, 1.6 %
    of the RMS force, is then found to better than 1 %); extra: more keys
    of the identify section."""
    return scene(tmp_path, f"""\
  parameters: [{', '.join(PARAMS)}]
{extra}  monte_carlo: {{runs: {runs}, force_noise: 0.01, seed: 11}}
""", name=name, traj=SINE.replace("dt: 0.002", "dt: 0.001"))


def test_monte_carlo_recovers_counted_parameters(tmp_path):
    """200 draws of 1 % force noise: the parameters with >= 1 % of the RMS
    force have a median error <= 1 % and their 95 % intervals hold the truth
    within the binomial band; the file's summary is the draws' (recomputed
    here), the draws' noise the one asked for."""
    runs = 200
    out = tmp_path / "mc.h5"
    proc = run(monte_carlo(tmp_path, runs), out)
    assert proc.returncode == 0, proc.stderr
    assert "identification Monte Carlo: 200 of 200 draws fitted" in proc.stdout
    lo, hi = (stats.binom.ppf(q, runs, 0.95) / runs for q in ((1 - BAND) / 2, (1 + BAND) / 2))
    with h5py.File(out, "r") as f:
        th, ci, truth = f["mc_theta"][()], f["mc_ci"][()], f["truth"][()]
        assert (f["status"][()] == 0).all()
        err = np.abs(th - truth) / np.abs(truth)
        np.testing.assert_allclose(f["mc_median_rel_error"][()], np.median(err, axis=0),
                                   rtol=1e-12)
        cover = np.mean((ci[..., 0] <= truth) & (truth <= ci[..., 1]), axis=0)
        np.testing.assert_array_equal(f["mc_coverage"][()], cover)
        counted = f["share"][()] >= 0.01
        np.testing.assert_array_equal(f["mc_counted"][()], counted.astype(np.int32))
        assert counted.sum() == 3                       # M, md, Ipin
        assert (np.median(err, axis=0)[counted] <= 0.01).all()
        assert ((lo <= cover[counted]) & (cover[counted] <= hi)).all(), (cover, lo, hi)
        # each draw's residual noise is force_noise of its actuator's RMS force
        sig = f["mc_sigma"][()].mean(axis=0) / f["force_rms"][()]
        np.testing.assert_allclose(sig, 0.01, rtol=0.02)


def test_threads_and_shards_give_the_file_of_one_run(tmp_path):
    """-j 2, and 3 shards joined or copied by merge: every dataset equal,
    bit for bit, to a single-threaded run's (the summary computed by the
    merge); a part alone has no summary.  The draws run the consistent fit
    and predict the held-out samples (their datasets merge as the rest)."""
    s = monte_carlo(tmp_path, 60, extra="  consistent: true\n")
    one, two = tmp_path / "one.h5", tmp_path / "two.h5"
    assert run(s, one, "-q", "-j", "1").returncode == 0
    assert run(s, two, "-q", "-j", "2").returncode == 0
    assert_same_content(one, two)
    parts = []
    for k in range(3):
        part = tmp_path / f"part{k}.h5"
        proc = run(s, part, "-q", "--shard", f"{k}/3")
        assert proc.returncode == 0, proc.stderr
        with h5py.File(part, "r") as f:
            st = f["status"][()]
            assert (st == -1000).any() and (st == 0).any()
            assert np.isnan(f["mc_coverage"][()]).all()
            assert np.isnan(f["mc_holdout_ratio_max"][()])
            assert ((f["mc_consistent_status"][()] == -1000) == (st == -1000)).all()
        parts.append(str(part))
    for extra in ([], ["--copy"]):
        out = tmp_path / f"merged{len(extra)}.h5"
        proc = subprocess.run([RUNNER, "merge", str(out), *parts[::-1], *extra],
                              capture_output=True, text=True, timeout=120)
        assert proc.returncode == 0, proc.stderr
        assert "identification Monte Carlo: 60 of 60" in proc.stdout
        assert "consistent fit: 60 of 60 draws (100.0 %)" in proc.stdout
        assert_same_content(one, out)
    # the draws are few: more shards than work units are refused
    proc = run(s, tmp_path / "p.h5", "--shard", "0/9")
    assert proc.returncode == 2 and "at most 8 shards" in proc.stderr
    # a part already complete is kept by --resume; --check writes nothing
    proc = run(s, parts[1], "--shard", "1/3", "--resume")
    assert proc.returncode == 0 and "not run again" in proc.stderr
    proc = run(s, None, "--check")
    assert proc.returncode == 0, proc.stderr
    assert "2001 samples, 5 parameters, 60 Monte Carlo draws in 8 work units" in proc.stdout


# ------------------------------------------------------------ measured data

@pytest.fixture(scope="module")
def measured(tmp_path_factory):
    """A simulated run of an exciting Fourier series with 1 % force noise,
    written by Python as CSV and HDF5 (with the rates and accelerations)."""
    geo = ident_paper.Geometry()
    rng = np.random.default_rng(1)
    fo = ident_paper.scale_to(ident_paper.Fourier(np.array([0.0, 0.25, 0.31]),
                                                  rng.normal(size=(3, 5)),
                                                  rng.normal(size=(3, 5)), 0.2),
                              (0.8, 0.1, 0.02))
    truth = {"M": 0.18, "m": 0.09, "link_Ic": 2e-4,
             "friction": {"viscous": 0.02, "coulomb": 0.01}}
    s = ident_sim.simulate(fo, truth, periods=1, geometry=geo)
    F = s.F + rng.normal(size=s.F.shape) * 0.01 * np.sqrt(np.mean(s.F**2, axis=0))
    d = tmp_path_factory.mktemp("measured")
    for suffix in (".csv", ".h5"):
        ident_io.save_data(str(d / f"meas{suffix}"), s.t, s.l, F, dl=s.dl, ddl=s.ddl)
    return d


DATA_MANIP = """\
manipulator:
  R: 0.2286
  rho: 0.5
  M: 0.18
  m: 0.09
  d: 0.1524
  link_Ic: 0.0002
  pin_friction: {viscous: 0.02, coulomb: 0.01}
"""


@pytest.mark.parametrize("suffix", [".csv", ".h5"])
def test_measured_table_fit_is_pythons(measured, suffix):
    """identify.data: the estimates of Python's rps3.ident_io.fit of the
    same file (both with the measured rates and accelerations, OLS)."""
    s = write_scene(measured / f"m{suffix}.yaml",
                    DATA_MANIP + f"identify:\n  data: meas{suffix}\n  method: ols\n")
    out = measured / f"fit{suffix}.h5"
    proc = run(s, out, "-q")
    assert proc.returncode == 0, proc.stderr
    ref = ident_io.fit(ident_io.load(measured / f"meas{suffix}"), method="ols")
    with h5py.File(out, "r") as f:
        assert tuple(names(f)) == ref.estimate.names
        np.testing.assert_allclose(f["theta"][()], ref.estimate.theta, rtol=TOL_PYTHON)
        np.testing.assert_allclose(f["std"][()], ref.estimate.std, rtol=1e-6)
        rec = f.attrs["input_files"]
    digest = hashlib.sha256((measured / f"meas{suffix}").read_bytes()).hexdigest()
    assert rec.startswith(f"identify.data sha256:{digest} "), rec


# --------------------------------------------------------------- bad input

def refused(s, tmp_path, *words):
    """rps3-run refuses s: exit 2, each word in the message, no output and
    no temporary file left."""
    out = tmp_path / "bad.h5"
    proc = run(s, out, "-q")
    assert proc.returncode == 2, proc.stderr
    for w in words:
        assert w in proc.stderr, (w, proc.stderr)
    assert not out.exists()
    assert not [p for p in os.listdir(tmp_path) if p.startswith("bad.h5")]
    return proc.stderr


def test_unknown_key_and_parameter_get_hints(tmp_path):
    refused(scene(tmp_path, "  metod: ols\n"), tmp_path, "s.yaml:", "identify.metod",
            "did you mean identify.method")
    refused(scene(tmp_path, "  parameters: [M, Ipn]\n"), tmp_path, "s.yaml:",
            "unknown parameter 'Ipn'", "did you mean Ipin")
    refused(scene(tmp_path, "  parameters: [M, payload.m]\n"), tmp_path,
            "identify.parameters", "'payload.m'", "leave its column at zero")
    refused(scene(tmp_path, "  monte_carlo: {runs: -3}\n"), tmp_path,
            "identify.monte_carlo.runs")


def test_not_exciting_data_are_refused(tmp_path):
    """A constant pose: no acceleration, no rate: Ipin and the friction
    are not determined; the message names them and the condition number."""
    still = SINE.replace("amp: [1.0, 0.05, 0.03]", "amp: [0.0, 0.0, 0.0]")
    refused(scene(tmp_path, "  parameters: [M, md, Ipin]\n", traj=still), tmp_path,
            "the trajectory does not excite", "condition number", "Ipin")


def test_scene_kinds_that_do_not_mix(tmp_path):
    sim = "simulate:\n  controller: pd\n"
    s = write_scene(tmp_path / "s.yaml", MANIP + SINE + sim + "identify:\n  method: ols\n")
    refused(s, tmp_path, "identification or a simulation")
    s = write_scene(tmp_path / "s.yaml", MANIP + SINE + "identify:\n  method: ols\n"
                    + "sweep:\n  manipulator.M: [0.1, 0.2]\n")
    refused(s, tmp_path, "no sweep")


BAD_TABLES = [
    ("t, l1, l2, l3, l1_dot, l2_dot, l3_dot, F1, F2, F3\n0, 0.3, 0.3, 0.3, 0, 0, 0, 1, 1, 1\n",
     ["t.csv", "l1_ddot", "rates", "accelerations"]),
    ("t, l1 [mm], l2, l3, l1_dot, l2_dot, l3_dot, l1_ddot, l2_ddot, l3_ddot, F1, F2, F3\n",
     ["t.csv:1:", "column l1", "units 'mm'", "in m"]),
    ("t, l1, l2, l3, l1_dot, l2_dot, l3_dot, l1_ddot, l2_ddot, l3_ddot, F1, F2, F3\n"
     "0, 0.3, 0.3, 0.3, 0, 0, 0, 0, 0, 0, 1, 1, 1\n"
     "0.1, 0.3, nan, 0.3, 0, 0, 0, 0, 0, 0, 1, 1, 1\n",
     ["t.csv:3:", "column l2", "not a finite number"]),
    ("t, l1, l2, l3, l1_dot, l2_dot, l3_dot, l1_ddot, l2_ddot, l3_ddot, F1, F2, F3\n"
     "0, 0.3, 0.3, 0.3, 0, 0, 0, 0, 0, 0, 1, 1, 1\n"
     "0.1, 0.3, 0.3, 0.3, 0, 0, 0, 0, 0, 0, 1, 1, 1\n"
     "0.1, 0.3, 0.3, 0.3, 0, 0, 0, 0, 0, 0, 1, 1, 1\n",
     ["t.csv:4", "column t", "increase strictly"]),
]


@pytest.mark.parametrize("text, words", BAD_TABLES)
def test_bad_tables_name_file_row_and_column(tmp_path, text, words):
    (tmp_path / "t.csv").write_text(text)
    s = write_scene(tmp_path / "s.yaml", DATA_MANIP + "identify:\n  data: t.csv\n")
    refused(s, tmp_path, "s.yaml:", "identify.data", *words)


def test_data_and_trajectory_or_monte_carlo_refused(tmp_path, measured):
    s = write_scene(tmp_path / "s.yaml", DATA_MANIP + SINE + "identify:\n  data: "
                    + str(measured / "meas.csv") + "\n")
    refused(s, tmp_path, "identify.data", "remove the trajectory section")
    s = write_scene(tmp_path / "s.yaml", DATA_MANIP + "identify:\n  data: "
                    + str(measured / "meas.csv") + "\n  monte_carlo: {runs: 10}\n")
    refused(s, tmp_path, "identify.monte_carlo.runs", "not with identify.data")


def test_constant_pose_data_do_not_excite(tmp_path):
    """A measured table of a platform at rest (tilted: beta > 0, where the
    pose's rates are defined): exit 2, the columns named."""
    rows = ["t, l1, l2, l3, l1_dot, l2_dot, l3_dot, l1_ddot, l2_ddot, l3_ddot, F1, F2, F3"]
    rows += [f"{0.01 * k}, 0.30, 0.31, 0.32, 0, 0, 0, 0, 0, 0, 1, 1, 1" for k in range(50)]
    (tmp_path / "rest.csv").write_text("\n".join(rows) + "\n")
    s = write_scene(tmp_path / "s.yaml", DATA_MANIP + "identify:\n  data: rest.csv\n")
    refused(s, tmp_path, "the data (identify.data) do not excite", "condition number",
            "Ipin", "pin.fv")


def test_off_axis_payload_is_a_warning(tmp_path):
    """A payload off the platform axes has products of inertia the paper
    parameters do not hold: the run says so (also with -q) and the file
    carries the warning."""
    manip = MANIP.replace("  pin_friction", "  payload: {mass: 0.3, com: [0.01, 0.02, 0.03], "
                          "inertia: [0.001, 0.001, 0.001]}\n  pin_friction")
    out = tmp_path / "pay.h5"
    proc = run(scene(tmp_path, "  method: ols\n", manip=manip), out, "-q")
    assert proc.returncode == 0, proc.stderr
    assert "warning" in proc.stderr and "products of inertia" in proc.stderr
    with h5py.File(out, "r") as f:
        assert "products of inertia" in f.attrs["warning"]
        assert "M" not in names(f) and "payload.m" in names(f)


#: the one deviation from CF the identification file keeps (as
#: rps3.ident_io's file): the variables over the parameter dimension hold
#: values of several units, named by parameter_units; each parameter alone,
#: in its UDUNITS units, is parameters/NAME
MIXED_UNITS = ("various: see parameter_units", "various: products of parameter_units")


@pytest.mark.usefixtures("offline")
def test_compliance_checker_cf_1_10(tmp_path):
    """A whole file with the consistent fit and draws, and its shards
    joined: no CF error but the mixed units of the parameter variables."""
    from test_cf import ALLOWED_EXCEPTIONS, ALLOWED_WARNINGS, compliance
    s = scene(tmp_path, f"""\
  parameters: [{', '.join(PARAMS)}]
  consistent: true
  monte_carlo: {{runs: 16, seed: 3}}
""")
    one = tmp_path / "one.nc"
    assert run(s, one, "-q").returncode == 0
    parts = [tmp_path / f"p{k}.nc" for k in range(2)]
    for k, part in enumerate(parts):
        assert run(s, part, "-q", "--shard", f"{k}/2").returncode == 0
    joined = tmp_path / "joined.nc"
    proc = subprocess.run([RUNNER, "merge", str(joined), *map(str, parts), "-q"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    for path in (one, joined):
        errors, warnings, exceptions = compliance(path, tmp_path)
        assert [e for e in errors if not any(u in e for u in MIXED_UNITS)] == [], errors
        assert all(w.startswith(ALLOWED_WARNINGS) for w in warnings), warnings
        assert all(any(a in e for a in ALLOWED_EXCEPTIONS) for e in exceptions), exceptions


def test_hdf5_data_in_other_units_refused(tmp_path, measured):
    """An HDF5 table whose forces are in kN: the file and the dataset are
    named, nothing is written."""
    bad = tmp_path / "kN.h5"
    with h5py.File(measured / "meas.h5", "r") as f, h5py.File(bad, "w") as g:
        for k in f:
            g[k] = f[k][()]
            g[k].attrs["units"] = f[k].attrs["units"]
        g["F2"].attrs["units"] = "kN"
    s = write_scene(tmp_path / "s.yaml", DATA_MANIP + "identify:\n  data: kN.h5\n")
    refused(s, tmp_path, "kN.h5: dataset /F2", "units 'kN'", "in N")


# ----------------------------------- consistent draws, held-out prediction

#: the held-out share of test_consistent_draws_predict_held_out_forces
HOLD = 0.25
#: the median over 20 draws of the WLS fit's held-out NRMSE against its
#: expectation: one draw's NRMSE over ~1500 held-out rows has a relative
#: spread of 1 / sqrt(2 * 1500) = 1.8 %, the median of 20 about 0.5 %; 3 %
#: is six of those
TOL_NRMSE_MEDIAN = 0.03
#: one draw's against the same expectation: 5.5 spreads
TOL_NRMSE_DRAW = 0.10
#: the requirement: the consistent fit predicts held-out forces within 2 %
#: of the unconstrained WLS fit
RATIO_MAX = 1.02


def test_consistent_draws_predict_held_out_forces(tmp_path):
    """20 draws with the consistent fit and the last quarter of the samples
    held out: every draw's consistent fit is physically consistent and
    converged, its held-out NRMSE within 2 % of the WLS fit's, and the WLS
    fit's at the noise level: the noise standard deviation over the RMS of
    the held-out forces (from the inverse dynamics of the same scene
    without the identify section, a plain run), times sqrt(1 + p / n) of
    the fit's own error.  The summary is the draws' (recomputed here)."""
    runs, p = 20, len(PARAMS)
    traj = SINE.replace("dt: 0.002", "dt: 0.001")
    s = scene(tmp_path, f"""\
  parameters: [{', '.join(PARAMS)}]
  consistent: true
  monte_carlo: {{runs: {runs}, force_noise: 0.01, seed: 3, holdout: {HOLD}}}
""", traj=traj)
    out = tmp_path / "mc.h5"
    proc = run(s, out, "-j", "2")
    assert proc.returncode == 0, proc.stderr
    assert f"consistent fit: {runs} of {runs} draws (100.0 %) physically consistent" in proc.stdout
    # the oracle: the forces of the inverse dynamics along the trajectory
    plain = tmp_path / "plain.h5"
    assert run(write_scene(tmp_path / "plain.yaml", MANIP + traj), plain, "-q").returncode == 0
    with h5py.File(plain, "r") as f:
        F0 = f["force"][0]
    ns = len(F0)
    nhold = int(np.floor(HOLD * ns))
    sig = 0.01 * np.sqrt(np.mean(F0 ** 2, axis=0))
    held = F0[ns - nhold:]
    want = np.sqrt(nhold * np.sum(sig ** 2) / np.sum(held ** 2 + sig ** 2))
    want *= np.sqrt(1 + p / (3 * (ns - nhold)))
    with h5py.File(out, "r") as f:
        np.testing.assert_allclose(f["force_rms"][()], sig / 0.01, rtol=1e-12)
        assert f.attrs["holdout"] == HOLD
        assert (f["status"][()] == 0).all()
        assert (f["mc_consistent"][()] == 1).all()
        assert (f["mc_consistent_status"][()] == 0).all()
        assert f["mc_consistent_fraction"][()] == 1.0
        assert f["mc_converged_fraction"][()] == 1.0
        nw, nc = f["mc_holdout_nrmse"][()], f["mc_consistent_holdout_nrmse"][()]
        ratio = nc / nw
        assert ratio.max() <= RATIO_MAX, ratio
        assert np.median(nw) == pytest.approx(want, rel=TOL_NRMSE_MEDIAN)
        np.testing.assert_allclose(nw, want, rtol=TOL_NRMSE_DRAW)
        assert f["mc_holdout_nrmse_median"][()] == np.median(nw)
        assert f["mc_consistent_holdout_nrmse_median"][()] == np.median(nc)
        assert f["mc_holdout_ratio_median"][()] == np.median(ratio)
        assert f["mc_holdout_ratio_max"][()] == ratio.max()
        # the noise-free fit (the file's) is on every sample, the draws' on
        # the first ns - nhold: their intervals are theta -+ t(dof) std at
        # those rows' degrees of freedom
        assert f["dof"][()] == 3 * ns - p
        th, sd, ci = f["mc_theta"][()], f["mc_std"][()], f["mc_ci"][()]
        t_draw = stats.t.ppf(0.975, 3 * (ns - nhold) - p)
        assert abs(t_draw / stats.t.ppf(0.975, 3 * ns - p) - 1) > 1e-5
        np.testing.assert_allclose((ci[..., 1] - th) / sd, t_draw, rtol=1e-9)


def test_no_holdout_and_no_consistent_fit(tmp_path):
    """holdout 0: no held-out datasets; without identify.consistent no
    consistent ones; the draws' fits are then of every sample."""
    s = monte_carlo(tmp_path, 8).read_text().replace(
        "seed: 11}", "seed: 11, holdout: 0}")
    path = write_scene(tmp_path / "h0.yaml", s)
    out = tmp_path / "h0.h5"
    proc = run(path, out, "-q")
    assert proc.returncode == 0, proc.stderr
    with h5py.File(out, "r") as f:
        for name in ("mc_holdout_nrmse", "mc_consistent", "mc_consistent_status",
                     "mc_consistent_holdout_nrmse", "mc_holdout_ratio_max"):
            assert name not in f, name
        assert f.attrs["holdout"] == 0
