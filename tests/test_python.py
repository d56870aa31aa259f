"""The Python package rps3 (python/, installed into .venv by `make venv`):
against the runner's HDF5 output (bitwise where the batch runs the
per-point path, to the batch kernel's rounding where it runs the kernel),
against the C tests' cases and identities, its batch against its own
points one by one, open_dataset's dimensions, and bad input raising clean
exceptions that name the argument."""

import gc
import os
import re
import subprocess
import sys

import h5py
import numpy as np
import pytest
import rps3
from conftest import CONFIGS, ROOT, STUDY_CONFIGS, run

# the paper's scene (configs/paper.yaml), as keyword arguments
PAPER = dict(R=0.2286, rho=0.5, M=0.18, d=0.1524, g=9.80665,
             effects=["platform_gravity", "link_gravity", "platform_inertia",
                      "link_inertia"], theta="closed_form", method="lagrange")
HELIX = dict(radius=0.000266, pitch=0.03048, z0=0.3048, period=10.0, blend=1.0)


def same_bits(a, b):
    """Bitwise equality of float arrays (NaN of the same bits included)."""
    a, b = np.ascontiguousarray(a), np.ascontiguousarray(b)
    return a.shape == b.shape and a.tobytes() == b.tobytes()


# ------------------------------------------------------------ against files

@pytest.mark.parametrize("case, m_over_M", [(0, 0.0), (1, 0.5)])
def test_paper_case_as_the_runner(paper_h5, case, m_over_M):
    """The paper's scene is the vectorised batch kernel's (closed form,
    Lagrange, the paper's effects), through which the package and the
    runner both compute: the same bits.  The tolerances below are the
    kernel's against the per-point rps3_inverse (tests/test_batch_kernel.c),
    kept so that the test still says what to expect if the runner's route
    changes: lengths to 4 ulp, theta to 2 ulp of pi, forces, shares and
    lambda R to 8 eps cond of the point's force scale."""
    with h5py.File(paper_h5, "r") as f:
        t = f["time"][()]
        want = {k: f[k][case] for k in ("force", "force_by_effect", "lambda",
                                         "condition", "length", "theta",
                                         "energy_residual")}
        effects = rps3.h5io.effects(f)
        pose = np.stack([f["alpha"][case], f["beta"][case], f["z_c"][case]], 1)
    model = rps3.Model(m_over_M=m_over_M, **PAPER)
    traj = rps3.trajectory.helix(t=t, model=model, **HELIX)
    assert same_bits(traj.pose, pose)
    out = model.inverse(traj.pose, traj.dpose, traj.ddpose)
    assert (out.status == 0).all()
    eps = np.finfo(float).eps
    cond = want["condition"][:, None]
    scale = np.maximum(np.abs(want["force"]).max(1, keepdims=True),
                       np.abs(want["force_by_effect"]).max((1, 2))[:, None])
    tol = 8 * eps * cond * scale
    np.testing.assert_allclose(out.l, want["length"], rtol=4 * eps, atol=0)
    np.testing.assert_allclose(out.theta, want["theta"], rtol=0,
                               atol=2 * np.spacing(np.pi))
    assert (np.abs(out.force - want["force"]) <= tol).all()
    assert (np.abs(out.lambda_ - want["lambda"]) * PAPER["R"] <= tol).all()
    np.testing.assert_allclose(out.condition, want["condition"],
                               rtol=8 * eps * want["condition"].max(), atol=0)
    assert list(out.shares) == effects
    # the runner computes through the same batch entry point: bit for bit
    with h5py.File(paper_h5, "r") as f:
        for got, name in ((out.force, "force"), (out.l, "length"),
                          (out.theta, "theta"), (out.lambda_, "lambda"),
                          (out.condition, "condition"),
                          (out.transmission, "transmission")):
            assert same_bits(got, f[name][case]), name
    for k, name in enumerate(effects):
        assert (np.abs(out.shares[name] - want["force_by_effect"][:, k, :])
                <= tol).all()
    # the residual is rounding in both: within the forces' rounding times
    # the largest power the links deliver
    power = np.abs(out.force).max() * np.abs(np.gradient(out.l, t, axis=0)).max()
    assert np.abs(out.energy_residual - want["energy_residual"]).max() <= \
        8 * eps * cond.max() * 3 * power


def test_multiroot_newton_euler_bitwise_as_the_runner(tmp_path):
    """The warm-started theta solve and the second formulation: the package
    (one batch call) and the runner (one case) follow the same points in
    the same order."""
    scene = tmp_path / "ne.yaml"
    text = open(os.path.join(CONFIGS, "paper.yaml")).read()
    text = text.replace("theta: closed_form", "theta: multiroot")
    text = text.replace("method: lagrange", "method: newton_euler")
    text = text.split("sweep:")[0]
    scene.write_text(text)
    out_h5 = tmp_path / "ne.h5"
    proc = run(scene, out_h5, "-q")
    assert proc.returncode == 0, proc.stderr
    with h5py.File(out_h5, "r") as f:
        t = f["time"][()]
        force, theta = f["force"][0], f["theta"][0]
        niter = f["solve_niter"][0]
    model = rps3.Model(**{**PAPER, "theta": "multiroot",
                          "method": "newton_euler"})
    traj = rps3.trajectory.helix(t=t, model=model, **HELIX)
    out = model.inverse(traj.pose, traj.dpose, traj.ddpose)
    assert same_bits(out.force, force)
    assert same_bits(out.theta, theta)
    assert np.isnan(out.lambda_).all()  # not computed by Newton-Euler
    assert niter.max() > 0


def test_golden_answers(paper_h5):
    """tests/golden/paper.txt (10 digits) from the package alone."""
    rows = np.loadtxt(os.path.join(ROOT, "tests", "golden", "paper.txt"))
    for case, m_over_M in ((0, 0.0), (1, 0.5)):
        sel = rows[rows[:, 0] == case]
        model = rps3.Model(m_over_M=m_over_M, **PAPER)
        traj = rps3.trajectory.helix(t=sel[:, 1], model=model, **HELIX)
        out = model.inverse(traj.pose, traj.dpose, traj.ddpose)
        # 10 significant digits printed: half a unit of the 10th
        for got, cols in ((out.l, slice(2, 5)), (out.theta, slice(5, 8)),
                          (out.force, slice(8, 11)), (out.lambda_, slice(11, 14))):
            np.testing.assert_allclose(got, sel[:, cols], rtol=5e-10, atol=0)


# ------------------------------------------------------ the C tests' cases

def entropy_model(**kw):
    """tests/testutil.h's model_entropy(): high-entropy parameters."""
    return rps3.Model(R=0.2385, rho=0.4387, M=0.2381, m=0.0917, d=0.1383,
                      link_Ic=3.17e-4, g=9.80665,
                      payload=dict(mass=0.0713, com=[0.0127, -0.0083, 0.0411],
                                   inertia=[1.13e-4, 1.71e-4, 0.97e-4]),
                      friction=dict(viscous=0.0137, coulomb=0.0029),
                      effects=list(rps3.EFFECTS), **kw)


def sine_points(model, n=2000):
    return rps3.trajectory.sine(mean=[0.71, 0.23, 0.27], amp=[1.3, 0.07, 0.04],
                                freq=[0.53, 1.7, 0.91], phase=[0.3, -1.1, 2.2],
                                duration=2.0, samples=n, model=model)


def test_lagrange_equals_newton_euler_and_energy_balance():
    lag = entropy_model()
    ne = entropy_model(method="newton_euler")
    tr = sine_points(lag)
    a = lag.inverse(tr.pose, tr.dpose, tr.ddpose)
    b = ne.inverse(tr.pose, tr.dpose, tr.ddpose)
    assert a.ok.all() and b.ok.all()
    # two independent formulations: TOL_PHYS of tests/testutil.h
    scale = np.abs(a.force).max()
    assert np.abs(a.force - b.force).max() <= 1e-9 * scale
    # the shares sum to the force (exact sums of the same terms)
    total = sum(a.shares.values())
    assert np.abs(total - a.force).max() <= 1e-12 * scale
    # actuator power = d(T + P)/dt: the residual is rounding only
    assert np.abs(a.energy_residual).max() <= 1e-9 * scale


def test_ik_fk_round_trip_and_guess():
    model = entropy_model(warm_start=False)
    tr = sine_points(model, 500)
    k = model.ik(tr.pose)
    assert k.ok.all()
    # theta solve to |f| <= 1e-12, times the condition number (~100)
    fk = model.fk(k.l)
    assert fk.ok.all()
    np.testing.assert_allclose(fk.pose, tr.pose, rtol=0, atol=1e-10)
    # from the exact theta the solve has nothing to do
    exact = model.fk(k.l, guess=k.theta)
    assert (exact.niter <= 1).all()
    np.testing.assert_allclose(exact.theta, k.theta, rtol=0, atol=1e-12)


def test_batch_equals_points_one_by_one():
    """The loop runs in C: n points in one call give what n calls of one
    point give, bit for bit."""
    model = entropy_model()
    tr = sine_points(model, 64)
    batch = model.inverse(tr.pose, tr.dpose, tr.ddpose)
    for i in range(0, 64, 7):
        one = model.inverse(tr.pose[i], tr.dpose[i], tr.ddpose[i])
        assert one.force.shape == (3,) and one.status.shape == ()
        assert same_bits(one.force, batch.force[i])
        assert same_bits(one.lambda_, batch.lambda_[i])
        for name in model.effects:
            assert same_bits(one.shares[name], batch.shares[name][i])


def test_lean_forces_as_every_output():
    """outputs=["forces"] (the library's leanest pass) gives the default
    path's forces to rounding (the C tests hold it to 8 eps cond of the
    force scale; the paper's effects along a sine stay far from any
    singular pose, cond < 1e3), NaN for what it does not compute, and the
    same statuses."""
    effects = list(rps3.DEFAULT_EFFECTS)
    every = [o for o in rps3.OUTPUTS if o != "certify"]
    full = rps3.Model(effects=effects, outputs=every)
    lean = rps3.Model(effects=effects, outputs=["forces"])
    assert lean.outputs == ("forces",) and full.outputs == tuple(every)
    tr = sine_points(full, 500)
    a = full.inverse(tr.pose, tr.dpose, tr.ddpose)
    b = lean.inverse(tr.pose, tr.dpose, tr.ddpose)
    assert np.all(a.status == 0) and np.all(b.status == 0)
    scale = np.max(np.abs(a.force))
    assert np.max(a.condition) < 1e3
    np.testing.assert_allclose(b.force, a.force, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(b.condition, a.condition, rtol=1e-12)
    assert np.all(np.isnan(b.transmission)) and np.all(np.isnan(b.theta))
    assert np.all(np.isnan(b.lambda_)) and np.all(np.isnan(b.energy_residual))
    assert all(np.all(np.isnan(v)) for v in b.shares.values())
    assert np.all(np.isnan(a.energy_residual))


def test_outputs_argument_errors():
    """An unknown output name is refused with a close match; a string is
    not a list."""
    with pytest.raises(ValueError, match="did you mean 'transmission'"):
        rps3.Model(outputs=["transmision"])
    with pytest.raises(ValueError, match="^outputs: expected a list"):
        rps3.Model(outputs="forces")
    with pytest.raises(ValueError, match="given twice"):
        rps3.Model(outputs=["forces", "forces"])


def test_failing_points_are_recorded_and_the_others_computed():
    model = rps3.Model()
    tr = rps3.trajectory.helix(samples=11)
    pose = tr.pose.copy()
    pose[3, 2] = -0.05          # below the base: unreachable
    pose[7, 1] = np.nan         # not finite
    out = model.inverse(pose, tr.dpose, tr.ddpose)
    assert out.status[3] == 1 and rps3.strerror(out.status[3]) == "pose unreachable"
    assert out.status[7] == -1
    assert np.isnan(out.force[[3, 7]]).all()
    good = np.setdiff1d(np.arange(11), [3, 7])
    assert (out.status[good] == 0).all()
    ref = model.inverse(tr.pose, tr.dpose, tr.ddpose)
    assert same_bits(out.force[good], ref.force[good])


def test_layouts_copies_and_lifetimes():
    """Inputs in any layout give the same bits; the trajectory's
    (Fortran-ordered) arrays reach the library without a copy; no input is
    modified; every output owns its own memory, alive after the model, the
    workspace and the inputs are gone."""
    model = entropy_model()
    tr = sine_points(model, 257)
    args = (tr.pose, tr.dpose, tr.ddpose)
    kept = [np.array(a) for a in args]
    ref = model.inverse(*args)
    assert ref.ok.all()
    # the trajectory's arrays are the library's layout: passed as they are
    for a in args:
        assert np.shares_memory(rps3._core.points(a, "pose")[0], a)
    # C-ordered, strided rows and columns, read-only, lists: same bits
    wide = [np.zeros((2 * 257, 5)) for _ in args]
    for w, a in zip(wide, args):
        w[::2, 1:4] = a
    frozen = [np.array(a) for a in args]
    for a in frozen:
        a.flags.writeable = False
    for layout in ([np.ascontiguousarray(a) for a in args],
                   [w[::2, 1:4] for w in wide], frozen,
                   [a.tolist() for a in args]):
        out = model.inverse(*layout)
        for name in ("force", "lambda_", "condition", "l", "theta", "status"):
            assert same_bits(getattr(out, name), getattr(ref, name)), name
    for a, b in zip(args, kept):
        assert same_bits(a, b)  # inputs untouched
    k = model.ik(tr.pose)
    for lens in (k.l, np.ascontiguousarray(k.l), np.asfortranarray(k.l)[::1]):
        assert same_bits(model.fk(lens, guess=k.theta).pose,
                         model.fk(k.l, guess=k.theta).pose)
    # outputs: disjoint, writable, and owned beyond the call's objects
    fields = {"force": ref.force, "lambda_": ref.lambda_, "l": ref.l,
              "theta": ref.theta, "condition": ref.condition,
              "energy_residual": ref.energy_residual, "status": ref.status,
              "warn": ref.warn, **ref.shares}
    for i, (x, a) in enumerate(fields.items()):
        assert not any(np.shares_memory(a, b) for b in args), x
        for y, b in list(fields.items())[i + 1:]:
            assert not np.shares_memory(a, b), (x, y)
    saved = {x: np.array(a) for x, a in fields.items()}
    del model, tr, args, out, k
    gc.collect()
    junk = [np.full((257, 33), 7.25) for _ in range(64)]  # reuse freed memory
    ref.force[:] = -1.0
    assert (ref.l == saved["l"]).all() and (ref.theta == saved["theta"]).all()
    for x, a in fields.items():
        if x != "force":
            assert same_bits(a, saved[x]), x
    assert junk[-1][0, 0] == 7.25


# ---------------------------------------------------------------- datasets

def test_open_dataset_sweep_dimensions(config_runs):
    h5, proc = config_runs["grid"]
    assert proc.returncode == 0, proc.stderr
    ds = rps3.open_dataset(h5)
    assert ds.force.dims == ("m_over_M", "rho", "pitch", "time", "link")
    sel = ds.force.sel(m_over_M=0.5, rho=0.3)
    assert sel.dims == ("pitch", "time", "link")
    assert ds.force.attrs["units"] == "N"
    with h5py.File(h5, "r") as f:
        case = rps3.h5io.case_where(f, manipulator__m_over_M=0.5,
                                    manipulator__rho=0.3, trajectory__pitch=0.0)
        want = f["force"][case]
    assert int(ds.case_index.sel(m_over_M=0.5, rho=0.3, pitch=0.0)) == case
    assert same_bits(sel.sel(pitch=0.0).values, want)
    ds.close()


def test_open_dataset_single_case(tmp_path):
    scene = tmp_path / "one.yaml"
    scene.write_text(open(os.path.join(CONFIGS, "paper.yaml")).read()
                     .split("sweep:")[0])
    out = tmp_path / "one.h5"
    assert run(scene, out, "-q").returncode == 0
    with rps3.open_dataset(out) as ds:
        assert ds.force.dims == ("case", "time", "link")


def assert_opens_by_value(h5):
    """rps3.open_dataset(h5) against the file read by h5py: one dimension
    per swept key (file order, each sorted), and every case's samples of
    every per-case variable, bit for bit, at the values of its keys
    (strings for enum keys), with case_index its number; no sweep, or a
    sweep that is not each combination of its values once, keeps `case`
    (the keys as its coordinates)."""
    with h5py.File(h5, "r") as f:
        keys = rps3.h5io.sweep_keys(f)
        cols = {k: rps3.h5io.sweep_value(f, k) for k in keys}
        swept = {rps3.h5io.key_name(k) for k in keys}
        names = [k for k in f if k not in swept and k != "case"
                 and isinstance(f[k], h5py.Dataset) and f[k].ndim >= 1
                 and f[k].dtype.kind in "fiu" and f[k].dims[0]
                 and f[k].dims[0][0].name == "/case"]
        data = {k: f[k][()] for k in names}
    ncase = len(data["status"])
    with rps3.open_dataset(h5) as ds:
        dims = ds["status"].dims
        if dims == ("case",):
            for k in keys:
                short = k.rsplit(".", 1)[-1]
                name = short if short in ds.coords else k
                assert list(ds[name].values) == [
                    rps3.h5io.text(v) if cols[k].dtype.kind in "SO" else v
                    for v in cols[k]]
            keys = []
        else:
            assert len(dims) == len(keys) and "case" not in ds.dims
            for d, k in zip(dims, keys):
                assert d == k.rsplit(".", 1)[-1] or d == k
                v = ds[d].values
                assert (v[1:] > v[:-1]).all(), (d, v)  # sorted, distinct
        for c in range(ncase):
            at = {d: rps3.h5io.text(cols[k][c]) if cols[k].dtype.kind in "SO"
                  else cols[k][c] for d, k in zip(dims, keys)} or {"case": c}
            if keys:
                assert int(ds.case_index.sel(at)) == c
            for name in names:
                assert same_bits(ds[name].sel(at).values, data[name][c]), (name, c)
        return ds.status.dims


@pytest.mark.parametrize("config", sorted(
    c[:-5] for c in os.listdir(CONFIGS)
    if c.endswith(".yaml") and c not in STUDY_CONFIGS))
def test_open_dataset_every_config(config_runs, config):
    """Every shipped scene's file, whatever its number of swept keys (one
    for rho, period, mass_ratio, pitch, paper; two for the simulated
    closed_loop, one of them names; three for grid and link_mass; none for
    the trajectories); an identification's, over its parameters."""
    h5, proc = config_runs[config]
    assert proc.returncode == 0, proc.stderr
    with h5py.File(h5, "r") as f:
        ident = rps3.h5io.text(f.attrs.get("content", b"")) == "identification"
        want = {k: f[k][()] for k in ("theta", "std", "ci95")} if ident else {}
    if not ident:
        assert_opens_by_value(h5)
        return
    with rps3.open_dataset(h5) as ds:
        assert ds.theta.dims == ("parameter",)
        for k, v in want.items():
            assert same_bits(ds[k].values, v), k


def paper_scene(sweep):
    text = open(os.path.join(CONFIGS, "paper.yaml")).read().split("sweep:")[0]
    return text + ("sweep:\n" + sweep if sweep else "")


@pytest.mark.parametrize("scene, extra, dims", [
    (paper_scene(""), [], ("case",)),
    (paper_scene("  trajectory.period: [12, 8, 10]\n"), [], ("period",)),
    # the short name would be the dataset theta's: the dotted key stays
    (paper_scene("  solver.theta: [multiroot, closed_form]\n"), [],
     ("solver.theta",)),
    (paper_scene("  manipulator.rho: [0.4, 0.5]\n  trajectory.pitch: [0, 0.03]\n"
                 "  manipulator.d: [0.1524, 0.14]\n  trajectory.period: [8, 10]\n"),
     ["--fields", "length"], ("rho", "pitch", "d", "period")),
    (open(os.path.join(CONFIGS, "closed_loop.yaml")).read().split("sweep:")[0]
     + "sweep:\n  simulate.kp: [3000, 1000, 2000]\n", [], ("kp",)),
    (open(os.path.join(CONFIGS, "closed_loop.yaml")).read().split("sweep:")[0],
     [], ("case",)),
    # a value given twice: not a product of the keys' values
    (paper_scene("  manipulator.rho: [0.5, 0.4, 0.5]\n"), [], ("case",)),
], ids=["none", "one", "collision", "four-fields", "sim-one", "sim-none",
        "repeated"])
def test_open_dataset_any_number_of_keys(tmp_path, scene, extra, dims):
    path = tmp_path / "scene.yaml"
    path.write_text(scene)
    out = tmp_path / "out.h5"
    proc = run(path, out, "-q", *extra)
    assert proc.returncode == 0, proc.stderr
    assert assert_opens_by_value(out) == dims


def test_open_dataset_refuses_other_files(tmp_path):
    """A file that is not HDF5, an HDF5 file of something else, and one
    with rps3's attribute but not rps3-run's datasets: a ValueError naming
    the file; a missing file: FileNotFoundError."""
    text = tmp_path / "notes.h5"
    text.write_text("not HDF5\n")
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as f:
        f["force"] = np.zeros((2, 3))
    half = tmp_path / "half.h5"
    with h5py.File(half, "w") as f:
        f.attrs["rps3_version"] = rps3.__version__
        f["force"] = np.zeros((2, 3))
    for path, msg in ((text, "not an HDF5 file"),
                      (other, "not an rps3 file: it has no root attribute rps3_version"),
                      (half, "an rps3 file but not one of rps3-run's")):
        with pytest.raises(ValueError, match=f"^{re.escape(str(path))}: {msg}"):
            rps3.open_dataset(path)
    with pytest.raises(FileNotFoundError):
        rps3.open_dataset(tmp_path / "missing.h5")


def test_open_dataset_joined_file_needs_every_part(tmp_path, config_runs):
    """A file joined by `rps3-run merge` (virtual datasets) reads its
    parts: with every part it is the single run's file; a part moved away,
    replaced by another file, or lacking a dataset is an error naming it
    (HDF5 would read its cases as NaN); HDF5_VDS_PREFIX finds moved parts."""
    grid = os.path.join(CONFIGS, "grid.yaml")
    parts = tmp_path / "parts"
    parts.mkdir()
    for k in range(3):
        proc = run(grid, parts / f"grid.{k}.h5", "-q", "--shard", f"{k}/3")
        assert proc.returncode == 0, proc.stderr
    joined = tmp_path / "grid.h5"
    proc = subprocess.run([os.path.join(ROOT, "build", "rps3-run"), "merge",
                           str(joined), *(str(parts / f"grid.{k}.h5") for k in range(3))],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    with h5py.File(joined, "r") as f:
        assert f["force"].is_virtual
    single, proc = config_runs["grid"]
    with rps3.open_dataset(joined) as a, rps3.open_dataset(single) as b:
        assert same_bits(a.force.values, b.force.values)
    part = parts / "grid.1.h5"
    moved = tmp_path / "elsewhere"
    (moved / "parts").mkdir(parents=True)
    part.rename(moved / "parts" / part.name)
    with pytest.raises(FileNotFoundError, match=r"reads part parts/grid\.1\.h5, "
                       r"which is missing"):
        rps3.open_dataset(joined)
    # HDF5 looks under each HDF5_VDS_PREFIX for the part's stored name
    # (relative to the joined file's directory): the data are read there
    env = dict(os.environ, HDF5_VDS_PREFIX=str(tmp_path / "nowhere") + os.pathsep
               + str(moved))
    code = ("import sys, rps3; ds = rps3.open_dataset(sys.argv[1]); "
            "print(int(ds.force.isnull().sum()), int(ds.status.max()))")
    proc = subprocess.run([sys.executable, "-c", code, str(joined)], env=env,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["0", "0"]
    # another file in the part's place
    part.write_text("not HDF5\n")
    with pytest.raises(OSError, match=r"reads part parts/grid\.1\.h5, which "
                       r"cannot be opened"):
        rps3.open_dataset(joined)
    # the part without one of its datasets
    (moved / "parts" / part.name).rename(part)
    with h5py.File(part, "a") as f:
        del f["theta"]
    with pytest.raises(OSError, match=r"dataset theta reads theta of part "
                       r".*grid\.1\.h5, which has no such dataset"):
        rps3.open_dataset(joined)


def test_open_dataset_warns_on_a_part(tmp_path):
    part = tmp_path / "grid.0.h5"
    proc = run(os.path.join(CONFIGS, "grid.yaml"), part, "-q", "--shard", "0/3")
    assert proc.returncode == 0, proc.stderr
    with pytest.warns(UserWarning, match="part 0/3 of a sharded run"):
        rps3.open_dataset(part).close()


# -------------------------------------------------------------- bad input

@pytest.mark.parametrize("kwargs, name", [
    (dict(rho=-0.5), "rho"),
    (dict(R=float("nan")), "R"),
    (dict(m_over_M=-1.0), "m_over_M"),
    (dict(m=0.1, m_over_M=0.5), "m_over_M"),
    (dict(effects=["platform_gravity", "gravity"]), "effects"),
    (dict(effects="link_gravity"), "effects"),
    (dict(effects=["link_gravity", "link_gravity"]), "effects"),
    (dict(method="euler"), "method"),
    (dict(theta="numeric"), "theta"),
    (dict(outputs=["some"]), "outputs"),
    (dict(solver="bisect"), "solver"),
    (dict(tol=0.0), "tol"),
    (dict(max_iter=2.5), "max_iter"),
    (dict(cond_warn=1e6, cond_max=1e3), "cond_max"),
    (dict(payload=dict(mass=-1.0)), "payload"),
    (dict(payload=dict(inertia=[1.0, 1.0])), "payload"),
    (dict(payload=dict(colour=1)), "payload"),
    (dict(friction=dict(viscous=-0.1)), "friction"),
])
def test_model_rejects_bad_values_naming_the_argument(kwargs, name):
    with pytest.raises(ValueError) as err:
        rps3.Model(**kwargs)
    assert str(err.value).startswith(name + ":"), str(err.value)


def test_a_string_for_a_number_is_a_type_error():
    with pytest.raises(TypeError, match="^R: expected a number, got a string"):
        rps3.Model(R="wide")


def test_unknown_keyword_is_a_type_error():
    with pytest.raises(TypeError):
        rps3.Model(radius=0.2)  # type: ignore[call-arg]


@pytest.mark.parametrize("kwargs, name", [
    (dict(radius=0.5), "radius"),
    (dict(period=-1.0), "period"),
    (dict(blend=9.0), "blend"),
    (dict(samples=1), "samples"),
    (dict(samples=11, t=[0.0, 1.0]), "t"),
    (dict(t=[0.0, 11.0]), "t"),
])
def test_helix_rejects_bad_values(kwargs, name):
    with pytest.raises(ValueError) as err:
        rps3.trajectory.helix(**kwargs)
    assert str(err.value).startswith(name + ":"), str(err.value)


def test_arrays_of_the_wrong_shape_or_missing_rates():
    model = rps3.Model()
    tr = rps3.trajectory.helix(samples=5)
    with pytest.raises(ValueError, match="^pose: expected shape"):
        model.ik(np.zeros((5, 2)))
    with pytest.raises(ValueError, match="^dpose: shape"):
        model.inverse(tr.pose, tr.dpose[:4], tr.ddpose)
    with pytest.raises(ValueError, match="^dpose: needed"):
        model.inverse(tr.pose)
    with pytest.raises(ValueError, match="^guess: shape"):
        model.fk(np.full((5, 3), 0.3), guess=np.zeros((4, 3)))
    # a static selection needs no rates
    static = rps3.Model(effects=["platform_gravity"],
                        outputs=["forces", "effects", "theta"])
    assert static.inverse(tr.pose).ok.all()
    # an empty batch is empty, not an error
    assert model.inverse(np.zeros((0, 3)), np.zeros((0, 3)),
                         np.zeros((0, 3))).force.shape == (0, 3)


def test_readme_python_example_runs(config_runs, tmp_path):
    """The README's Python example, as printed, on out/grid.h5."""
    readme = open(os.path.join(ROOT, "README.md")).read()
    section = readme.split("## Python", 1)[1]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "grid.h5").symlink_to(config_runs["grid"][0])
    proc = subprocess.run([sys.executable, "-c", code], cwd=tmp_path,
                          capture_output=True, text=True, timeout=120,
                          env={**os.environ, "MPLBACKEND": "Agg"})
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip().endswith(" 0")  # the largest status: all ok


# ------------------------------------------------- arguments of real numbers

# values that are not real numbers: complex (float64 would drop the
# imaginary part, silently), strings (float64 would parse them), objects
NOT_REAL_ARRAYS = {
    "complex": lambda a: np.asarray(a) + 1e-3j,
    "complex-zero-imag": lambda a: np.asarray(a, dtype=complex),
    "strings": lambda a: np.asarray(a).astype(str),
    "objects": lambda a: np.asarray(a).astype(object),
    "bools": lambda a: np.ones(np.shape(a), bool),
    "list-with-none": lambda a: [None] * len(a) if np.ndim(a) == 1 else
                                [[None] * 3] * len(a),
}
NOT_REAL_SCALARS = {
    "complex": lambda x: complex(x, 1e-3),
    "numpy-complex": lambda x: np.complex128(x + 1e-3j),
    "0d-complex": lambda x: np.array(x + 0j),
    "string": lambda x: str(x),
    "bytes": lambda x: str(x).encode(),
    "decimal": lambda x: __import__("decimal").Decimal(str(x)),
}


def _helix():
    return rps3.trajectory.helix(samples=5)


# every argument of the public functions that takes numbers: (function,
# valid keyword arguments, the argument, whether it is an array); the
# arrays of the stages are their (n, 3) inputs
def _number_arguments():
    tr = _helix()
    model = rps3.Model()
    k = model.ik(tr.pose)
    sine = dict(mean=[0.0, 0.05, 0.15], amp=[0.3, 0.0, 0.05],
                freq=[0.5, 0.0, 0.5], duration=2.0, phase=[0.0, 0.0, 0.0])
    table = dict(times=tr.t, pose=tr.pose, rate=tr.dpose, acc=tr.ddpose)
    rows = []
    for name in ("R", "rho", "M", "m_over_M", "d", "link_Ic", "g", "tol",
                 "max_iter", "cond_warn", "cond_max"):
        default = {"max_iter": 50, "tol": 1e-12, "cond_warn": 1e6,
                   "cond_max": 1e13}.get(name, 0.2)
        rows.append(("Model", rps3.Model, {name: default}, name, False))
    rows.append(("Model", rps3.Model, {"m": 0.09}, "m", False))
    rows.append(("Model", rps3.Model,
                 {"payload": {"mass": 0.05, "com": [0.0, 0.0, 0.01]}}, "payload", "mass"))
    rows.append(("Model", rps3.Model,
                 {"payload": {"com": [0.0, 0.0, 0.01]}}, "payload", "com"))
    rows.append(("Model", rps3.Model,
                 {"payload": {"inertia": [1e-4, 1e-4, 1e-4]}}, "payload", "inertia"))
    rows.append(("Model", rps3.Model, {"friction": {"viscous": 0.01}}, "friction", "viscous"))
    rows.append(("Model", rps3.Model, {"friction": {"coulomb": 0.01}}, "friction", "coulomb"))
    for key in ("viscous", "coulomb", "vreg"):
        rows.append(("Model", rps3.Model, {"prismatic_friction": {key: 0.01}},
                     "prismatic_friction", key))
    rows.append(("ik", model.ik, {"pose": tr.pose}, "pose", True))
    rows.append(("fk", model.fk, {"lengths": k.l, "guess": k.theta}, "lengths", True))
    rows.append(("fk", model.fk, {"lengths": k.l, "guess": k.theta}, "guess", True))
    for name in ("pose", "dpose", "ddpose"):
        rows.append(("inverse", model.inverse,
                     {"pose": tr.pose, "dpose": tr.dpose, "ddpose": tr.ddpose}, name, True))
    for name in ("radius", "pitch", "z0", "period", "blend"):
        rows.append(("helix", rps3.trajectory.helix,
                     {name: {"radius": 0.000266, "pitch": 0.03048, "z0": 0.3048,
                             "period": 10.0, "blend": 1.0}[name]}, name, False))
    rows.append(("helix", rps3.trajectory.helix, {"t": [0.0, 1.0, 2.0]}, "t", True))
    for name in ("mean", "amp", "freq", "phase"):
        rows.append(("sine", rps3.trajectory.sine, dict(sine), name, True))
    rows.append(("sine", rps3.trajectory.sine, dict(sine), "duration", False))
    rows.append(("sine", rps3.trajectory.sine, dict(sine, t=[0.0, 1.0]), "t", True))
    for name in ("times", "pose", "rate", "acc"):
        rows.append(("table", rps3.trajectory.table, dict(table), name, True))
    rows.append(("table", rps3.trajectory.table, dict(table, t=[0.0, 0.5]), "t", True))
    rows.append(("strerror", rps3.strerror, {"status": 1}, "status", False))
    return rows


NUMBER_ARGUMENTS = _number_arguments()


def test_number_arguments_cover_every_parameter():
    """The table above names every parameter of the public functions
    that takes numbers: a new one must be added to it."""
    import inspect
    # bodies: rps3.Body objects (tests/test_ident_std.py checks their numbers)
    words = {"effects", "method", "theta", "solver", "outputs", "warm_start",
             "model", "samples", "self", "bodies"}
    covered = {(f, a) for f, _, _, a, _ in NUMBER_ARGUMENTS}
    for fname, fn in (("Model", rps3.Model.__init__), ("ik", rps3.Model.ik),
                      ("fk", rps3.Model.fk), ("inverse", rps3.Model.inverse),
                      ("helix", rps3.trajectory.helix),
                      ("sine", rps3.trajectory.sine),
                      ("table", rps3.trajectory.table),
                      ("strerror", rps3.strerror)):
        for p in inspect.signature(fn).parameters:
            assert p in words or (fname, p) in covered, (fname, p)


def _bad_calls():
    for fname, fn, kw, name, kind in NUMBER_ARGUMENTS:
        good = kw[name] if name in kw else None
        if isinstance(kind, str):  # a key of a dict argument
            good = kw[name][kind]
        array = kind is True or isinstance(good, list)
        for bad_name, bad in (NOT_REAL_ARRAYS if array else NOT_REAL_SCALARS).items():
            if fname == "strerror" and bad_name == "decimal":
                continue
            value = bad(good)
            args = dict(kw)
            if isinstance(kind, str):
                args[name] = dict(kw[name], **{kind: value})
            else:
                args[name] = value
            yield pytest.param(fn, args, name, id=f"{fname}-{name}"
                               f"{'.' + kind if isinstance(kind, str) else ''}-{bad_name}")


@pytest.mark.parametrize("fn, kwargs, name", list(_bad_calls()))
def test_not_real_numbers_are_a_type_error_naming_the_argument(fn, kwargs, name):
    """A complex (even with a zero imaginary part), string, boolean or
    object value of a numeric argument raises TypeError naming the
    argument, instead of losing its imaginary part or being parsed."""
    with pytest.raises(TypeError) as err:
        fn(**kwargs)
    assert str(err.value).startswith(name + ":"), str(err.value)


def test_number_arguments_take_what_is_real():
    """The same arguments take numpy integers and floats, 0-d arrays,
    Fractions and integer arrays as the floats they are."""
    from fractions import Fraction
    a = rps3.Model(R=np.float32(0.25), rho=np.array(0.5), M=Fraction(9, 50),
                   max_iter=np.int64(40), payload=dict(com=np.array([0, 0, 1]) / 100))
    b = rps3.Model(R=0.25, rho=0.5, M=0.18, max_iter=40, payload=dict(com=[0, 0, 0.01]))
    assert (a.R, a.rho, a.M, a._c.opt.max_iter) == (b.R, b.rho, b.M, b._c.opt.max_iter)
    assert a._c.payload.com[2] == 0.01
    tr = _helix()
    ints = np.array([[0, 0, 1]] * 2, dtype=np.int16)  # alpha, beta 0; z_c 1 m
    assert same_bits(b.ik(ints).l, b.ik(ints.astype(float)).l)
    assert same_bits(b.inverse(tr.pose.astype(np.float32), tr.dpose, tr.ddpose).force,
                     b.inverse(tr.pose.astype(np.float32).astype(float), tr.dpose,
                               tr.ddpose).force)
    assert rps3.strerror(np.int32(1)) == rps3.strerror(1) == "pose unreachable"


def test_case_where_checks_its_values(config_runs):
    with h5py.File(config_runs["grid"][0], "r") as f:
        with pytest.raises(TypeError, match="^manipulator__rho: expected a real number"):
            rps3.h5io.case_where(f, manipulator__rho=0.3 + 1e-3j)
        with pytest.raises(KeyError, match="not a swept key"):
            rps3.h5io.case_where(f, force=0.3)
    with h5py.File(config_runs["closed_loop"][0], "r") as f:
        with pytest.raises(TypeError, match="takes names"):
            rps3.h5io.case_where(f, simulate__controller=1.0)


def test_import_needs_only_what_the_figures_install():
    """`make paper` installs analysis/requirements.txt alone (no xarray,
    no h5netcdf): importing the package and computing must not need them,
    nor matplotlib (rps3.plot and rps3.view load on first use)."""
    code = ("import sys\n"
            "for m in ('xarray', 'h5netcdf', 'matplotlib', 'yaml'):\n"
            "    sys.modules[m] = None  # importing it raises ImportError\n"
            "import rps3\n"
            "out = rps3.Model().inverse(*[getattr(rps3.trajectory.helix(samples=5), k)\n"
            "                             for k in ('pose', 'dpose', 'ddpose')])\n"
            "assert out.status.max() == 0\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True,
                          text=True)
    assert proc.returncode == 0, proc.stderr
