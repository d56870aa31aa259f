"""A MuJoCo model of the 3-RPS mechanism, built from rps3's model parameters
by the package's exporter (rps3.export.mjcf, whose module doc describes the
bodies; its geoms are drawings without mass or contacts), and the oracle's
use of it: a state from the oracle's kinematics and the actuator forces
solved from MuJoCo's own dynamics.

    xml = mujoco_xml(params)          # MJCF text, rps3.export.mjcf
    model = build(params)             # mujoco.MjModel
    qpos, qvel, qacc = state(model, kin)   # from oracle.Symbolic.kinematics
    F = actuator_forces(model, data, qpos, qvel, qacc, params)

`params` is a dict with the keys of rps3_model (R, rho, M, m, d, link_Ic, g,
payload {mass, com, inertia}, friction {viscous, coulomb}); see
tests/oracle.py for the paper's and a high-entropy set.  With a key
"bodies" (rps3.Model's general bodies) it is the general model: R, rho, g,
bodies, friction and prismatic, each friction law shared by the legs or a
list of three (tests/test_ident_mujoco_general.py).

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
import rps3

# the exporter's masses for massless moving bodies (see its module doc)
EPS_MASS = rps3.export.EPS_MASS
EPS_INERTIA = rps3.export.EPS_INERTIA


def model_of(p):
    """The rps3.Model of the parameters p (every input, nothing derived);
    with a key "bodies", the general model of those bodies (rps3.Model's
    bodies argument: M, m, d, link_Ic and payload are then not read)."""
    if "bodies" in p:
        return rps3.Model(R=p["R"], rho=p["rho"], g=p["g"], bodies=p["bodies"],
                          friction=p["friction"],
                          prismatic_friction=p.get("prismatic"))
    return rps3.Model(R=p["R"], rho=p["rho"], M=p["M"], m=p["m"], d=p["d"],
                      link_Ic=p["link_Ic"], g=p["g"], payload=p["payload"],
                      friction=p["friction"],
                      prismatic_friction=p.get("prismatic"))


def mujoco_xml(p):
    """MJCF text of the mechanism with parameters p (see the module doc)."""
    return rps3.export.mjcf(model_of(p))


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


def _leg(law, i):
    """Leg i's friction law of a law shared by the legs or a list of three."""
    return law if isinstance(law, dict) else law[i]


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
        need[dof] += _leg(p["friction"], i)["coulomb"] * np.sign(qvel[dof])
    # the prismatic joints' Coulomb friction, a known force opposing each
    # slide's rate (the viscous part is the exported slide's damping)
    pr = p.get("prismatic", dict(viscous=0.0, coulomb=0.0))
    for i in range(3):
        dof = model.joint(f"leg_{i}").dofadr[0]
        need[dof] += _leg(pr, i)["coulomb"] * np.sign(qvel[dof])
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
