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
from conftest import CONFIGS, ROOT, run

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
    """forces="lean" (the library's RPS3_FORCES_LEAN, certify off) gives the
    default path's forces to rounding (the C tests hold it to 8 eps cond of
    the force scale; the paper's effects along a sine stay far from any
    singular pose, cond < 1e3), NaN for what it does not compute, and the
    same statuses."""
    effects = list(rps3.DEFAULT_EFFECTS)
    full = rps3.Model(effects=effects, certify=False)
    lean = rps3.Model(effects=effects, certify=False, forces="lean")
    tr = sine_points(full, 500)
    a = full.inverse(tr.pose, tr.dpose, tr.ddpose)
    b = lean.inverse(tr.pose, tr.dpose, tr.ddpose)
    assert np.all(a.status == 0) and np.all(b.status == 0)
    scale = np.max(np.abs(a.force))
    assert np.max(a.condition) < 1e3
    np.testing.assert_allclose(b.force, a.force, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(b.condition, a.condition, rtol=1e-12)
    assert np.all(np.isnan(b.transmission)) and np.all(np.isnan(b.theta))


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


# -------------------------------------------------------------- bad input

@pytest.mark.parametrize("kwargs, name", [
    (dict(rho=-0.5), "rho"),
    (dict(R=float("nan")), "R"),
    (dict(R="wide"), "R"),
    (dict(m_over_M=-1.0), "m_over_M"),
    (dict(m=0.1, m_over_M=0.5), "m_over_M"),
    (dict(effects=["platform_gravity", "gravity"]), "effects"),
    (dict(effects="link_gravity"), "effects"),
    (dict(effects=["link_gravity", "link_gravity"]), "effects"),
    (dict(method="euler"), "method"),
    (dict(theta="numeric"), "theta"),
    (dict(forces="some"), "forces"),
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
    static = rps3.Model(effects=["platform_gravity"], certify=False)
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
