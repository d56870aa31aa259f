"""rps3-simstudy end to end: closed-loop tracking and simulation accuracy in
self-describing HDF5 (units on every dataset), the orderings the study
claims, and the figures of analysis/simulation.py.  The --quick run (helix
shortened to 2 s, accuracy over 0.5 s); `make simulation` is the full one."""

import os
import subprocess
import sys

import h5py
import numpy as np

from conftest import ANALYSIS, ROOT

SIMSTUDY = os.path.join(ROOT, "build", "rps3-simstudy")


def test_simstudy_file_orderings_and_figures(tmp_path):
    out = tmp_path / "sim.h5"
    p = subprocess.run([SIMSTUDY, "-o", str(out), "--quick"],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert not (tmp_path / "sim.h5.tmp").exists()
    with h5py.File(out, "r") as f:
        assert "rps3_version" in f.attrs and "command_line" in f.attrs

        def units(name, obj):
            if isinstance(obj, h5py.Dataset):
                assert "units" in obj.attrs, name
        f.visititems(units)
        for path in ("helix", "fast_sine"):
            g = f["tracking"][path]
            assert (g["status"][()] == 0).all(), path
            err = np.nanmax(g["error"][()], axis=2)  # [controller, model]
            # computed torque with the exact model beats PD; leaving the
            # link mass out of its model costs at least 10x
            assert err[2, 0] < err[0, 0], path
            assert err[2, 1] > 10 * err[2, 0], path
            assert g["force"].shape[-1] == 3
        a = f["accuracy"]
        err, cpu = a["error"][()], a["cpu_per_sim_s"][()]
        assert (a["status"][()] == 0).all()
        assert (cpu > 0).all()
        integ = a["integrator"][()]
        h = a["h_or_tol"][()]
        rk4 = np.flatnonzero(integ == 0)
        # RK4 at the control rate (1 ms) is already far below a micrometre;
        # smaller steps are not worse (theta tol 1e-12 column)
        assert err[rk4[0], 0] < 1e-9
        assert err[rk4[np.argmin(h[rk4])], 0] <= err[rk4[0], 0] * 1.5
    figs = tmp_path / "figs"
    p = subprocess.run([sys.executable, os.path.join(ANALYSIS, "simulation.py"),
                        str(out), str(figs)], capture_output=True, text=True,
                       timeout=120)
    assert p.returncode == 0, p.stderr
    for name in ("tracking_helix.png", "tracking_fast_sine.png",
                 "simulation_accuracy.png"):
        assert (figs / name).stat().st_size > 10000, name
    assert "| helix | computed_torque | exact |" in p.stdout
