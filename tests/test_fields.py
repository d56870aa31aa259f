"""rps3-run --fields: only the listed per-sample fields are written (the
per-case ones and the coordinates always), unknown names are refused with
the valid ones, and part files of such runs merge and resume, but never
with parts of other fields."""

import subprocess

import h5py
import numpy as np
import pytest
import xarray as xr
from conftest import CONFIGS, FAILING_SINE, RUNNER, run, write_scene

PER_SAMPLE = ["force", "force_by_effect", "length", "length_rate",
              "length_accel", "theta", "alpha", "beta", "z_c", "x_c", "y_c",
              "lambda", "energy_residual", "energy_scale", "condition",
              "transmission", "solve_niter", "solve_resid", "warn"]
ALWAYS = ["status", "failed_at", "message", "scene_resolved", "case", "time",
          "link", "effect", "constraint", "scene", "trajectory__amp_2"]


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    """9 cases of 4001 samples (3 jobs of 3 cases); the amp[2] = 0.2 case
    fails."""
    tmp = tmp_path_factory.mktemp("fields")
    text = FAILING_SINE.replace("SAMPLES", "4001").replace(
        "THETA", "closed_form").replace(
        "[0.05, 0.2, 0.1]", "[0.05, 0.2, 0.1, 0.07, 0.02, 0.09, 0.03, 0.06, "
        "0.08]")
    return write_scene(tmp / "s.yaml", text)


@pytest.fixture(scope="module")
def whole(scene, tmp_path_factory):
    out = tmp_path_factory.mktemp("whole") / "all.h5"
    assert run(scene, out, "-q").returncode == 1
    return out


def test_only_the_listed_fields(scene, whole, tmp_path):
    out = tmp_path / "f.h5"
    proc = run(scene, out, "-q", "--fields", "theta,force,warn")
    assert proc.returncode == 1, proc.stderr         # the failing cases
    with h5py.File(out, "r") as f, h5py.File(whole, "r") as g:
        assert f.attrs["fields"] == "force,theta,warn"   # schema order
        assert g.attrs["fields"] == ",".join(PER_SAMPLE)
        names = set(f.keys())
        assert names == set(ALWAYS) | {"force", "theta", "warn"}, names
        for k in ("warn", "status", "failed_at"):
            assert f[k][()].tobytes() == g[k][()].tobytes(), k
        assert list(f["message"][()]) == list(g["message"][()])
        # computed by rps3_inverse_batch (see below): equal to rounding
        for k in ("force", "theta"):
            close_to_rounding(f[k][()], g[k][()], k)
        # the same layout as the whole file, attributes included
        assert f["force"].chunks == g["force"].chunks
        assert f["force"].attrs["units"] == "N"
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        assert ds["force"].dims == ("case", "time", "link")
    # smaller, and the estimate knows it
    check = run(scene, None, "--check", "--fields", "force")
    full = run(scene, None, "--check")
    assert check.returncode == 0 and full.returncode == 0
    assert check.stdout.split("output about")[1] != \
        full.stdout.split("output about")[1]


def close_to_rounding(a, b, name, scale=None):
    """a and b NaN at the same places, and within 1e-12 of the largest
    magnitude (or of scale) elsewhere: the batch kernel agrees with
    rps3_inverse to within 8 eps cond (tests/test_batch_kernel.c)."""
    assert np.array_equal(np.isnan(a), np.isnan(b)), name
    s = np.nanmax(np.abs(a)) if scale is None else scale
    assert np.nanmax(np.abs(a - b)) <= 1e-12 * s, (name, np.nanmax(
        np.abs(a - b)) / s)


# the per-sample fields rps3_inverse_batch returns, the pose with them
BATCH = ["force", "force_by_effect", "length", "theta", "alpha", "beta",
         "z_c", "lambda", "energy_residual", "condition", "solve_niter",
         "warn"]


@pytest.mark.parametrize("theta", ["closed_form", "multiroot"])
def test_a_file_of_batch_fields_is_computed_by_the_batch(tmp_path, theta):
    """A file of only the fields rps3_inverse_batch returns is computed by
    it: by the vectorised kernel where it applies (closed form), equal to
    rps3_inverse's numbers to rounding; by the per-point loop elsewhere
    (multiroot), bit for bit.  Failing cases fail alike."""
    text = FAILING_SINE.replace("SAMPLES", "1001").replace("THETA", theta)
    scene = write_scene(tmp_path / "s.yaml", text)
    full, part = tmp_path / "full.h5", tmp_path / "part.h5"
    assert run(scene, full, "-q").returncode == 1
    proc = run(scene, part, "-q", "--fields", ",".join(BATCH))
    assert proc.returncode == 1, proc.stderr
    with h5py.File(full, "r") as f, h5py.File(part, "r") as g:
        for k in ("status", "failed_at", "warn", "solve_niter"):
            assert f[k][()].tobytes() == g[k][()].tobytes(), k
        assert list(f["message"][()]) == list(g["message"][()])
        assert (f["status"][()] != 0).sum() == 1
        for k in BATCH:
            a, b = f[k][()], g[k][()]
            if theta == "multiroot":
                assert a.tobytes() == b.tobytes(), k
            elif k == "energy_residual":
                # rounding noise either way: against its terms' scale
                close_to_rounding(a, b, k, np.nanmax(f["energy_scale"]))
            elif a.dtype.kind == "f":
                close_to_rounding(a, b, k)


@pytest.mark.parametrize("arg", ["forces", "force,", "", "force,status",
                                 "force,,length", "Force"])
def test_unknown_fields_are_refused(scene, tmp_path, arg):
    proc = run(scene, tmp_path / "x.h5", "--fields", arg)
    assert proc.returncode == 2, proc.stderr
    assert "is not a per-sample field; the fields are force,force_by_effect," \
           in proc.stderr
    assert "(status, failed_at, message, scene_resolved and the coordinates " \
           "are always written)" in proc.stderr
    assert list(tmp_path.iterdir()) == []
    proc = run(scene, tmp_path / "x.h5", "--fields")
    assert proc.returncode == 2 and "--fields needs a value" in proc.stderr


def test_a_simulation_is_written_whole(tmp_path):
    """--fields chooses variables of the inverse-dynamics file only."""
    proc = run(f"{CONFIGS}/closed_loop.yaml", tmp_path / "x.h5",
               "--fields", "force")
    assert proc.returncode == 2
    assert "a scene with a simulate section writes the simulation file " \
           "whole" in proc.stderr
    assert list(tmp_path.iterdir()) == []


def merge(out, parts, *extra):
    return subprocess.run([RUNNER, "merge", str(out)] +
                          [str(p) for p in parts] + list(extra),
                          capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize("copy", [[], ["--copy"]])
def test_parts_of_the_same_fields_merge(scene, tmp_path, copy):
    one = tmp_path / "one.h5"
    assert run(scene, one, "-q", "--fields", "force,length").returncode == 1
    parts = [tmp_path / f"p{k}.h5" for k in range(3)]
    for k, p in enumerate(parts):
        proc = run(scene, p, "-q", "--shard", f"{k}/3",
                   "--fields", "length,force")
        assert proc.returncode in (0, 1), proc.stderr
    out = tmp_path / "m.h5"
    proc = merge(out, parts, *copy)
    assert proc.returncode == 1, proc.stderr
    with h5py.File(out, "r") as f, h5py.File(one, "r") as g:
        assert set(f.keys()) == set(g.keys())
        assert f.attrs["fields"] == "force,length"
        for k in ("force", "length", "status"):
            assert f[k][()].tobytes() == g[k][()].tobytes(), k


def test_parts_of_other_fields_are_refused(scene, tmp_path):
    parts = [tmp_path / f"p{k}.h5" for k in range(3)]
    for k, p in enumerate(parts):
        extra = ["--fields", "force"] if k == 1 else []
        assert run(scene, p, "-q", "--shard", f"{k}/3",
                   *extra).returncode in (0, 1)
    out = tmp_path / "m.h5"
    for copy in ([], ["--copy"]):
        proc = merge(out, parts, *copy)
        assert proc.returncode == 2, proc.stderr
        assert "has fields force: parts with different --fields are not " \
               "merged" in proc.stderr, proc.stderr
        assert not out.exists()


def test_resume_keeps_a_part_of_the_same_fields_only(scene, tmp_path):
    part = tmp_path / "p0.h5"
    args = ["--shard", "0/3", "--resume", "--failed-ok"]
    assert run(scene, part, "-q", "--shard", "0/3", "--fields",
               "force").returncode in (0, 1)
    before = part.stat().st_mtime_ns
    proc = run(scene, part, *args, "--fields", "force")
    assert proc.returncode == 0 and "not run again" in proc.stderr
    assert part.stat().st_mtime_ns == before
    proc = run(scene, part, *args)
    assert proc.returncode == 0, proc.stderr
    assert "has the fields force, this run writes force,force_by_effect," \
           in proc.stderr and "running shard 0/3 again" in proc.stderr
    with h5py.File(part, "r") as f:
        assert "length" in f and not np.isnan(f["length"][0]).all()
