"""rps3-study end to end: it writes self-describing HDF5 (dimension scales,
units), the numbers obey what the study claims, and the analysis scripts
draw their figures.  Small runs (20 samples, one timed pass, a coarse
workspace grid); `make study` is the full one."""

import os
import subprocess
import sys

import h5py
import numpy as np
import xarray as xr

from conftest import ANALYSIS, ROOT

STUDY = os.path.join(ROOT, "build", "rps3-study")


def study(*args):
    p = subprocess.run([STUDY, *map(str, args)], capture_output=True,
                       text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    return p


def test_accuracy_file_and_plot(tmp_path):
    out = tmp_path / "accuracy.h5"
    study("accuracy", "-o", out, "--samples", 20, "--repeats", 1)
    assert not (tmp_path / "accuracy.h5.tmp").exists()
    ds = xr.open_dataset(out, engine="h5netcdf")
    assert ds["force_error"].dims == ("trajectory", "config")
    with h5py.File(out, "r") as f:
        for name in ("rps3_version", "created_utc", "command_line"):
            assert name in f.attrs
        for name, d in f.items():
            assert "units" in d.attrs and "description" in d.attrs, name
        study_ = np.array([s.decode() for s in f["study"][()]])
        label = np.array([s.decode() for s in f["label"][()]])
        err = f["force_error"][()]
        theta = f["theta_error"][()]
        ns = f["ns_per_point"][()]
        floor = f["reference_floor_force"][()]
        f_traj = [s.decode() for s in f["trajectory"][()]]
    # the reference is its own formulation in long double (study_ref.c,
    # the model's inputs only; test_study_ref.c), so the default path
    # (closed form, exact rates, Lagrange) is graded too: never exactly 0,
    # and far above the reference's own floor (~1e-18 | 1e-17).  The bound:
    # a double evaluation loses cond x eps; 4.6e-16 (helix) and 3.6e-14
    # (sine_edge, close to the singular surface) were measured with 1000
    # samples, a subset sees at most that, and 1e-13 leaves a factor 2.8
    # while any wrong term (the effects ladder: >= 1e-3) is far above it
    closed = np.flatnonzero(label == "closed form (39)")[0]
    ne = np.flatnonzero(label == "newton_euler")[0]
    assert (err[:, closed] > 0).all() and (err[:, closed] < 1e-13).all()
    assert (err[:, ne] > 0).all() and (err[:, ne] < 1e-13).all()
    assert (theta[:, closed] <= 4.5e-16).all()  # vs long double: 2 ulp
    assert (floor < 1e-16).all() and (floor > 0).all()
    assert (err[:, closed] > 10 * floor).all()
    # deliberately worse settings score worse than the default: a loose
    # solver tolerance, rates by differences, an effect left out
    worse = [np.flatnonzero(label == lab)[0] for lab in
             ("newton tol=1e-06 warm", "fd_pose h=1e-03 s", "+payload")]
    for w in worse:
        assert (err[:, w] > 1e3 * err[:, closed]).all(), label[w]
    assert (ns > 0).all() and np.isfinite(ns).all()
    # a looser tolerance is never more accurate than a tight one (warm
    # hybridsj), and the loosest is visibly wrong
    rows = [np.flatnonzero(label == f"hybridsj tol={t} warm")[0]
            for t in ("1e-02", "1e-06", "1e-10", "1e-14")]
    for t in range(err.shape[0]):
        e = err[t, rows]
        assert (np.diff(e) < 0).all(), e
    # rates from the spline of poses sampled every h (a table's route):
    # on the smooth sine_edge the error falls with h (as h^2, the order of
    # the spline's acceleration: 1.4e-2, 8.6e-5, 1.5e-6 with 1000 samples),
    # and stays far above the exact route's (on the helix a subset of
    # samples may miss the blend corners, where alone the spline errs)
    spl = [np.flatnonzero(label == f"spline_pose h={h} s")[0]
           for h in ("1e-01", "1e-02", "1e-03")]
    edge = f_traj.index("sine_edge")
    assert (np.diff(err[edge, spl]) < 0).all(), err[edge, spl]
    assert err[edge, spl[-1]] < 1e-4
    assert (err[edge, spl] > 1e3 * err[edge, closed]).all()
    assert set(study_) == {"theta", "derivative", "method", "effects", "dt"}
    p = subprocess.run([sys.executable, os.path.join(ANALYSIS,
                        "accuracy_cost.py"), str(out), str(tmp_path)],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert "| helix |" in p.stdout and "| sine_edge |" in p.stdout
    assert (tmp_path / "accuracy_cost.png").stat().st_size > 10000


def test_workspace_file_and_plot(tmp_path):
    out = tmp_path / "workspace.h5"
    study("workspace", "-o", out, "--quick")
    ds = xr.open_dataset(out, engine="h5netcdf")
    assert ds["force"].dims == ("rho", "alpha", "beta", "z_c", "link")
    ok = ds["status"].values == 0
    # reachable points are finite, others NaN; the level pose is in the
    # home mode and well conditioned
    assert np.isfinite(ds["force"].values[ok]).all()
    assert np.isnan(ds["condition"].values[ds["status"].values == 1]).all()
    level = ds["mode"].sel(beta=0.0).values
    assert (level[ds["status"].sel(beta=0.0).values == 0] == 1).all()
    assert 0.5 < ok.mean() < 1.0
    # the safe region is drawn with the force transmission: its holding
    # forces stay moderate (a region of cond < 1e6 alone would hold
    # 2.3e4 N), and every refused point past trans_max is singular
    # (status 4)
    tr = ds["transmission"].values
    assert ds["transmission"].attrs["units"] == "1"
    assert np.isfinite(tr[ok]).all() and (tr[ok] <= 1e8).all()
    safe = ok & (ds["mode"].values == 1) & (tr < 100.0)
    assert 0.5 < safe.mean() < ok.mean()
    assert np.nanmax(np.where(safe, ds["max_force"].values, np.nan)) < 1e3
    p = subprocess.run([sys.executable, os.path.join(ANALYSIS,
                        "workspace.py"), str(out), str(tmp_path)],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "workspace.png").stat().st_size > 10000


def test_bad_command_line():
    for args in ([], ["accuracy"], ["nonsense", "-o", "x.h5"],
                 ["accuracy", "-o", "x.h5", "--samples", "3"]):
        p = subprocess.run([STUDY, *args], capture_output=True, text=True)
        # one line saying what is wrong, then where the usage is (GNU)
        assert p.returncode == 2 and "Try 'rps3-study --help'" in p.stderr, p.stderr
