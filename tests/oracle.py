"""Oracles that read the model's inputs, never a field the library derived.

- `symbolic()`: the inverse dynamics derived here with SymPy from first
  principles, in the pose coordinates q = (alpha, beta, z_c) themselves (a
  minimal set: no multipliers, no link coordinates): the kinetic and
  potential energy of the platform (a uniform disc of radius r), the links
  (a point mass m at d from the pin plus a centroidal moment link_Ic about
  the pin axis), a rigid payload, and the Euler-Lagrange equations
      d/dt dL/dq' - dL/dq = Q,   Q_j = sum_i F_i dl_i/dq_j + tau_i dtheta_i/dq_j
  with the pin friction torque tau_i = -(viscous theta_i' + coulomb
  sign(theta_i')).  The geometry is built from R, rho and the pin angles
  (0, 2pi/3, 4pi/3): the orientation Rz(alpha) Ry(beta) Rz(-alpha), the
  centre from the condition that each ball joint stays in its pin's
  vertical plane (not from (3)-(4)), b_i = c + rot r_i.
- `library_forces()`: the library's forces for a batch of states through
  a small C shim (tests/oracle_shim.c) built against include/rps3.h and
  build/librps3.so.
- `helix_states()`, `sine_states()`: pose, rates and accelerations of the
  paper's helix (Table I with the errata) and of sinusoids, written here.
- The kinematics of every joint (theta, l, their rates and accelerations,
  the platform's position, orientation and body angular velocity), which
  tests/mujoco_model.py turns into a MuJoCo state.
"""

import ctypes
import functools
import os
import subprocess

import numpy as np
import sympy as sp

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# effect k is the bit 1 << k of rps3_options.effects
EFFECTS = ("platform_gravity", "link_gravity", "platform_inertia",
           "link_inertia", "payload", "pin_friction", "prismatic_friction")
EFF_DEFAULT = 0b0001111
EFF_ALL = 0b1111111

# Table II (the paper's case)
PAPER = dict(R=0.2286, rho=0.5, M=0.18, m=0.09, d=0.1524, link_Ic=0.0,
             g=9.80665, payload=dict(mass=0.0, com=(0.0, 0.0, 0.0),
                                     inertia=(0.0, 0.0, 0.0)),
             friction=dict(viscous=0.0, coulomb=0.0))

# high-entropy parameters with every effect present (tests/testutil.h's)
ENTROPY = dict(R=0.2385, rho=0.4387, M=0.2381, m=0.0917, d=0.1383,
               link_Ic=3.17e-4, g=9.80665,
               payload=dict(mass=0.0713, com=(0.0127, -0.0083, 0.0411),
                            inertia=(1.13e-4, 1.71e-4, 0.97e-4)),
               friction=dict(viscous=0.0137, coulomb=0.0029))
# and friction in the prismatic joints (the exported MJCF has none)
ENTROPY_PRISMATIC = dict(ENTROPY, prismatic=dict(viscous=0.213, coulomb=0.047))

PARAM_NAMES = ("R", "rho", "M", "m", "d", "link_Ic", "g", "payload_mass",
               "com_x", "com_y", "com_z", "I_x", "I_y", "I_z", "viscous",
               "coulomb", "prismatic_viscous", "prismatic_coulomb")


def param_vector(p):
    """The model parameters in the order of PARAM_NAMES (and the shim)."""
    pl, fr = p["payload"], p["friction"]
    pr = p.get("prismatic", dict(viscous=0.0, coulomb=0.0))
    return np.array([p["R"], p["rho"], p["M"], p["m"], p["d"], p["link_Ic"],
                     p["g"], pl["mass"], *pl["com"], *pl["inertia"],
                     fr["viscous"], fr["coulomb"], pr["viscous"],
                     pr["coulomb"]], float)


# ------------------------------------------------------------ trajectories

def helix_states(t, p, radius=0.266e-3, pitch=0.03048, z0=0.3048,
                 period=10.0, blend=1.0):
    """Table I with the errata: phi linear with parabolic blends of length
    t_a, phi(T*) = 2 pi; alpha = pi/2 - phi/2, 1 - cos beta = 2 r*/r,
    z_c = z_i + h t / T*.  Returns (pose, dpose, ddpose), each (n, 3)."""
    t = np.atleast_1d(np.asarray(t, float))
    wmax = 2 * np.pi / (period - blend)
    acc = wmax / blend
    tb = period - blend
    phi = np.where(t < blend, 0.5 * acc * t**2,
                   np.where(t < tb, wmax * (t - 0.5 * blend),
                            2 * np.pi - 0.5 * acc * (period - t)**2))
    dphi = np.where(t < blend, acc * t,
                    np.where(t < tb, wmax, acc * (period - t)))
    ddphi = np.where(t < blend, acc, np.where(t < tb, 0.0, -acc))
    beta = np.arccos(1 - 2 * radius / (p["rho"] * p["R"]))
    pose = np.stack([np.pi / 2 - phi / 2, np.full_like(t, beta),
                     z0 + pitch * t / period], axis=1)
    dpose = np.stack([-dphi / 2, 0 * t, np.full_like(t, pitch / period)],
                     axis=1)
    ddpose = np.stack([-ddphi / 2, 0 * t, 0 * t], axis=1)
    return pose, dpose, ddpose


def sine_states(t, mean, amp, freq, phase):
    """pose_k = mean_k + amp_k sin(2 pi freq_k t + phase_k)."""
    t = np.atleast_1d(np.asarray(t, float))[:, None]
    w = 2 * np.pi * np.asarray(freq, float)
    ph = w * t + np.asarray(phase, float)
    a = np.asarray(amp, float)
    return (np.asarray(mean, float) + a * np.sin(ph), a * w * np.cos(ph),
            -a * w**2 * np.sin(ph))


def random_sine(rng):
    """A random smooth trajectory well inside the workspace."""
    mean = [rng.uniform(-3, 3), rng.uniform(0.12, 0.35), rng.uniform(0.22, 0.35)]
    amp = [rng.uniform(0.2, 1.5), rng.uniform(0.02, 0.1), rng.uniform(0.01, 0.06)]
    freq = rng.uniform(0.3, 2.1, 3)
    phase = rng.uniform(-3.1, 3.1, 3)
    return mean, amp, freq, phase


# ----------------------------------------------------------------- library

def build_shim(outdir):
    """Compile tests/oracle_shim.c against build/librps3.so; the CDLL."""
    so = os.path.join(str(outdir), "liboracle_shim.so")
    build = os.path.join(ROOT, "build")
    cc = os.environ.get("CC", "cc")
    subprocess.run([cc, "-std=c99", "-O2", "-fPIC", "-shared",
                    "-I" + os.path.join(ROOT, "include"),
                    os.path.join(ROOT, "tests", "oracle_shim.c"), "-o", so,
                    "-L" + build, "-lrps3", "-Wl,-rpath," + build],
                   check=True, capture_output=True, text=True)
    lib = ctypes.CDLL(so)
    dp = np.ctypeslib.ndpointer(np.float64, flags="C_CONTIGUOUS")
    ip = np.ctypeslib.ndpointer(np.int32, flags="C_CONTIGUOUS")
    lib.rps3_shim_forces.argtypes = [dp, ctypes.c_int, ctypes.c_int,
                                     ctypes.c_int, ctypes.c_int, dp, dp, dp,
                                     dp, dp, ip, ctypes.c_char_p, ctypes.c_int]
    assert lib.rps3_shim_npar() == len(PARAM_NAMES)
    return lib


def build_sim_shim(outdir):
    """Compile tests/sim_shim.c (rps3_sim driven open loop by a force
    table) against build/librps3.so; the CDLL."""
    so = os.path.join(str(outdir), "libsim_shim.so")
    build = os.path.join(ROOT, "build")
    subprocess.run([os.environ.get("CC", "cc"), "-std=c99", "-O2", "-fPIC",
                    "-shared", "-I" + os.path.join(ROOT, "include"),
                    os.path.join(ROOT, "tests", "sim_shim.c"), "-o", so,
                    "-L" + build, "-lrps3", "-Wl,-rpath," + build],
                   check=True, capture_output=True, text=True)
    lib = ctypes.CDLL(so)
    dp = np.ctypeslib.ndpointer(np.float64, flags="C_CONTIGUOUS")
    lib.rps3_shim_sim.argtypes = [dp, ctypes.c_int, ctypes.c_int,
                                  ctypes.c_double, ctypes.c_double, dp, dp,
                                  ctypes.c_int, ctypes.c_double, dp, dp, dp,
                                  dp, dp, ctypes.c_char_p, ctypes.c_int]
    return lib


def library_forces(lib, p, effects, states, method=0, theta=0):
    """F (n, 3), F_effect (n, 7, 3) and status (n,) from rps3_inverse."""
    pose, dpose, ddpose = (np.ascontiguousarray(s, float) for s in states)
    n = len(pose)
    F = np.zeros((n, 3))
    # the shim writes every effect of the library (RPS3_NEFFECT), EFFECTS
    # and those the oracle has not (the prismatic joints' friction)
    Fe = np.zeros((n, lib.rps3_shim_neffect(), 3))
    st = np.zeros(n, np.int32)
    err = ctypes.create_string_buffer(256)
    rc = lib.rps3_shim_forces(param_vector(p), effects, method, theta, n,
                              pose, dpose, ddpose, F, Fe, st, err, 256)
    assert rc == 0, err.value.decode()
    return F, Fe[:, :len(EFFECTS)], st


# ---------------------------------------------------------------- symbolic

def _vee(S):
    """axial vector of the skew part of S"""
    return 0.5 * np.array([S[2, 1] - S[1, 2], S[0, 2] - S[2, 0],
                           S[1, 0] - S[0, 1]])


def _euler_lagrange(Mq, dM, G, qd, qdd):
    """d/dt dT/dq' - dT/dq + dV/dq for T = q'^T M(q) q' / 2: with
    dM[l] = dM/dq_l, the Christoffel form
    M q'' + sum_kl (dM_jk/dq_l - dM_kl/dq_j / 2) q'_k q'_l + dV/dq_j."""
    c = np.einsum("ljk,k,l->j", dM, qd, qd) - 0.5 * np.einsum(
        "jkl,k,l->j", dM, qd, qd)
    return Mq @ qdd + c + G


class Symbolic:
    """The geometry derived with SymPy (positions and their first and second
    partial derivatives in q), lambdified; the Lagrangian assembled from it.

    Every body contributes T = q'^T M_b(q) q' / 2 with M_b from its
    Jacobians (m J^T J for a point, J_w^T I J_w for a rotation), and dM_b/dq
    from the second partials, exactly: the Euler-Lagrange equations then
    need no numerical differentiation.  See the module docstring."""

    def __init__(self):
        q = sp.symbols("alpha beta z_c", real=True)
        par = sp.symbols(" ".join(PARAM_NAMES), real=True)
        (R, rho, _, _, d, _, _, _, sx, sy, sz, *_) = par
        a, b, z = q

        def Rz(x):
            return sp.Matrix([[sp.cos(x), -sp.sin(x), 0],
                              [sp.sin(x), sp.cos(x), 0], [0, 0, 1]])

        Ry = sp.Matrix([[sp.cos(b), 0, sp.sin(b)], [0, 1, 0],
                        [-sp.sin(b), 0, sp.cos(b)]])
        rot = Rz(a) * Ry * Rz(-a)
        r = rho * R
        psi = [0, 2 * sp.pi / 3, 4 * sp.pi / 3]
        u = [sp.Matrix([sp.cos(p), sp.sin(p), 0]) for p in psi]
        axis = [sp.Matrix([-sp.sin(p), sp.cos(p), 0]) for p in psi]
        pins = [R * ui for ui in u]
        w = [rot * (r * ui) for ui in u]
        # the centre: every ball joint in its pin's vertical plane (the pin
        # axis is normal to it); two planes fix (x_c, y_c), the third holds
        cx, cy = sp.symbols("c_x c_y", real=True)
        sol = sp.solve([(sp.Matrix([cx, cy, z]) + w[i]).dot(axis[i])
                        for i in (0, 1)], [cx, cy], dict=True)[0]
        c = sp.Matrix([sol[cx], sol[cy], z])
        balls = [c + wi for wi in w]
        v = [balls[i] - pins[i] for i in range(3)]
        length = [sp.sqrt(vi.dot(vi)) for vi in v]
        theta = [sp.atan2(v[i][2], -v[i].dot(u[i])) for i in range(3)]
        link_com = [pins[i] + d * v[i] / length[i] for i in range(3)]
        pcom = c + rot * sp.Matrix([sx, sy, sz])

        def jet(f):
            """f, df/dq_j, d2f/dq_j dq_k of a scalar"""
            J = [sp.diff(f, q[j]) for j in range(3)]
            return [f, J, [[sp.diff(J[j], q[k]) for k in range(3)]
                           for j in range(3)]]

        scalars = theta + length + [c[k] for k in range(3)] + \
            [pcom[k] for k in range(3)] + \
            [x[k] for x in link_com for k in range(3)] + \
            [rot[i, j] for i in range(3) for j in range(3)]
        self._geo = sp.lambdify((q, par), [jet(f) for f in scalars],
                                modules="numpy", cse=True)

    def _geometry(self, p, pose):
        out = self._geo(np.asarray(pose, float), param_vector(p))
        val = np.array([o[0] for o in out], float)
        J = np.array([o[1] for o in out], float)
        H = np.array([o[2] for o in out], float)
        sl = {"theta": slice(0, 3), "l": slice(3, 6), "c": slice(6, 9),
              "pcom": slice(9, 12), "links": slice(12, 21),
              "rot": slice(21, 30)}
        return {k: (val[s], J[s], H[s]) for k, s in sl.items()}

    @staticmethod
    def _rotation(g):
        """rot, J_w (body angular velocity = J_w q') and dJ_w/dq_l"""
        R, dR, ddR = g["rot"]
        R = R.reshape(3, 3)
        dR = dR.T.reshape(3, 3, 3)          # dR[k] = d rot / dq_k
        ddR = ddR.transpose(1, 2, 0).reshape(3, 3, 3, 3)  # [k][l]
        Jw = np.stack([_vee(R.T @ dR[k]) for k in range(3)], axis=1)
        dJw = np.stack([np.stack([_vee(dR[l].T @ dR[k] + R.T @ ddR[k, l])
                                  for k in range(3)], axis=1)
                        for l in range(3)])
        return R, Jw, dJw

    def kinematics(self, p, pose, dpose, ddpose):
        """Joint and platform motion of one state, as a dict of arrays."""
        g = self._geometry(p, pose)
        qd, qdd = np.asarray(dpose, float), np.asarray(ddpose, float)
        out = {}
        for name, key in (("theta", "theta"), ("l", "l"), ("c", "c")):
            val, J, H = g[key]
            out[name] = val
            out["d" + name] = J @ qd
            out["dd" + name] = J @ qdd + np.einsum("ijk,j,k->i", H, qd, qd)
        R, Jw, dJw = self._rotation(g)
        out["rot"] = R
        out["omega_body"] = Jw @ qd
        out["domega_body"] = Jw @ qdd + np.einsum("lik,k,l->i", dJw, qd, qd)
        return out

    def forces(self, p, effects, pose, dpose, ddpose):
        """F (3,) and the share of each effect (7, 3) at one state."""
        g = self._geometry(p, pose)
        qd, qdd = np.asarray(dpose, float), np.asarray(ddpose, float)
        grav, pl = p["g"], p["payload"]
        r = p["rho"] * p["R"]

        def point(mass, J, H):
            """a point mass at x(q): M = m J^T J, its dV/dq = m g dz/dq"""
            Mq = mass * J.T @ J
            dM = mass * (np.einsum("ajl,ak->ljk", H, J) +
                         np.einsum("aj,akl->ljk", J, H))
            return _euler_lagrange(Mq, dM, mass * grav * J[2], qd, qdd)

        def rotation(I):
            """rotation of the platform frame with body inertia diag(I)"""
            _, Jw, dJw = self._rotation(g)
            Id = np.diag(I)
            Mq = Jw.T @ Id @ Jw
            dM = np.einsum("lak,ab,bj->ljk", dJw, Id, Jw)
            dM = dM + dM.transpose(0, 2, 1)
            return _euler_lagrange(Mq, dM, np.zeros(3), qd, qdd)

        def no_gravity(mass, J, H):
            return point(mass, J, H) - mass * grav * J[2]

        _, Jc, Hc = g["c"]
        _, Jp, Hp = g["pcom"]
        _, Jx, Hx = g["links"]
        _, Jt, Ht = g["theta"]
        _, Jl, _ = g["l"]
        M, m, Ic = p["M"], p["m"], p["link_Ic"]
        rows = np.zeros((len(EFFECTS), 3))
        rows[0] = M * grav * Jc[2]                      # platform weight
        for i in range(3):
            s = slice(3 * i, 3 * i + 3)
            rows[1] += m * grav * Jx[s][2]              # link weights
            rows[3] += no_gravity(m, Jx[s], Hx[s])      # links swinging
            # the centroidal moment about the pin axis: T = Ic theta'^2 / 2
            Mi = Ic * np.outer(Jt[i], Jt[i])
            dMi = Ic * (np.einsum("jl,k->ljk", Ht[i], Jt[i]) +
                        np.einsum("j,kl->ljk", Jt[i], Ht[i]))
            rows[3] += _euler_lagrange(Mi, dMi, np.zeros(3), qd, qdd)
        # the uniform disc of (21): M r^2/4, M r^2/4, M r^2/2
        rows[2] = no_gravity(M, Jc, Hc) + rotation(
            (M * r**2 / 4, M * r**2 / 4, M * r**2 / 2))
        rows[4] = point(pl["mass"], Jp, Hp) + rotation(pl["inertia"])
        thd = Jt @ qd
        fr = p["friction"]
        tau = -(fr["viscous"] * thd + fr["coulomb"] * np.sign(thd))
        rows[5] = -(Jt.T @ tau)  # the friction torques' generalized force
        # the prismatic joints' friction: a force on each actuator's own
        # coordinate, J_l^T f in the pose's
        pr = p.get("prismatic", dict(viscous=0.0, coulomb=0.0))
        ld = Jl @ qd
        rows[6] = Jl.T @ (pr["viscous"] * ld + pr["coulomb"] * np.sign(ld))
        Fe = np.linalg.solve(Jl.T, rows.T).T  # J_l^T F = the loads
        for k in range(len(EFFECTS)):
            if not effects & (1 << k):
                Fe[k] = 0.0
        return Fe.sum(axis=0), Fe


@functools.lru_cache(maxsize=1)
def symbolic():
    """The derivation, done once per process."""
    return Symbolic()
