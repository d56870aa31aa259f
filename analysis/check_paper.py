#!/usr/bin/env python3
"""Check an rps3-run file of configs/paper.yaml against what physics guarantees,
and measure the increase of the actuating forces due to link mass next to
the paper's "approximately 20 percent".

usage: check_paper.py OUT.h5 [--sweep LINK_MASS.h5]

Each check prints one PASS/FAIL line; the last line is "N passed, N failed"
and the exit status is 1 when a check failed.  With --sweep (the output of
configs/link_mass.yaml) it also prints how the increase moves with d, m/M
and rho, and checks how it must move.

The checks and their tolerances:
  - every case ok (status 0), no NaN;
  - energy: actuator power = d(T + P)/dt at every sample, |residual| <=
    1e-12 x the largest energy scale of the case (an identity, so rounding);
  - the shares of the effects sum to the force (1e-12 relative);
  - kinematics against an independent implementation here: the helix of
    Table I (phi with parabolic blends, alpha = -phi/2 + pi/2, cos beta =
    1 - 2 r*/r, z_c = z_i + h t/T*), x_c, y_c from (3)-(4) and the link
    lengths as |b_i - P_i| (1e-12 relative);
  - lengths follow z: the mean of the three lengths is the length of a level
    platform at height z_c up to r beta^2 (the tilt enters the mean at
    second order only, by symmetry);
  - the three forces are phase-shifted copies: by the 3-fold symmetry, a
    pose with alpha lowered by 2 pi/3 has the forces of the links permuted;
    on the constant-rate segment that is a shift of 6 s, F_i(t + 6 s) =
    F_{i+1}(t) up to the rise of z_c in those 6 s (0.018 m, 6 % of z_c),
    so the deviations from the three-link mean must agree to 10 % of their
    amplitude, and the other permutation must not;
  - link mass raises every force: F(m/M = 0.5) > F(m = 0) at every sample
    and link, and the difference is exactly the links' shares (the
    platform's shares do not depend on m).
"""

import argparse
import math
import sys

import h5py
import numpy as np
import yaml
from rps3 import h5io  # noqa: E402

PAPER_INCREASE = 0.20  # section VI: "increased by approximately 20 percent"
RTOL = 1e-12           # identities that hold up to rounding
PHASE_TOL = 0.10       # see the module docstring
SHIFT = 2 * math.pi / 3


class Checks:
    """PASS/FAIL lines and their count."""

    def __init__(self):
        self.passed = 0
        self.failed = 0

    def check(self, ok, what, detail):
        print(f"{'PASS' if ok else 'FAIL'}: {what}: {detail}")
        if ok:
            self.passed += 1
        else:
            self.failed += 1
        return ok


def scene_of(f, case):
    """The case's full scene (scene_resolved) as a dict."""
    return yaml.safe_load(h5io.text(f["scene_resolved"][case]))


# ---------------------------------------------------------- kinematics


def helix_pose(tr, t):
    """Table I with the errata: (alpha, beta, z_c) of the helix at times t."""
    T, ta = tr["period"], tr.get("blend", tr.get("blend_ratio", 0) * tr["period"])
    wmax = 2 * math.pi / (T - ta)          # peak phi rate (Table II)
    acc = wmax / ta
    phi = np.where(t < ta, 0.5 * acc * t**2,
                   np.where(t <= T - ta, wmax * (t - 0.5 * ta),
                            2 * math.pi - 0.5 * acc * (T - t) ** 2))
    return -phi / 2 + math.pi / 2, phi


def ball_joints(man, alpha, beta, z):
    """Ball joints b_i [time, link, xyz] and pins P_i of eqs. (1)-(4), (27)."""
    R, r = man["R"], man["rho"] * man["R"]
    psi = np.array([0, 2 * math.pi / 3, 4 * math.pi / 3])
    ca, sa, cb, sb = np.cos(alpha), np.sin(alpha), np.cos(beta), np.sin(beta)
    # Rz(alpha) Ry(beta) Rz(-alpha), eq. (1)-(2)
    rot = np.empty(alpha.shape + (3, 3))
    rot[..., 0, 0] = ca**2 * cb + sa**2
    rot[..., 0, 1] = ca * sa * (cb - 1)
    rot[..., 0, 2] = ca * sb
    rot[..., 1, 0] = ca * sa * (cb - 1)
    rot[..., 1, 1] = sa**2 * cb + ca**2
    rot[..., 1, 2] = sa * sb
    rot[..., 2, 0] = -ca * sb
    rot[..., 2, 1] = -sa * sb
    rot[..., 2, 2] = cb
    # centre, eqs. (3)-(4) times R
    c = np.stack([-0.5 * r * (1 - cb) * np.cos(2 * alpha),
                  0.5 * r * (1 - cb) * np.sin(2 * alpha), z], axis=-1)
    body = r * np.stack([np.cos(psi), np.sin(psi), np.zeros(3)], axis=-1)
    pins = R * np.stack([np.cos(psi), np.sin(psi), np.zeros(3)], axis=-1)
    b = c[..., None, :] + np.einsum("...jk,ik->...ij", rot, body)
    return b, pins, c


def check_kinematics(ck, f, case):
    """Helix, centre and lengths against the independent formulas above."""
    sc = scene_of(f, case)
    man, tr = sc["manipulator"], sc["trajectory"]
    R, r = man["R"], man["rho"] * man["R"]
    t = h5io.times(f)[case]
    alpha, beta, z = f["alpha"][case], f["beta"][case], f["z_c"][case]
    a_ref, _ = helix_pose(tr, t)
    b_ref = math.acos(1 - 2 * tr["radius"] / r)
    z_ref = tr["z0"] + tr["pitch"] * t / tr["period"]
    err = max(np.abs(alpha - a_ref).max(), np.abs(beta - b_ref).max())
    ck.check(err <= RTOL * math.pi, f"case {case}: helix pose (Table I)",
             f"max |alpha, beta - Table I| = {err:.3g} rad")
    err = np.abs(z - z_ref).max()
    ck.check(err <= RTOL * R, f"case {case}: z_c = z_i + h t/T*",
             f"max error {err:.3g} m")
    bj, pins, c = ball_joints(man, alpha, beta, z)
    err = max(np.abs(f["x_c"][case] - c[:, 0]).max(),
              np.abs(f["y_c"][case] - c[:, 1]).max(),
              np.abs(np.hypot(c[:, 0], c[:, 1]) - tr["radius"]).max())
    ck.check(err <= RTOL * R, f"case {case}: centre on the helix, (3)-(4)",
             f"max error {err:.3g} m")
    lengths = np.linalg.norm(bj - pins, axis=-1)
    err = np.abs(f["length"][case] - lengths).max()
    ck.check(err <= RTOL * R, f"case {case}: lengths = |b_i - P_i|, (5)-(7)",
             f"max error {err:.3g} m")
    level = np.hypot(R - r, z)
    err = np.abs(f["length"][case].mean(axis=1) - level).max()
    bound = r * b_ref**2
    ck.check(err <= bound, f"case {case}: lengths follow z_c",
             f"max |mean l_i - sqrt((R - r)^2 + z_c^2)| = {err:.3g} m "
             f"<= r beta^2 = {bound:.3g} m")


# ------------------------------------------------------------- dynamics


def check_dynamics(ck, f, case):
    """Energy balance and the sum of the effects."""
    res = np.abs(f["energy_residual"][case])
    scale = np.nanmax(f["energy_scale"][case])
    ck.check(res.max() <= RTOL * scale, f"case {case}: energy balance",
             f"max |residual| = {res.max():.3g} W, scale {scale:.3g} W")
    force = f["force"][case]
    err = np.abs(f["force_by_effect"][case].sum(axis=1) - force).max()
    ck.check(err <= RTOL * np.abs(force).max(),
             f"case {case}: effects sum to the force",
             f"max error {err:.3g} N")


def check_phase(ck, f, case):
    """F_i(t + 6 s) = F_{i+1}(t) on the constant-rate segment."""
    tr = scene_of(f, case)["trajectory"]
    t = h5io.times(f)[case]
    T = tr["period"]
    ta = tr.get("blend", tr.get("blend_ratio", 0) * T)
    wmax = 2 * math.pi / (T - ta)
    shift = SHIFT / (wmax / 2)             # alpha-dot = -phi-dot/2, eq. (38)
    dt = t[1] - t[0]
    n = int(round(shift / dt))
    if abs(n * dt - shift) > 1e-9 * shift:
        ck.check(False, f"case {case}: phase", "the shift is not on the grid")
        return
    seg = np.flatnonzero((t >= ta) & (t + shift <= T - ta))
    force = f["force"][case]
    dev = force - force.mean(axis=1, keepdims=True)
    amp = np.abs(dev).max()
    err = {p: max(np.abs(dev[seg + n, i] - dev[seg, (i + p) % 3]).max()
                  for i in range(3)) for p in (1, 2)}
    ck.check(err[1] <= PHASE_TOL * amp < err[2],
             f"case {case}: forces are phase-shifted copies",
             f"|F_i(t + {shift:g} s) - F_i+1(t)| (deviations from the mean) "
             f"= {err[1]:.3g} N <= {PHASE_TOL:g} x {amp:.3g} N; the other "
             f"order gives {err[2]:.3g} N")


# ----------------------------------------------------------- link mass


def increase(f0, f1):
    """The increase of f1 over f0 [time, link], by four measures."""
    return {
        "peak": np.abs(f1).max() / np.abs(f0).max() - 1,
        "rms": math.sqrt((f1**2).mean() / (f0**2).mean()) - 1,
        "mean": (f1 / f0 - 1).mean(),
        "max": (f1 / f0 - 1).max(),
        "min": (f1 / f0 - 1).min(),
    }


def check_link_mass(ck, f):
    """Link mass raises the forces, by exactly the links' shares."""
    c0 = h5io.case_where(f, manipulator__m_over_M=0.0)
    c1 = h5io.case_where(f, manipulator__m_over_M=0.5)
    f0, f1 = f["force"][c0], f["force"][c1]
    ck.check(bool((f1 > f0).all()), "link mass raises every force",
             f"min F(m/M = 0.5) - F(0) = {(f1 - f0).min():.3g} N")
    links = h5io.effect_sum(f, ("link_gravity", "link_inertia"), c1)
    err = np.abs(f1 - f0 - links).max()
    ck.check(err <= RTOL * np.abs(f1).max(),
             "the increase is the links' shares",
             f"max |F(0.5) - F(0) - links| = {err:.3g} N")
    return c0, c1


def level_estimate(sc):
    """Increase at the level pose at z_i: 3 (m/M) (d/l) cos^2 theta.

    Statics of a level platform: each link carries M g / 3 of the platform
    plus, through the ball joint, the part of its own weight its pin does not
    take: a moment balance about the pin gives a force m g d cos(theta) / l
    normal to the link at the ball joint, whose vertical share must be
    carried along the links too.  Then F = M g / (3 sin theta) +
    m g d cos^2(theta) / (l sin theta), and the ratio of the two terms is
    3 (m/M) (d/l) cos^2(theta).
    """
    man, tr = sc["manipulator"], sc["trajectory"]
    R, r = man["R"], man["rho"] * man["R"]
    length = math.hypot(R - r, tr["z0"])
    cos_t = (R - r) / length
    m_over_M = man["m_over_M"] if "m_over_M" in man else man["m"] / man["M"]
    return 3 * m_over_M * man["d"] / length * cos_t**2, length, math.degrees(
        math.acos(cos_t))


def report_increase(f, c0, c1):
    """Print the measured increase next to the paper's figure."""
    inc = increase(f["force"][c0], f["force"][c1])
    sc = scene_of(f, c1)
    est, length, theta = level_estimate(sc)
    grav = h5io.effect_sum(f, ("link_gravity",), c1)
    iner = h5io.effect_sum(f, ("link_inertia",), c1)
    plat_in = h5io.effect_sum(f, h5io.INERTIA_EFFECTS, c1)
    f0 = f["force"][c0]
    print()
    print("Increase of the actuating forces due to link mass "
          "(m/M = 0.5 over m = 0):")
    print(f"  peak |F| over time and links  {100 * inc['peak']:6.2f} %"
          "   (max|F(0.5)| / max|F(0)| - 1)")
    print(f"  RMS of F over time and links  {100 * inc['rms']:6.2f} %")
    print(f"  pointwise F(0.5)/F(0) - 1     {100 * inc['mean']:6.2f} % mean, "
          f"{100 * inc['min']:.2f} .. {100 * inc['max']:.2f} %")
    print(f"  paper, section VI             {100 * PAPER_INCREASE:6.2f} %"
          "   (\"approximately\", read from its Figs. 3-4)")
    print(f"  level-pose statics at z_i     {100 * est:6.2f} %"
          f"   (3 (m/M)(d/l) cos^2 theta, l = {length:.4f} m, "
          f"theta = {theta:.1f} deg)")
    print(f"  of which link weight          {100 * np.abs(grav / f0).max():6.2f} %"
          f" at most; link inertia {np.abs(iner / f0).max():.2g}, all inertia "
          f"{np.abs(plat_in / f0).max():.2g} of F(0)")
    man = sc["manipulator"]
    need = PAPER_INCREASE / inc["peak"]
    print(f"  20 % at the peak would need m/M = {0.5 * need:.2f} or "
          f"d = {man['d'] * need:.3f} m (linear in m/M, and in d up to the "
          f"tiny link inertia; "
          f"the links are {length:.3f} m long)")
    return inc


def report_sweep(ck, path):
    """How the increase moves with d, m/M and rho (configs/link_mass.yaml)."""
    with h5py.File(path, "r") as f:
        bad = h5io.failed(f)
        ck.check(not bad, f"{path}: every case ok", f"{len(bad)} failed")
        sv = h5io.sweep_values(f)
        d, mm, rho = (sv[k] for k in ("manipulator.d", "manipulator.m_over_M",
                                      "manipulator.rho"))
        force = f["force"][()]
        ds, ms, rs = np.unique(d), np.unique(mm), np.unique(rho)
        if ms[0] != 0:
            ck.check(False, "sweep", "m/M = 0 missing: no reference")
            return
        table = {}
        for dv in ds:
            for rv in rs:
                ref = np.flatnonzero((d == dv) & (rho == rv) & (mm == 0))[0]
                for mv in ms[1:]:
                    c = np.flatnonzero((d == dv) & (rho == rv) & (mm == mv))[0]
                    table[dv, mv, rv] = increase(force[ref], force[c])
    print()
    print("Peak-force increase due to link mass [%] (configs/link_mass.yaml):")
    print("  d [m]   m/M  " + "".join(f"  rho={rv:<5g}" for rv in rs))
    for dv in ds:
        for mv in ms[1:]:
            print(f"  {dv:<7g} {mv:<5g}" +
                  "".join(f"  {100 * table[dv, mv, rv]['peak']:9.2f}"
                          for rv in rs))
    # linear in m/M: pointwise increases scale exactly with m (F = F0 + m G)
    lin = max(abs(table[dv, mv, rv]["mean"] / mv -
                  table[dv, ms[-1], rv]["mean"] / ms[-1])
              for dv in ds for mv in ms[1:] for rv in rs)
    ck.check(lin <= 1e-9, "increase is linear in m/M",
             f"max spread of (mean increase)/(m/M) = {lin:.3g}")
    up_d = all(table[ds[i], mv, rv]["mean"] < table[ds[i + 1], mv, rv]["mean"]
               for i in range(len(ds) - 1) for mv in ms[1:] for rv in rs)
    ck.check(up_d, "increase grows with d", "at every m/M and rho")
    down_rho = all(table[dv, mv, rs[i]]["mean"] > table[dv, mv, rs[i + 1]]["mean"]
                   for i in range(len(rs) - 1) for dv in ds for mv in ms[1:])
    ck.check(down_rho, "increase falls as rho grows",
             "links stand steeper, their weight loads the actuators less")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("h5", help="rps3-run output of configs/paper.yaml")
    ap.add_argument("--sweep", help="rps3-run output of configs/link_mass.yaml")
    args = ap.parse_args(argv)
    ck = Checks()
    with h5py.File(args.h5, "r") as f:
        bad = h5io.failed(f)
        ck.check(not bad, "every case ok", f"failed: {bad}" if bad else
                 f"{f['status'].shape[0]} cases")
        nan = int(np.isnan(f["force"][()]).sum())
        ck.check(nan == 0, "no NaN in force", f"{nan} NaN")
        for case in range(f["status"].shape[0]):
            check_dynamics(ck, f, case)
            check_kinematics(ck, f, case)
            check_phase(ck, f, case)
        c0, c1 = check_link_mass(ck, f)
        report_increase(f, c0, c1)
    if args.sweep:
        report_sweep(ck, args.sweep)
    print()
    print(f"{ck.passed} passed, {ck.failed} failed")
    return 1 if ck.failed else 0


if __name__ == "__main__":
    sys.exit(main())
