"""An independent regressor of the 3-RPS's actuator forces, F = Y(q, qd, qdd) pi,
for identification (docs/identification.md; tests/test_ident.py).

Built here with numpy from the geometry alone, without rps3's kinematics or
dynamics:

- The pose (alpha, beta, z_c) is carried as a truncated Taylor series in
  time (`Jet`: value, rate, acceleration, jerk coefficients), and every
  kinematic quantity is computed from it by Taylor arithmetic, so rates
  and accelerations are exact to rounding, not finite differences.
- Geometry: pins at P_i = R (cos phi_i, sin phi_i, 0), phi_i = 0, 2pi/3,
  4pi/3, axes t_i = (-sin phi_i, cos phi_i, 0) (tangent); platform
  orientation Rz(alpha) Ry(beta) Rz(-alpha) (the paper's (2)); centre
  (x_c, y_c) from the condition that ball joints 1 and 2 stay in their
  pins' vertical planes, (c + rot r_i) . t_i = 0 (not from (3)-(4), which
  tests/test_ident.py checks it against, with joint 3's plane); ball joints
  b_i = c + rot r_i, r_i = rho R (cos phi_i, sin phi_i, 0); l_i = |b_i - P_i|,
  u_i = (b_i - P_i) / l_i = -cos theta_i e_r + sin theta_i K.
- Bodies, each with its frame (origin, axes) and the 10 standard
  parameters (m, m c, I about the origin) in that frame, in rps3.ident's
  order: the platform (origin the centre, axes x to ball joint 1, z the
  normal), then per leg i the cylinder (origin the pin P_i, axes
  e1 = u_i along the link towards the platform, e2 = t_i the pin axis,
  e3 = e1 x e2) and the piston (origin the ball joint b_i, the cylinder's
  axes: it slides in the cylinder without turning in it).
- Each body's wrench about its origin, in body axes, is linear in its 10
  parameters (Newton-Euler about a moving origin):
      f = m (a_o - g) + domega x h + omega x (omega x h)
      n = I domega + omega x (I omega) + h x (a_o - g)
  with h = m c, g = (0, 0, -g) in body axes.  Virtual power maps it to the
  pose coordinates, Q = sum_b Jv_b^T f_b + Jw_b^T n_b (Jv_b, Jw_b: the
  body's origin velocity and angular velocity per unit pose rate, from the
  Taylor arithmetic with unit rates), and the closed chain to the actuator
  forces, Jl^T (F - f_prism) = Q + Jtheta^T tau_pin, Jl = d l / d pose,
  Jtheta = d theta / d pose, with the friction the actuators must overcome
  f_prism_i = fv_i l_i' + fc_i s(l_i') and tau_pin_i = fv_i theta_i' +
  fc_i s(theta_i') (s = sign, or tanh(v / vreg)).

`energy_rows` gives the kinetic and potential energy and their rates
(linear in pi too) for the power balance F . l' = dT/dt + dP/dt +
friction power, computed from the energies, not from the wrenches.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from rps3 import ident

PHI = np.array([0.0, 2.0 * np.pi / 3.0, 4.0 * np.pi / 3.0])


# ------------------------------------------------------- Taylor arithmetic

class Jet:
    """A truncated Taylor series in time: c[k] is the k-th coefficient
    (f^(k) / k!), trailing axes the array's shape."""

    def __init__(self, c):
        self.c = np.asarray(c, float)

    @property
    def order(self):
        return self.c.shape[0] - 1

    @staticmethod
    def const(x, order):
        x = np.asarray(x, float)
        c = np.zeros((order + 1,) + x.shape)
        c[0] = x
        return Jet(c)

    def _lift(self, other):
        # truncate to the common order and pad the trailing shapes on the
        # left, so that (K+1, n, 3) and (K+1, 3) or (K+1,) broadcast
        if not isinstance(other, Jet):
            other = Jet.const(other, self.order)
        k = min(self.order, other.order)
        a, b = self.c[:k + 1], other.c[:k + 1]
        nd = max(a.ndim, b.ndim)
        a = a.reshape(a.shape[:1] + (1,) * (nd - a.ndim) + a.shape[1:])
        b = b.reshape(b.shape[:1] + (1,) * (nd - b.ndim) + b.shape[1:])
        return Jet(a), Jet(b)

    def __add__(self, other):
        a, b = self._lift(other)
        return Jet(a.c + b.c)

    __radd__ = __add__

    def __neg__(self):
        return Jet(-self.c)

    def __sub__(self, other):
        a, b = self._lift(other)
        return Jet(a.c - b.c)

    def __rsub__(self, other):
        return (-self) + other

    def __mul__(self, other):
        if not isinstance(other, Jet):
            x = np.asarray(other, float)
            return Jet(self.c * x.reshape((1,) * max(0, self.c.ndim - 1 - x.ndim) + x.shape))
        a, b = self._lift(other)
        return Jet(np.stack([sum(a.c[j] * b.c[k - j] for j in range(k + 1))
                             for k in range(a.order + 1)]))

    __rmul__ = __mul__

    def __truediv__(self, other):
        if not isinstance(other, Jet):
            return self * (1.0 / np.asarray(other, float))
        a, b = self._lift(other)
        q = []
        for k in range(a.order + 1):
            q.append((a.c[k] - sum(b.c[j] * q[k - j] for j in range(1, k + 1)))
                     / b.c[0])
        return Jet(np.stack(q))

    def __getitem__(self, idx):
        idx = idx if isinstance(idx, tuple) else (idx,)
        return Jet(self.c[(slice(None),) + idx])

    def sum(self, axis):
        return Jet(self.c.sum(axis=axis if axis < 0 else axis + 1))

    def deriv(self):
        """The series of the time derivative (one order less)."""
        k = np.arange(1, self.order + 1).reshape((-1,) + (1,) * (self.c.ndim - 1))
        return Jet(self.c[1:] * k)

    def value(self, k=0):
        """The k-th time derivative's value."""
        return self.c[k] * float(np.prod(np.arange(1, k + 1)))

    def sqrt(self):
        s = [np.sqrt(self.c[0])]
        for k in range(1, self.order + 1):
            s.append((self.c[k] - sum(s[j] * s[k - j] for j in range(1, k)))
                     / (2.0 * s[0]))
        return Jet(np.stack(s))

    def sincos(self):
        s, c = [np.sin(self.c[0])], [np.cos(self.c[0])]
        for k in range(1, self.order + 1):
            s.append(sum(j * self.c[j] * c[k - j] for j in range(1, k + 1)) / k)
            c.append(-sum(j * self.c[j] * s[k - j] for j in range(1, k + 1)) / k)
        return Jet(np.stack(s)), Jet(np.stack(c))


def stack(jets, axis=-1):
    """Jets of one shape stacked along a new trailing-shape axis."""
    return Jet(np.stack([j.c for j in jets], axis=axis if axis < 0 else axis + 1))


def atan2(y, x):
    """atan2 of two series: theta' = (x y' - y x') / (x^2 + y^2),
    integrated term by term."""
    w = (x * y.deriv() - y * x.deriv()) / (x * x + y * y)
    k = np.arange(1, w.order + 2).reshape((-1,) + (1,) * (w.c.ndim - 1))
    return Jet(np.concatenate([np.arctan2(y.c[0], x.c[0])[None], w.c / k]))


def dot(a, b):
    return (a * b).sum(-1)


def cross(a, b):
    return stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                  a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                  a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]])


def matT_vec(A, v):
    """A^T v for (..., 3, 3) A and (..., 3) v."""
    return (A * v[..., :, None]).sum(-2)


def matT_mat(A, B):
    """A^T B."""
    return stack([matT_vec(A, B[..., :, j]) for j in range(3)], axis=-1)


def vee(W):
    """The vector of the skew part of W (exact for skew W)."""
    return stack([(W[..., 2, 1] - W[..., 1, 2]) * 0.5,
                  (W[..., 0, 2] - W[..., 2, 0]) * 0.5,
                  (W[..., 1, 0] - W[..., 0, 1]) * 0.5])


# ----------------------------------------------------------------- geometry

@dataclass(frozen=True)
class Geometry:
    """The mechanism's dimensions and gravity (Table II by default)."""

    R: float = 0.2286      #: base radius [m]
    rho: float = 0.5       #: r / R [-]
    g: float = 9.80665     #: gravity along -Z [m/s^2]


def pose_jet(pose, dpose, ddpose, dddpose=None):
    """The pose as a third-order series from its value and derivatives,
    each (n, 3)."""
    pose = np.asarray(pose, float)
    d3 = np.zeros_like(pose) if dddpose is None else np.asarray(dddpose, float)
    return Jet(np.stack([pose, np.asarray(dpose, float),
                         np.asarray(ddpose, float) / 2.0, d3 / 6.0]))


def chain(geom, q):
    """Positions of the closed chain from the pose series q (..., 3):
    platform rotation and centre, ball joints, lengths, link angles, and
    each body's rotation and origin (series)."""
    a, b, z = q[..., 0], q[..., 1], q[..., 2]
    sa, ca = a.sincos()
    sb, cb = b.sincos()
    zero = a * 0.0
    one = zero + 1.0
    # Rz(alpha) Ry(beta) Rz(-alpha)
    Rz = stack([stack([ca, -sa, zero]), stack([sa, ca, zero]),
                stack([zero, zero, one])], axis=-2)
    Ry = stack([stack([cb, zero, sb]), stack([zero, one, zero]),
                stack([-sb, zero, cb])], axis=-2)
    Rzm = stack([stack([ca, sa, zero]), stack([-sa, ca, zero]),
                 stack([zero, zero, one])], axis=-2)
    rot = _matmul(_matmul(Rz, Ry), Rzm)
    r = geom.rho * geom.R
    t = np.stack([-np.sin(PHI), np.cos(PHI), np.zeros(3)], axis=1)   # (3, 3)
    er = np.stack([np.cos(PHI), np.sin(PHI), np.zeros(3)], axis=1)
    P = geom.R * er
    rr = r * er                                    # r_i in platform axes
    arm = [sum(rot[..., :, k] * rr[i, k] for k in range(3)) for i in range(3)]
    # ball joints 1 and 2 in their pins' planes: (c + arm_i) . t_i = 0
    s1 = -sum(arm[0][..., k] * t[0, k] for k in range(3))
    s2 = -sum(arm[1][..., k] * t[1, k] for k in range(3))
    det = t[0, 0] * t[1, 1] - t[0, 1] * t[1, 0]
    xc = (s1 * t[1, 1] - s2 * t[0, 1]) / det
    yc = (t[0, 0] * s2 - t[1, 0] * s1) / det
    c = stack([xc, yc, z])
    ball = [c + arm[i] for i in range(3)]
    d = [ball[i] - P[i] for i in range(3)]
    l = [dot(d[i], d[i]).sqrt() for i in range(3)]
    u = [d[i] / l[i][..., None] for i in range(3)]
    theta = [atan2(u[i][..., 2], -dot(u[i], Jet.const(er[i], q.order)))
             for i in range(3)]
    bodies = [(rot, c)]
    for i in range(3):
        ti = Jet.const(np.broadcast_to(t[i], u[i].c.shape[1:]), q.order)
        axes = stack([u[i], ti, cross(u[i], ti)], axis=-1)
        bodies.append((axes, Jet.const(np.broadcast_to(P[i], u[i].c.shape[1:]),
                                       q.order)))
        bodies.append((axes, ball[i]))
    return dict(rot=rot, c=c, ball=ball, l=stack(l), theta=stack(theta),
                residual3=dot(ball[2], Jet.const(t[2], q.order)),
                bodies=bodies)


def _matmul(A, B):
    return stack([stack([sum(A[..., i, k] * B[..., k, j] for k in range(3))
                         for j in range(3)]) for i in range(3)], axis=-2)


def body_motion(rot, origin):
    """Body-axes origin velocity and angular velocity (series, one order
    less than the positions)."""
    v = matT_vec(rot, origin.deriv())
    w = vee(matT_mat(rot, rot.deriv()))
    return v, w


# ---------------------------------------------------------------- regressor

def _skew(v):
    z = np.zeros(v.shape[:-1])
    return np.stack([np.stack([z, -v[..., 2], v[..., 1]], -1),
                     np.stack([v[..., 2], z, -v[..., 0]], -1),
                     np.stack([-v[..., 1], v[..., 0], z], -1)], -2)


def _Lmat(w):
    """L(w) with I w = L(w) (Ixx, Ixy, Ixz, Iyy, Iyz, Izz)."""
    z = np.zeros(w.shape[:-1])
    x, y, zz = w[..., 0], w[..., 1], w[..., 2]
    return np.stack([np.stack([x, y, zz, z, z, z], -1),
                     np.stack([z, x, z, y, zz, z], -1),
                     np.stack([z, z, x, z, y, zz], -1)], -2)


def wrench_regressor(a, w, dw):
    """(n, 6, 10): the wrench (f, n) about the origin, body axes, per unit
    standard parameter, from the origin acceleration minus gravity a, the
    angular velocity w and acceleration dw (body axes)."""
    n = a.shape[0]
    A = np.zeros((n, 6, 10))
    A[:, 0:3, 0] = a
    Sw = _skew(w)
    A[:, 0:3, 1:4] = _skew(dw) + Sw @ Sw
    A[:, 3:6, 1:4] = -_skew(a)
    A[:, 3:6, 4:10] = _Lmat(dw) + Sw @ _Lmat(w)
    return A


def _sign(v, vreg):
    return np.sign(v) if vreg == 0.0 else np.tanh(v / vreg)


def regressor(geom, pose, dpose, ddpose, vreg=0.0):
    """Y (n, 3, 82): actuator forces [N] per unit standard parameter (the
    order of rps3.ident.STANDARD_NAMES) at the states (n, 3) each.
    vreg: Coulomb's sign law, 0 the exact sign, else tanh(v / vreg)."""
    pose = np.atleast_2d(np.asarray(pose, float))
    n = pose.shape[0]
    q = pose_jet(pose, dpose, ddpose)
    ch = chain(geom, q)
    # Jacobians: the velocities per unit pose rate (first-order series)
    jac = []
    for k in range(3):
        e = np.zeros((n, 3))
        e[:, k] = 1.0
        chk = chain(geom, Jet(np.stack([pose, e])))
        vel = [body_motion(rot, o) for rot, o in chk["bodies"]]
        jac.append(dict(l=chk["l"].value(1), theta=chk["theta"].value(1),
                        body=[np.concatenate([v.value(0), w.value(0)], -1)
                              for v, w in vel]))
    Jl = np.stack([j["l"] for j in jac], -1)           # (n, 3 l, 3 pose)
    Jth = np.stack([j["theta"] for j in jac], -1)
    gvec = np.array([0.0, 0.0, -geom.g])
    Q = np.zeros((n, 3, ident.N_STANDARD))
    for b, (rot, o) in enumerate(ch["bodies"]):
        v, w = body_motion(rot, o)
        R0 = rot.c[0]
        a = np.einsum("nji,nj->ni", R0, o.value(2) - gvec)
        A = wrench_regressor(a, w.value(0), w.value(1))
        Jb = np.stack([jac[k]["body"][b] for k in range(3)], 1)  # (n, 3, 6)
        Q[:, :, 10 * b:10 * b + 10] = np.einsum("nks,nsp->nkp", Jb, A)
    dth = ch["theta"].value(1)
    dl = ch["l"].value(1)
    off = ident.N_BODY_PARAMETERS
    for i in range(3):
        # pin friction: generalized force Jtheta^T tau
        Q[:, :, off + 6 + 2 * i] = Jth[:, i, :] * dth[:, i:i + 1]
        Q[:, :, off + 7 + 2 * i] = Jth[:, i, :] * _sign(dth[:, i:i + 1], vreg)
    Y = np.linalg.solve(np.transpose(Jl, (0, 2, 1)), Q)
    for i in range(3):
        Y[:, i, off + 2 * i] += dl[:, i]
        Y[:, i, off + 1 + 2 * i] += _sign(dl[:, i], vreg)
    return Y


def kinematics(geom, pose, dpose, ddpose):
    """l, theta and their first two derivatives, the centre c, the third
    pin-plane residual, each (n, 3) (or (n,)), for checks."""
    ch = chain(geom, pose_jet(np.atleast_2d(pose), np.atleast_2d(dpose),
                              np.atleast_2d(ddpose)))
    return dict(l=ch["l"].value(0), dl=ch["l"].value(1), ddl=ch["l"].value(2),
                theta=ch["theta"].value(0), dtheta=ch["theta"].value(1),
                ddtheta=ch["theta"].value(2), c=ch["c"].value(0),
                residual3=ch["residual3"].value(0), rot=ch["rot"].value(0))


def energy_rows(geom, pose, dpose, ddpose, dddpose=None, vreg=0.0):
    """Rows (n, 82) linear in the standard parameters: kinetic energy T and
    its rate dT/dt, potential energy P and dP/dt, and the friction power
    D (>= 0 for non-negative coefficients), from the energies of the
    bodies (not from their wrenches); plus l' (n, 3)."""
    pose = np.atleast_2d(np.asarray(pose, float))
    n = pose.shape[0]
    ch = chain(geom, pose_jet(pose, dpose, ddpose, dddpose))
    T = np.zeros((2, n, ident.N_STANDARD))
    P = np.zeros((2, n, ident.N_STANDARD))
    for b, (rot, o) in enumerate(ch["bodies"]):
        v, w = body_motion(rot, o)
        rows = [0.5 * dot(v, v)]
        vxw = cross(v, w)
        rows += [vxw[..., k] for k in range(3)]
        wx, wy, wz = w[..., 0], w[..., 1], w[..., 2]
        rows += [0.5 * wx * wx, wx * wy, wx * wz, 0.5 * wy * wy, wy * wz,
                 0.5 * wz * wz]
        for p, jet in enumerate(rows):
            T[:, :, 10 * b + p] = jet.c[:2]     # T and dT/dt (1! c_1)
        prow = [o[..., 2] * geom.g] + [rot[..., 2, k] * geom.g for k in range(3)]
        for p, jet in enumerate(prow):
            P[:, :, 10 * b + p] = jet.c[:2]
    D = np.zeros((n, ident.N_STANDARD))
    dl, dth = ch["l"].value(1), ch["theta"].value(1)
    off = ident.N_BODY_PARAMETERS
    for i in range(3):
        D[:, off + 2 * i] = dl[:, i] ** 2
        D[:, off + 1 + 2 * i] = dl[:, i] * _sign(dl[:, i], vreg)
        D[:, off + 6 + 2 * i] = dth[:, i] ** 2
        D[:, off + 7 + 2 * i] = dth[:, i] * _sign(dth[:, i], vreg)
    return dict(T=T[0], dT=T[1], P=P[0], dP=P[1], D=D, dl=dl)


# ------------------------------------------------------------ random states

def random_states(rng, n, scale=1.0):
    """n consistent states (pose, dpose, ddpose) inside the workspace: the
    platform above the base with moderate tilt, any azimuth."""
    pose = np.stack([rng.uniform(-np.pi, np.pi, n), rng.uniform(0.05, 0.45, n),
                     rng.uniform(0.18, 0.40, n)], 1)
    dpose = rng.uniform(-1, 1, (n, 3)) * np.array([2.0, 0.6, 0.2]) * scale
    ddpose = rng.uniform(-1, 1, (n, 3)) * np.array([8.0, 3.0, 1.0]) * scale
    return pose, dpose, ddpose


def sines(t, mean, amp, freq, phase):
    """pose_k = mean_k + sum_j amp_kj sin(2 pi freq_kj t + phase_kj): a
    periodic excitation with its exact rates and accelerations; amp, freq,
    phase (3, nh)."""
    t = np.asarray(t, float)[:, None, None]
    w = 2 * np.pi * np.asarray(freq, float)
    a = np.asarray(amp, float)
    ph = w * t + np.asarray(phase, float)
    return (np.asarray(mean, float) + (a * np.sin(ph)).sum(-1),
            (a * w * np.cos(ph)).sum(-1), (-a * w**2 * np.sin(ph)).sum(-1))


def exciting(t, rng, scale=1.0):
    """A random sum of three sines per pose coordinate (0.1-1 Hz) about a
    mid-workspace pose, alpha over a wide range: (pose, dpose, ddpose)."""
    amp = np.array([[1.2, 0.6, 0.3], [0.12, 0.06, 0.04], [0.04, 0.02, 0.01]]) * scale
    freq = rng.uniform(0.1, 1.0, (3, 3))
    phase = rng.uniform(-np.pi, np.pi, (3, 3))
    return sines(t, [rng.uniform(-1, 1), 0.25, 0.29], amp, freq, phase)


def random_parameters(rng, layout, friction_scale=1.0):
    """Physically consistent standard parameters of a layout: each body a
    random box (mass 0.05-0.3 kg, sides 1-10 cm) at a random offset and
    orientation; pistons' centres inside the cylinder (behind the ball
    joint along -e1); friction coefficients 0.05-0.5 (viscous, N s/m or
    N m s/rad) and 0.01-0.2 (Coulomb, N or N m) times friction_scale."""
    pi = []
    for name in layout.bodies:
        mass = rng.uniform(0.05, 0.3)
        a, b, c = rng.uniform(0.01, 0.10, 3)
        Ib = mass / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
        Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        com = rng.uniform(-0.05, 0.05, 3)
        if name.startswith("piston"):
            com[0] = -rng.uniform(0.03, 0.12)
        if name.startswith("cylinder"):
            com[0] = rng.uniform(0.05, 0.15)
        pi.append(ident.body_parameters(mass, com, Q @ Ib @ Q.T))
    nf = len(layout.friction_indices)
    fr = np.empty(nf)
    fr[0::2] = rng.uniform(0.05, 0.5, nf // 2) * friction_scale
    fr[1::2] = rng.uniform(0.01, 0.2, nf // 2) * friction_scale
    return np.concatenate(pi + [fr])
