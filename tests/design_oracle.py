"""A brute-force reference of the design indices, in numpy, from the
paper's geometry alone (no library call): the tests of rps3.design hold
the library's fast evaluation to it (tests/test_design_opt.py).

Where the library has one closed form per quantity, this module takes
another route wherever one exists:

- the link lengths from the paper's scalar equations (5)-(7) as printed,
  in units of R, with the parasitic centre (3)-(4); the ball joints from
  the vector form b_i = c + Rz(alpha) Ry(beta) Rz(-alpha) r_i, and the two
  are checked against each other (`check_lengths`);
- the link angles theta_i from (12)-(14): X_bi along the pin's radial
  direction is R - l_i cos(theta_i), Z_bi = l_i sin(theta_i);
- the platform twists that each index needs from a null space (SVD) of
  the stacked wrenches of the legs, not from a formula for the twist;
- the Jacobian of the homogeneous condition number by central
  differences of the lengths, not by its analytic derivative;
- the summaries by plain loops over the grid's points.
"""

from __future__ import annotations

import numpy as np

SQ3 = np.sqrt(3.0)
# the pins' directions, 0, 120 and 240 degrees from X (Fig. 1)
PSI = np.array([0.0, 2 * np.pi / 3, 4 * np.pi / 3])
RADIAL = np.stack([np.cos(PSI), np.sin(PSI), np.zeros(3)], axis=1)
# the pin axes phi_zi of (30): normal to each leg's plane
AXIS = np.stack([-np.sin(PSI), np.cos(PSI), np.zeros(3)], axis=1)


def rot(alpha, beta):
    """Rz(alpha) Ry(beta) Rz(-alpha), the Z-Y-Z Euler angles with the spin
    gamma = -alpha of (2)."""
    ca, sa, cb, sb = np.cos(alpha), np.sin(alpha), np.cos(beta), np.sin(beta)
    Rz = np.array([[ca, -sa, 0], [sa, ca, 0], [0, 0, 1]])
    Ry = np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
    return Rz @ Ry @ Rz.T


def centre(R, rho, pose):
    """(x_c, y_c, z_c) [m] of (3)-(4)."""
    a, b, z = pose
    Xc = -0.5 * rho * (1 - np.cos(b)) * np.cos(2 * a)
    Yc = 0.5 * rho * (1 - np.cos(b)) * np.sin(2 * a)
    return np.array([R * Xc, R * Yc, z])


def lengths_printed(R, rho, pose):
    """l_i [m] from (5)-(7) as printed, in units of R."""
    a, b, z = pose
    c = centre(R, rho, pose) / R
    X, Y, Z = c
    Ca, Sa, Cb, Sb = np.cos(a), np.sin(a), np.cos(b), np.sin(b)
    S2a = np.sin(2 * a)
    base = 1 + rho**2 + X**2 + Y**2 + Z**2
    L1 = (base - 2 * X + 2 * rho * (Ca**2 * Cb + Sa**2) * (X - 1)
          + rho * (Cb - 1) * S2a * Y - 2 * rho * Sb * Ca * Z)
    u = Ca**2 * Cb + Sa**2
    v = Ca * Sa * (Cb - 1)
    w = Sa**2 * Cb + Ca**2
    L2 = (base + X - SQ3 * Y - rho * (u - SQ3 * v) * (X + 0.5)
          - rho * (v - SQ3 * w) * (Y - SQ3 / 2) + rho * Sb * (Ca - SQ3 * Sa) * Z)
    L3 = (base + X + SQ3 * Y - rho * (u + SQ3 * v) * (X + 0.5)
          - rho * (v + SQ3 * w) * (Y + SQ3 / 2) + rho * Sb * (Ca + SQ3 * Sa) * Z)
    return R * np.sqrt(np.array([L1, L2, L3]))


def legs(R, rho, pose):
    """The vector geometry of one pose: pins P (3, 3), balls b (3, 3),
    centre c, rotation Q, link unit vectors u (3, 3), lengths l, angles
    theta from (12)-(14)."""
    a, b, _ = pose
    Q = rot(a, b)
    c = centre(R, rho, pose)
    P = R * RADIAL
    balls = c + (Q @ (rho * R * RADIAL).T).T
    v = balls - P
    length = np.linalg.norm(v, axis=1)
    # (12)-(14): the ball's radial coordinate is R - l cos(theta)
    radial = np.einsum("ij,ij->i", balls, RADIAL)
    theta = np.arctan2(balls[:, 2], R - radial)
    return dict(P=P, b=balls, c=c, Q=Q, u=v / length[:, None], l=length,
                theta=theta)


def check_lengths(R, rho, pose):
    """max |(5)-(7) - |b_i - P_i|| [m]: the two routes agree."""
    return float(np.max(np.abs(lengths_printed(R, rho, pose)
                               - legs(R, rho, pose)["l"])))


def lengths_jacobian(R, rho, pose, h=1e-6):
    """dl/d(alpha, beta, z_c), (3, 3), by central differences of (5)-(7)."""
    J = np.empty((3, 3))
    for k in range(3):
        e = np.zeros(3)
        e[k] = h
        J[:, k] = (lengths_printed(R, rho, np.asarray(pose) + e)
                   - lengths_printed(R, rho, np.asarray(pose) - e)) / (2 * h)
    return J


# ------------------------------------------------------------------ design
# The flags of a pose, as docs/design.md names them (bit k = 1 << k)
STROKE, PIN, BALL, INTERFERE, ASSEMBLY, SINGULAR = 1, 2, 4, 8, 16, 32
# the singular flag: the homogeneous condition number above cond_sing
# (rps3_design_opts' default), or G exactly singular
COND_SING = 1e8


def mass_model(ds):
    """m, d, link_Ic of a design's links: an actuator body (a point at
    actuator_d) and a uniform rod from the pin to l_max."""
    rod = ds["link_density"] * ds["l_max"]
    m = ds["actuator_mass"] + rod
    if m == 0:
        return 0.0, 0.0, 0.0
    d = (ds["actuator_mass"] * ds["actuator_d"] + rod * ds["l_max"] / 2) / m
    Ic = (rod * ds["l_max"]**2 / 12 + rod * (ds["l_max"] / 2 - d)**2
          + ds["actuator_mass"] * (ds["actuator_d"] - d)**2)
    return m, d, Ic


def segment_distance(p0, p1, q0, q1, n=201, iters=45):
    """Least distance between the segments p0-p1 and q0-q1, by search:
    the distance from the point at s on p to the segment q (its nearest
    t in closed form, clamped) is convex in s; sampled at n values of s,
    then a ternary search around the least sample."""
    dp, dq = p1 - p0, q1 - q0

    def at(s):
        p = p0 + np.multiply.outer(s, dp)
        t = np.clip((p - q0) @ dq / np.dot(dq, dq), 0.0, 1.0)
        return np.linalg.norm(p - (q0 + np.multiply.outer(t, dq)), axis=-1)

    s = np.linspace(0.0, 1.0, n)
    k = int(np.argmin(at(s)))
    lo, hi = s[max(k - 1, 0)], s[min(k + 1, n - 1)]
    for _ in range(iters):
        a, b = lo + (hi - lo) / 3, hi - (hi - lo) / 3
        if at(np.array(a)) < at(np.array(b)):
            hi = b
        else:
            lo = a
    return float(min(at(np.array(0.5 * (lo + hi))), at(s).min()))


def wrench_rows(R, rho, pose, L=1.0):
    """The six unit wrenches on the platform, rows (f, (b_i - c) x f / L):
    rows 0-2 along the links (transmission), 3-5 along the pin axes
    (constraint), each a pure force through its ball joint."""
    g = legs(R, rho, pose)
    rows = []
    for f in (g["u"], AXIS):
        for i in range(3):
            rows.append(np.concatenate([f[i], np.cross(g["b"][i] - g["c"], f[i]) / L]))
    return np.array(rows), g


def pose_indices(ds, pose, L=None):
    """Every per-pose output of rps3_design_eval for one pose, brute force:
    a dict of flags, l, theta, ball, clearance, lti, oti, cti, cond_h,
    transmission, c, spin."""
    R, rho = ds["R"], ds["rho"]
    pose = np.asarray(pose, float)
    G, g = wrench_rows(R, rho, pose)
    out = dict(l=g["l"], theta=g["theta"], c=g["c"])
    if np.any(g["b"][:, 2] <= 0) or np.any(g["l"] <= 0):
        nan3 = np.full(3, np.nan)
        return dict(flags=ASSEMBLY, l=nan3, theta=nan3, ball=nan3, c=nan3,
                    clearance=np.nan, lti=np.nan, oti=np.nan, cti=np.nan,
                    cond_h=np.nan, transmission=np.nan, spin=np.nan)
    normal = g["Q"][:, 2]
    out["ball"] = np.arccos(np.clip(g["u"] @ normal, -1, 1))
    out["spin"] = np.arctan2(g["Q"][1, 0], g["Q"][0, 0])
    dist = min(segment_distance(g["P"][i], g["b"][i], g["P"][j], g["b"][j])
               for i, j in ((0, 1), (1, 2), (2, 0)))
    out["clearance"] = dist - 2 * ds["link_radius"]
    # output twist of row k: the platform twist every other row is
    # reciprocal to, from the null space of the other five rows
    eta = np.empty(6)
    for k in range(6):
        others = np.delete(G, k, axis=0)
        _, s, Vt = np.linalg.svd(others)
        t = Vt[-1]
        # [f, m] . [v_c, omega]; scale so that row k's product is 1
        prod = G[k] @ t
        if abs(prod) < 1e-14 * np.linalg.norm(t):
            eta[k] = 0.0
            continue
        t = t / prod
        v = t[:3] + np.cross(t[3:], g["b"][k % 3] - g["c"])
        eta[k] = 1.0 / np.linalg.norm(v)
    out["oti"], out["cti"] = eta[:3].min(), eta[3:].min()
    out["lti"] = min(1.0, out["oti"], out["cti"])
    Lh = rho * R if L is None else L
    Gh = G.copy()
    Gh[:, 3:] /= Lh
    # Frobenius norms from the eigenvalues of Gh^T Gh (the squared
    # singular values): |Gh|_F^2 = sum ev, |Gh^-1|_F^2 = sum 1/ev
    ev = np.linalg.eigvalsh(Gh.T @ Gh)
    out["cond_h"] = (np.sqrt(np.sum(ev) * np.sum(1 / ev)) / 6
                     if ev[0] > 0 else np.inf)
    # the static load path: the forces along the links and the pins hold a
    # platform wrench w = (f, n) about c: G^T (F, C) = w
    scale = np.array([1, 1, 1, R, R, R])
    try:
        A = np.linalg.inv(G.T)
        out["transmission"] = np.max(np.abs(A[:3]) @ scale)
    except np.linalg.LinAlgError:
        out["transmission"] = np.inf
    flags = 0
    if np.any(g["l"] < ds["l_min"]) or np.any(g["l"] > ds["l_max"]):
        flags |= STROKE
    if np.any(g["theta"] < ds["theta_min"]) or np.any(g["theta"] > ds["theta_max"]):
        flags |= PIN
    if np.any(out["ball"] > ds["ball_max"]):
        flags |= BALL
    if ds["link_radius"] > 0 and out["clearance"] < 0:
        flags |= INTERFERE
    if not out["cond_h"] <= COND_SING:
        flags |= SINGULAR
    out["flags"] = flags
    return out


def margins(ds, res):
    """How far the pose is from flipping a flag (the least relative
    distance to a limit): the tests leave out the poses within rounding of
    a limit, where the library and the oracle may round apart."""
    if res["flags"] & ASSEMBLY:
        return np.inf
    m = [np.min(np.abs(res["l"] - ds["l_min"])) / ds["l_max"],
         np.min(np.abs(res["l"] - ds["l_max"])) / ds["l_max"],
         np.min(np.abs(res["theta"] - ds["theta_min"])),
         np.min(np.abs(res["theta"] - ds["theta_max"])),
         np.min(np.abs(res["ball"] - ds["ball_max"]))]
    if ds["link_radius"] > 0:
        m.append(abs(res["clearance"]) / ds["l_max"])
    return min(m)


def grid_poses(lo, hi, n):
    """The cell-centred grid of rps3_design_grid, alpha fastest, written
    as three nested loops; and the cell volume."""
    poses = []
    for i2 in range(n[2]):
        for i1 in range(n[1]):
            for i0 in range(n[0]):
                idx = (i0, i1, i2)
                poses.append([lo[k] + (idx[k] + 0.5) * (hi[k] - lo[k]) / n[k]
                              for k in range(3)])
    cell = 1.0
    for k in range(3):
        cell *= (hi[k] - lo[k]) / n[k]
    return np.array(poses), cell


def summary(ds, poses, cell, lti_good=0.7):
    """The summary of rps3_design_eval by a loop over the poses."""
    rows = [pose_indices(ds, p) for p in poses]
    reach = [r for r in rows if r["flags"] == 0]
    out = dict(n=len(rows), nreach=len(reach))
    out["reach_fraction"] = len(reach) / len(rows)
    out["volume"] = len(reach) * cell
    if reach:
        lti = np.array([r["lti"] for r in reach])
        out["gti"] = float(np.mean(lti))
        out["good_fraction"] = float(np.mean(lti >= lti_good))
        out["lti_min"] = float(lti.min())
        out["cond_h_max"] = max(r["cond_h"] for r in reach)
        out["xc_max"] = max(abs(r["c"][0]) for r in reach)
        out["yc_max"] = max(abs(r["c"][1]) for r in reach)
        out["spin_max"] = max(abs(r["spin"]) for r in reach)
        out["l_lo"] = min(r["l"].min() for r in reach)
        out["l_hi"] = max(r["l"].max() for r in reach)
    out["nflag"] = [sum(1 for r in rows if r["flags"] & (1 << k))
                    for k in range(6)]
    return out, rows


# -------------------------------------------------------------------- task
# The inverse dynamics of a design's model by Lagrange's equations in the
# pose coordinates q = (alpha, beta, z_c), every derivative by central
# differences: the mass matrix M(q) from the bodies' velocity Jacobians,
# the velocity terms from dM/dq, and the forces from the virtual work of
# the actuators, J_l^T F = Q (J_l = dl/dq).  No multiplier, no closed
# form of the library's.

H_JAC = 1e-5   # step of the position Jacobians [rad, m]
H_MASS = 1e-4  # step of dM/dq: the Jacobians' rounding (1e-16 / H_JAC)
               # over it stays near 1e-7 of M


def _bodies(ds, q):
    """Positions of one pose: platform centre, rotation, payload point,
    link angles, link lengths."""
    g = legs(ds["R"], ds["rho"], q)
    pay = g["c"] + g["Q"] @ np.array([0.0, 0.0, ds["payload_height"]])
    return g["c"], g["Q"], pay, g["theta"], g["l"]


def _jac(fun, q, h=H_JAC):
    q = np.asarray(q, float)
    cols = []
    for k in range(3):
        e = np.zeros(3)
        e[k] = h
        cols.append((np.asarray(fun(q + e)) - np.asarray(fun(q - e))) / (2 * h))
    return np.stack(cols, axis=-1)


def _vee(S):
    return 0.5 * np.array([S[2, 1] - S[1, 2], S[0, 2] - S[2, 0], S[1, 0] - S[0, 1]])


def mass_matrix(ds, q, link_mass=True):
    M, r = ds["M"], ds["rho"] * ds["R"]
    m, d, Ic = mass_model(ds)
    Jc = _jac(lambda x: _bodies(ds, x)[0], q)
    Jp = _jac(lambda x: _bodies(ds, x)[2], q)
    Jt = _jac(lambda x: _bodies(ds, x)[3], q)
    Q = _bodies(ds, q)[1]
    dQ = _jac(lambda x: _bodies(ds, x)[1], q)          # (3, 3, 3): [.., .., k]
    Jw = np.stack([_vee(Q.T @ dQ[:, :, k]) for k in range(3)], axis=1)
    Ib = np.diag([M * r**2 / 4, M * r**2 / 4, M * r**2 / 2])
    out = M * Jc.T @ Jc + Jw.T @ Ib @ Jw + ds["payload"] * Jp.T @ Jp
    if link_mass:
        out = out + (m * d**2 + Ic) * Jt.T @ Jt
    return out


def potential(ds, q, link_mass=True):
    c, _, pay, theta, _ = _bodies(ds, q)
    m, d, _ = mass_model(ds)
    V = ds["g"] * (ds["M"] * c[2] + ds["payload"] * pay[2])
    if link_mass:
        V += ds["g"] * m * d * np.sum(np.sin(theta))
    return V


def forces(ds, q, qd, qdd, link_mass=True):
    """F (3,) [N] at one state, and dl/dt (3,) [m/s]."""
    q, qd, qdd = (np.asarray(x, float) for x in (q, qd, qdd))
    Mq = mass_matrix(ds, q, link_mass)
    dM = _jac(lambda x: mass_matrix(ds, x, link_mass), q, H_MASS)  # [j, k, l]
    cor = (np.einsum("jkl,k,l->j", dM, qd, qd)
           - 0.5 * np.einsum("klj,k,l->j", dM, qd, qd))
    G = _jac(lambda x: np.atleast_1d(potential(ds, x, link_mass)), q)[0]
    Qgen = Mq @ qdd + cor + G
    Jl = _jac(lambda x: _bodies(ds, x)[4], q)
    return np.linalg.solve(Jl.T, Qgen), Jl @ qd


def task(ds, pose, dpose, ddpose, link_mass=True):
    """Peak and RMS force, peak power and rate per link over the states."""
    F, dl = zip(*(forces(ds, *s, link_mass=link_mass)
                  for s in zip(pose, dpose, ddpose)))
    F, dl = np.array(F), np.array(dl)
    return dict(F_peak=np.max(np.abs(F), axis=0),
                F_rms=np.sqrt(np.mean(F**2, axis=0)),
                P_peak=np.max(np.abs(F * dl), axis=0),
                v_peak=np.max(np.abs(dl), axis=0), F=F, dl=dl)
