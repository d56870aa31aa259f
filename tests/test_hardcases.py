"""Hard cases through rps3-run (the C side is tests/test_hardcases.c).

Each scene drives the runner into a hard case and the file must say what
the library guarantees: finite numbers wherever status is 0, the warning
bit exactly where the condition number passes cond_warn, the singular case
recorded and the sweep going on, forces that scale as dimensional analysis
says, exact zeros for a massless mechanism.
"""

import math

import h5py
import numpy as np

from conftest import run, write_scene

SINE = """\
manipulator: {{R: {R!r}, rho: 0.5, M: 0.18, m: {m!r}, d: {d!r}, link_Ic: {Ic!r}}}
trajectory:
  kind: sine
  mean: [0.0, {beta!r}, {z!r}]
  amp: [0.7, {beta_amp!r}, {z_amp!r}]
  freq: [{f0!r}, {f1!r}, {f2!r}]
  phase: [0.3, 1.1, 0.0]
  duration: {T!r}
  samples: 201
solver: {{cond_warn: {cond_warn!r}}}
{sweep}"""


def sine(**kw):
    """A sine scene with Table II's mechanism; kw overrides the defaults."""
    v = dict(R=0.2286, m=0.09, d=0.1524, Ic=0.0, beta=0.3, z=0.28,
             beta_amp=0.1, z_amp=0.02, f0=0.7, f1=1.3, f2=0.9, T=2.0,
             cond_warn=1e6, sweep="")
    v.update(kw)
    return SINE.format(**v)


def load(path):
    with h5py.File(path, "r") as f:
        return {k: f[k][()] for k in ("force", "condition", "warn", "status",
                                      "failed_at", "energy_residual",
                                      "energy_scale", "force_by_effect")} | {
            "message": [m.decode() if isinstance(m, bytes) else m
                        for m in f["message"][()]]}


def test_beta_to_zero_finite_and_continuous(runner, tmp_path):
    """beta = 0 exactly, 1e-12, 1e-8, 1e-4 (alpha undefined at 0): every
    case ok and finite, and F(beta) - F(0) shrinks with beta (O(beta))."""
    scene = write_scene(tmp_path / "b0.yaml", sine(
        beta=0.0, beta_amp=0.0,
        sweep="sweep:\n  trajectory.mean[1]: [0.0, 1.0e-12, 1.0e-8, 1.0e-4]\n"))
    p = run(scene, tmp_path / "b0.h5", "-q")
    assert p.returncode == 0, p.stderr
    d = load(tmp_path / "b0.h5")
    assert (d["status"] == 0).all()
    assert np.isfinite(d["force"]).all()
    scale = np.abs(d["force"][0]).max()
    diff = [np.abs(d["force"][k] - d["force"][0]).max() / scale
            for k in range(1, 4)]
    # linear in beta with a slope of order one (per radian), plus rounding
    for dk, beta in zip(diff, (1e-12, 1e-8, 1e-4)):
        assert dk <= 10.0 * beta + 1e-13, (dk, beta)
    assert diff[2] > 1e-7  # the tilt does change the forces


def test_singular_approach_flags_and_records(runner, tmp_path):
    """A sweep of the tilt across the singular surface (beta ~ 0.92 rad at
    z = 0.3 m, alpha = 0.7 sin 0.3): the condition number rises smoothly to
    one peak and falls past it, the warning bit is set exactly where it
    passes cond_warn, and status-0 rows are finite.  A case at the
    singularity itself (cond > cond_max = 1e13) is recorded as ESING (4)
    with a message, and the sweep goes on (tests/test_hardcases.c reaches
    it exactly; here it is allowed, not required)."""
    betas = np.round(np.arange(0.5, 1.1, 0.0025), 6)
    scene = write_scene(tmp_path / "sing.yaml", sine(
        beta=0.5, beta_amp=0.0, z=0.3, z_amp=0.0, f0=0.0, cond_warn=50.0,
        sweep="sweep:\n  trajectory.mean[1]: [" +
        ", ".join(repr(float(b)) for b in betas) + "]\n"))
    p = run(scene, tmp_path / "sing.h5", "-q")
    assert p.returncode in (0, 1), p.stderr
    d = load(tmp_path / "sing.h5")
    ok = d["status"] == 0
    assert ok[0] and ok[-1]
    for c in np.flatnonzero(ok):
        assert np.isfinite(d["force"][c]).all()
        assert np.isfinite(d["condition"][c]).all()
        warned = (d["warn"][c] & 1) != 0
        assert (warned == (d["condition"][c] > 50.0)).all()
    for c in np.flatnonzero(~ok):
        assert d["status"][c] == 4 and d["failed_at"][c] >= 0
        assert d["message"][c]
    cond = np.array([d["condition"][c][0] if ok[c] else np.inf
                     for c in range(len(betas))])
    peak = int(np.argmax(cond))
    assert 0 < peak < len(betas) - 1
    assert cond[peak] > 1e3  # the sweep passes close to the surface
    assert (np.diff(cond[:peak + 1]) > 0).all()   # rises smoothly ...
    assert (np.diff(cond[peak:]) < 0).all()       # ... and falls past it
    assert (d["warn"][ok] & 1).any() and not (d["warn"][ok] & 1).all()


def test_forces_scale_with_R(runner, tmp_path):
    """R from 1 mm to 100 m with every length scaled and times scaled by
    sqrt(s) (Froude): accelerations keep their ratio to g, so every force
    is unchanged; the energy residual (a power) scales by sqrt(s)."""
    base = dict(R=0.2286, d=0.1524, z=0.28, z_amp=0.02, Ic=2e-4,
                f0=0.7, f1=1.3, f2=0.9, T=2.0)
    ref = None
    for R in (1e-3, 0.2286, 100.0):
        s = R / 0.2286
        ts = math.sqrt(s)
        scene = write_scene(tmp_path / f"R{R}.yaml", sine(
            R=R, d=base["d"] * s, z=base["z"] * s, z_amp=base["z_amp"] * s,
            Ic=base["Ic"] * s * s, f0=base["f0"] / ts, f1=base["f1"] / ts,
            f2=base["f2"] / ts, T=base["T"] * ts))
        p = run(scene, tmp_path / f"R{R}.h5", "-q")
        assert p.returncode == 0, p.stderr
        d = load(tmp_path / f"R{R}.h5")
        if ref is None:
            ref = d
            continue
        scale = np.abs(ref["force"]).max()
        # covariant computation: differences are rounding only
        np.testing.assert_allclose(d["force"], ref["force"], rtol=0,
                                   atol=1e-12 * scale)
        np.testing.assert_allclose(d["force_by_effect"],
                                   ref["force_by_effect"], rtol=0,
                                   atol=1e-12 * scale)


def test_zero_masses_give_zero_force(runner, tmp_path):
    """A massless mechanism needs no force: exactly 0, not a NaN."""
    scene = write_scene(tmp_path / "m0.yaml", sine(m=0.0).replace(
        "M: 0.18", "M: 0.0"))
    p = run(scene, tmp_path / "m0.h5", "-q")
    assert p.returncode == 0, p.stderr
    d = load(tmp_path / "m0.h5")
    assert (d["force"] == 0.0).all()
    assert (d["energy_residual"] == 0.0).all()
