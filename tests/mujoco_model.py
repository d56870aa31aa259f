"""A MuJoCo model of the 3-RPS mechanism, built from rps3's model parameters.

    xml = mujoco_xml(params)          # MJCF text
    model = build(params)             # mujoco.MjModel
    qpos, qvel, qacc = state(model, kin)   # from oracle.Symbolic.kinematics
    F = actuator_forces(model, data, qpos, qvel, qacc, params)

`params` is a dict with the keys of rps3_model (R, rho, M, m, d, link_Ic, g,
payload {mass, com, inertia}, friction {viscous, coulomb}); see
tests/oracle.py for the paper's and a high-entropy set.

The mechanism, as MuJoCo bodies (world frame: Z up, X towards pin 1):
- link_i: a body at pin P_i = R (cos psi_i, sin psi_i, 0), psi_i = 0,
  2pi/3, 4pi/3, with a hinge `pin_i` about the pin axis (-sin psi_i,
  cos psi_i, 0); at angle 0 the link points inwards along -u_i, so the
  hinge angle is theta_i of the paper.  Its mass m sits at d along the link
  and its centroidal inertia is link_Ic about every axis (only the pin
  axis matters: the link turns about nothing else).  Pin friction: the
  viscous part is the hinge's `damping`; the Coulomb part is a known torque
  added by `actuator_forces` (MuJoCo's frictionloss is a soft constraint,
  and is not what the library models).
- piston_i: a child of link_i with a slide `leg_i` along the link; its
  position is the link length l_i, and the motor `F_i` acts on it (F > 0
  extends).  The piston is massless in the library: here it carries
  EPS_MASS, the least MuJoCo accepts for a moving body, and its site
  `ball_i_link` is the ball joint's centre on the link side.
- platform: a free body at the platform centre with the platform's axes,
  the uniform disc of (21) (mass M, moments M r^2/4, M r^2/4, M r^2/2),
  sites `ball_i` at r_i = r (cos psi_i, sin psi_i, 0), and a `payload`
  child welded to it (its mass, centre of mass and principal moments).
- equality `connect` constraints close the three loops site to site (ball
  joints); the model can be simulated as it is.

`actuator_forces` does not rely on the soft constraints: it takes MuJoCo's
rigid-body dynamics (mass matrix, bias forces, passive damping, from
mj_inverse with constraints disabled) and its kinematic Jacobians of the
ball-joint sites, and solves for the three actuator forces and the nine
ball-joint reactions exactly, so the comparison is at rounding level.
"""

import numpy as np

import mujoco

# MuJoCo refuses moving bodies lighter than mjMINVAL (1e-15); the massless
# pistons (and massless links) get this much, 1e-12 kg: 1e-11 N at 10 m/s^2
# against forces of ~1 N
EPS_MASS = 1e-12
EPS_INERTIA = 1e-12


def _fmt(v):
    return " ".join(f"{x:.17g}" for x in np.atleast_1d(v))


def mujoco_xml(p):
    """MJCF text of the mechanism with parameters p (see the module doc)."""
    R, r = p["R"], p["rho"] * p["R"]
    M, m, d = p["M"], p["m"], p["d"]
    Ic = max(p["link_Ic"], EPS_INERTIA)
    pl, fr = p["payload"], p["friction"]
    links, sites, eqs, acts = [], [], [], []
    for i in range(3):
        psi = 2 * np.pi * i / 3
        u = np.array([np.cos(psi), np.sin(psi), 0.0])
        ax = np.array([-np.sin(psi), np.cos(psi), 0.0])
        links.append(f"""
    <body name="link_{i}" pos="{_fmt(R * u)}">
      <joint name="pin_{i}" type="hinge" axis="{_fmt(ax)}" damping="{fr['viscous']:.17g}"/>
      <inertial pos="{_fmt(-d * u)}" mass="{max(m, EPS_MASS):.17g}" diaginertia="{_fmt([Ic] * 3)}"/>
      <body name="piston_{i}">
        <joint name="leg_{i}" type="slide" axis="{_fmt(-u)}"/>
        <inertial pos="0 0 0" mass="{EPS_MASS}" diaginertia="{_fmt([EPS_INERTIA] * 3)}"/>
        <site name="ball_{i}_link" pos="0 0 0"/>
      </body>
    </body>""")
        sites.append(f'      <site name="ball_{i}" pos="{_fmt(r * u)}"/>')
        eqs.append(f'    <connect site1="ball_{i}_link" site2="ball_{i}"/>')
        acts.append(f'    <motor name="F_{i}" joint="leg_{i}" gear="1"/>')
    payload = ""
    if pl["mass"] > 0:
        payload = f"""
      <body name="payload" pos="{_fmt(pl['com'])}">
        <inertial pos="0 0 0" mass="{pl['mass']:.17g}" diaginertia="{_fmt(np.maximum(pl['inertia'], EPS_INERTIA))}"/>
      </body>"""
    Ip = [M * r * r / 4, M * r * r / 4, M * r * r / 2]
    return f"""<mujoco model="rps3">
  <compiler angle="radian" inertiafromgeom="false"/>
  <option gravity="0 0 {-p['g']:.17g}" integrator="RK4" timestep="1e-4"/>
  <worldbody>{''.join(links)}
    <body name="platform">
      <freejoint name="platform"/>
      <inertial pos="0 0 0" mass="{max(M, EPS_MASS):.17g}" diaginertia="{_fmt(np.maximum(Ip, EPS_INERTIA))}"/>
{chr(10).join(sites)}{payload}
    </body>
  </worldbody>
  <equality>
{chr(10).join(eqs)}
  </equality>
  <actuator>
{chr(10).join(acts)}
  </actuator>
</mujoco>
"""


def build(p):
    """The MjModel of mujoco_xml(p)."""
    return mujoco.MjModel.from_xml_string(mujoco_xml(p))


def state(model, kin):
    """qpos, qvel, qacc of the model for one state of the mechanism; kin is
    a dict with theta, dtheta, ddtheta, l, dl, ddl (3 each), c, dc, ddc
    (platform centre and its derivatives, world), rot (3 x 3, platform axes
    as columns), omega_body and domega_body (platform axes)."""
    qpos = np.zeros(model.nq)
    qvel = np.zeros(model.nv)
    qacc = np.zeros(model.nv)
    for i in range(3):
        for name, val in ((f"pin_{i}", "theta"), (f"leg_{i}", "l")):
            j = model.joint(name)
            qpos[j.qposadr[0]] = kin[val][i]
            qvel[j.dofadr[0]] = kin["d" + val][i]
            qacc[j.dofadr[0]] = kin["dd" + val][i]
    j = model.joint("platform")
    a, v = j.qposadr[0], j.dofadr[0]
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, np.ascontiguousarray(kin["rot"]).ravel())
    qpos[a:a + 3] = kin["c"]
    qpos[a + 3:a + 7] = quat
    # free joint: linear velocity in the world frame, angular in the body's
    qvel[v:v + 3] = kin["dc"]
    qvel[v + 3:v + 6] = kin["omega_body"]
    qacc[v:v + 3] = kin["ddc"]
    qacc[v + 3:v + 6] = kin["domega_body"]
    return qpos, qvel, qacc


def closure_residual(model, data):
    """max distance between the paired ball-joint sites [m] after
    mj_kinematics: zero when the state closes the three loops."""
    return max(np.linalg.norm(data.site(f"ball_{i}").xpos -
                              data.site(f"ball_{i}_link").xpos)
               for i in range(3))


def actuator_forces(model, data, qpos, qvel, qacc, p):
    """Actuator forces [N] that produce the motion (qpos, qvel, qacc), with
    the nine ball-joint reactions solved exactly alongside (no softness)."""
    data.qpos[:] = qpos
    data.qvel[:] = qvel
    data.qacc[:] = qacc
    saved = model.opt.disableflags
    model.opt.disableflags = saved | mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
    try:
        # qfrc_inverse = M qacc + bias (gravity, Coriolis) - passive (damping)
        mujoco.mj_inverse(model, data)
    finally:
        model.opt.disableflags = saved
    need = data.qfrc_inverse.copy()
    # Coulomb pin friction, a known torque opposing each pin's rate
    for i in range(3):
        dof = model.joint(f"pin_{i}").dofadr[0]
        need[dof] += p["friction"]["coulomb"] * np.sign(qvel[dof])
    # ball-joint reactions: Jacobian of (platform site - link site)
    cols = []
    jp = np.zeros((3, model.nv))
    jq = np.zeros((3, model.nv))
    for i in range(3):
        mujoco.mj_jacSite(model, data, jp, None, model.site(f"ball_{i}").id)
        mujoco.mj_jacSite(model, data, jq, None,
                          model.site(f"ball_{i}_link").id)
        cols.append((jp - jq).T)
    B = np.zeros((model.nv, 3))
    for i in range(3):
        B[model.joint(f"leg_{i}").dofadr[0], i] = 1.0
    A = np.hstack(cols + [B])
    x = np.linalg.solve(A, need)
    return x[9:]
