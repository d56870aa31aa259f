"""rps3.export: the MJCF model loads in MuJoCo with visible geoms and the
closed loops, the URDF spanning tree loads in Pinocchio with its loop
closures, and both move and push like rps3's mechanism.

- joint_values (the library's kinematics in the exports' joint terms)
  against the SymPy oracle's kinematics (tests/oracle.py), which shares no
  line with src/;
- MuJoCo: the ball-joint sites of both sides at the library's ball joints,
  their velocities equal (the loops stay closed at velocity level), and the
  actuator forces solved from MuJoCo's dynamics (tests/mujoco_model.py's
  actuator_forces) equal rps3's inverse dynamics (every effect: the export
  is the whole mechanism);
- Pinocchio: the frames ball_i (platform side) and ball_i_link (leg side)
  at the library's ball joints, their velocities equal, and the forces
  solved from Pinocchio's RNEA and frame Jacobians with the URDF's closures
  equal rps3's.

Tolerances: positions, TOL_POS of tests/test_view.py (rounding of ~0.3 m
coordinates); rates and forces, TOL of tests/test_oracles.py (1e-9 of the
largest value: exact formulations in double agree to ~1e-11, MuJoCo's
pistons carry 1e-12 kg), while a 1 % wrong inertia moves the forces by
~1e-4.
"""

import os

import numpy as np
import pytest

import mujoco
import mujoco_model
import oracle
import rps3
from rps3 import export

pin = pytest.importorskip("pinocchio", reason="the URDF is checked with Pinocchio "
                          "(PyPI pin, in tests/requirements.txt)")

TOL_POS = 1e-12
TOL = 1e-9
EFF_ALL = list(rps3.EFFECTS)
# Pinocchio's constraintDynamics on the URDF (pistons of 1e-12 kg): ~1e-5
# measured (cond(M) ~ 1e12 x 1e-16)
CONSTRAINED_TOL = 1e-4


@pytest.fixture(scope="module")
def sym():
    return oracle.symbolic()


def sines(n=4, samples=4, seed=2385):
    rng = np.random.default_rng(seed)
    parts = [oracle.sine_states(np.linspace(0.05, 1.95, samples),
                                *oracle.random_sine(rng)) for _ in range(n)]
    return tuple(np.concatenate([p[k] for p in parts]) for k in range(3))


def helix():
    return oracle.helix_states(np.array([0.0, 0.5, 1.0, 3.7, 9.0, 9.6]), oracle.PAPER)


# the paper's case and every effect with high-entropy parameters
CASES = [("paper-helix", oracle.PAPER, helix), ("entropy-sines", oracle.ENTROPY, sines)]
IDS = [c[0] for c in CASES]


def model_of(p):
    return rps3.Model(R=p["R"], rho=p["rho"], M=p["M"], m=p["m"], d=p["d"],
                      link_Ic=p["link_Ic"], g=p["g"], payload=p["payload"],
                      friction=p["friction"], effects=EFF_ALL)


def rel(a, b):
    return np.max(np.abs(np.asarray(a) - np.asarray(b))) / max(np.max(np.abs(b)), 1e-300)


# ------------------------------------------------------------ joint values

@pytest.mark.parametrize("name,p,states", CASES, ids=IDS)
def test_joint_values_are_the_oracles(sym, name, p, states):
    model = model_of(p)
    st = states()
    for k in range(len(st[0])):
        q = export.joint_values(model, st[0][k], st[1][k], st[2][k])
        o = sym.kinematics(p, st[0][k], st[1][k], st[2][k])
        for mine, theirs in (("pin", "theta"), ("leg", "l")):
            for pre in ("", "d", "dd"):
                got = [q[f"{pre}{mine}_{i}"] for i in range(3)]
                assert rel(got, o[pre + theirs]) <= TOL, (name, k, pre + theirs)
        assert np.max(np.abs(q["c"] - o["c"])) <= TOL_POS
        assert np.max(np.abs(q["rot"] - o["rot"])) <= TOL_POS
        assert rel(q["v"], o["dc"]) <= TOL and rel(q["a"], o["ddc"]) <= TOL
        assert rel(q["omega_body"], o["omega_body"]) <= TOL, (name, k)
        assert rel(q["domega_body"], o["domega_body"]) <= TOL, (name, k)
        # the quaternion is the rotation: MuJoCo's conversion back
        back = np.zeros(9)
        mujoco.mju_quat2Mat(back, q["quat"])
        assert np.max(np.abs(back.reshape(3, 3) - q["rot"])) <= TOL_POS


def test_joint_values_refuse_what_the_library_refuses():
    model = rps3.Model()
    with pytest.raises(ValueError, match=r"^pose: \[0\.0, 0\.1, -0\.3\]: .*unreachable"):
        export.joint_values(model, [0.0, 0.1, -0.3])
    with pytest.raises(ValueError, match=r"^dpose: "):
        export.joint_values(model, [0.0, 0.1, 0.3], [np.nan, 0, 0])


# ------------------------------------------------------------------ MJCF

def mj_state(mj, q):
    """MuJoCo's qpos, qvel, qacc from joint_values."""
    kin = {"theta": [q[f"pin_{i}"] for i in range(3)], "l": [q[f"leg_{i}"] for i in range(3)],
           "c": q["c"], "rot": q["rot"], "dc": q["v"], "ddc": q["a"],
           "omega_body": q["omega_body"], "domega_body": q["domega_body"]}
    for pre in ("d", "dd"):
        kin[pre + "theta"] = [q[f"{pre}pin_{i}"] for i in range(3)]
        kin[pre + "l"] = [q[f"{pre}leg_{i}"] for i in range(3)]
    return mujoco_model.state(mj, kin)


def test_mjcf_loads_with_visible_bodies():
    p = oracle.ENTROPY
    mj = mujoco.MjModel.from_xml_string(export.mjcf(model_of(p)))
    assert (mj.nq, mj.nv, mj.nu, mj.neq) == (13, 12, 3, 3)
    assert (mj.eq_type == mujoco.mjtEq.mjEQ_CONNECT).all()
    # every moving body can be seen
    assert mj.ngeom >= 16
    for b in range(1, mj.nbody):
        assert mj.body_geomnum[b] > 0, mj.body(b).name
    # the geoms are drawings: no contacts, no mass (the parameters' masses)
    assert (mj.geom_contype == 0).all() and (mj.geom_conaffinity == 0).all()
    total = p["M"] + 3 * p["m"] + p["payload"]["mass"]
    assert abs(mj.body_subtreemass[0] - total) < 1e-9
    assert mj.numeric("rps3_pin_coulomb").data[0] == p["friction"]["coulomb"]


@pytest.mark.parametrize("name,p,states", CASES, ids=IDS)
def test_mjcf_kinematics_and_inverse_dynamics_are_rps3s(name, p, states):
    model = model_of(p)
    mj = mujoco.MjModel.from_xml_string(export.mjcf(model))
    data = mujoco.MjData(mj)
    st = states()
    out = model.inverse(*st)
    assert out.ok.all()
    g = rps3.view.geometry(model, st[0])
    Fm = np.zeros_like(out.force)
    jp, jq = np.zeros((3, mj.nv)), np.zeros((3, mj.nv))
    for k in range(len(Fm)):
        q = export.joint_values(model, st[0][k], st[1][k], st[2][k])
        qpos, qvel, qacc = mj_state(mj, q)
        data.qpos[:] = qpos
        mujoco.mj_kinematics(mj, data)
        mujoco.mj_comPos(mj, data)
        for i in range(3):
            for site in (f"ball_{i}", f"ball_{i}_link"):
                assert np.max(np.abs(data.site(site).xpos - g.ball[k, i])) <= TOL_POS, \
                    (name, k, site)
            # both sides of a ball joint move together
            mujoco.mj_jacSite(mj, data, jp, None, mj.site(f"ball_{i}").id)
            mujoco.mj_jacSite(mj, data, jq, None, mj.site(f"ball_{i}_link").id)
            vb = jp @ qvel
            assert np.max(np.abs(vb - jq @ qvel)) <= TOL * max(np.max(np.abs(vb)), 1e-3)
        Fm[k] = mujoco_model.actuator_forces(mj, data, qpos, qvel, qacc, p)
    assert rel(out.force, Fm) <= TOL, (name, out.force, Fm)


def general_model():
    """General bodies (an offset platform with products of inertia, each
    leg's cylinder and piston its own), friction in every joint (the pins'
    Coulomb shared: the MuJoCo oracle adds one), every effect."""
    B = rps3.Body
    legs = [dict(cylinder=B(0.07 + 0.01 * i, (0.09, 0.002 * i, -0.004),
                            [[2e-5, 0, 1e-6], [0, 6e-4, 0], [1e-6, 0, 6e-4]]),
                 piston=B(0.03, (-0.05, 0.0, 0.001 * i), (5e-6, 8e-5, 8e-5)))
            for i in range(3)]
    plat = B(0.2, (0.004, -0.003, 0.012),
             [[1.2e-3, 1e-5, -2e-5], [1e-5, 1.1e-3, 3e-5], [-2e-5, 3e-5, 2.2e-3]])
    fr = [dict(viscous=0.01 + 0.004 * i, coulomb=0.003) for i in range(3)]
    return rps3.Model(R=0.2385, rho=0.4387, bodies=dict(platform=plat, legs=legs),
                      friction=fr,
                      prismatic_friction=dict(viscous=0.4, coulomb=0.05),
                      effects=EFF_ALL)


def test_mjcf_of_general_bodies_is_rps3s():
    """The exported bodies and joint friction of a general model: MuJoCo's
    inverse dynamics of the MJCF give rps3's forces (TOL)."""
    model = general_model()
    mj = mujoco.MjModel.from_xml_string(export.mjcf(model))
    data = mujoco.MjData(mj)
    st = sines()
    out = model.inverse(*st)
    assert out.ok.all()
    p = dict(friction=dict(coulomb=0.003), prismatic=dict(viscous=0.4, coulomb=0.05))
    Fm = np.zeros_like(out.force)
    for k in range(len(Fm)):
        q = export.joint_values(model, st[0][k], st[1][k], st[2][k])
        qpos, qvel, qacc = mj_state(mj, q)
        Fm[k] = mujoco_model.actuator_forces(mj, data, qpos, qvel, qacc, p)
    assert rel(out.force, Fm) <= TOL, (out.force, Fm)
    # the paper's bodies give other forces: the bodies were exported
    paper = rps3.Model(R=0.2385, rho=0.4387, effects=EFF_ALL)
    assert rel(paper.inverse(*st).force, Fm) > 1e-3


# ------------------------------------------------------------------ URDF

def pin_model(model):
    pm = pin.buildModelFromXML(export.urdf(model))
    pm.gravity.linear = np.array([0.0, 0.0, -model.g])  # URDF has no gravity
    return pm


def pin_q(pm, q, pre=""):
    """Pinocchio's q (pre "") or v (pre "d") or a (pre "dd") from joint_values."""
    free = pm.joints[pm.getJointId("platform_free")]
    out = np.zeros(pm.nq if pre == "" else pm.nv)
    for i in range(3):
        for name in (f"pin_{i}", f"leg_{i}"):
            j = pm.joints[pm.getJointId(name)]
            out[j.idx_q if pre == "" else j.idx_v] = q[pre + name]
    rot = q["rot"]
    if pre == "":
        w, x, y, z = q["quat"]
        out[free.idx_q:free.idx_q + 7] = [*q["c"], x, y, z, w]
    elif pre == "d":
        # the free flyer's velocity in its local frame
        out[free.idx_v:free.idx_v + 6] = [*(rot.T @ q["v"]), *q["omega_body"]]
    else:
        # its spatial acceleration in the local frame: the classical
        # acceleration less omega x v (both local)
        w, v = q["omega_body"], rot.T @ q["v"]
        out[free.idx_v:free.idx_v + 6] = [*(rot.T @ q["a"] - np.cross(w, v)),
                                          *q["domega_body"]]
    return out


def test_urdf_loads_with_its_loops():
    p = oracle.ENTROPY
    model = model_of(p)
    text = export.urdf(model)
    pm = pin_model(model)
    assert (pm.nq, pm.nv) == (13, 12)
    names = {f.name for f in pm.frames}
    loops = export.loops(text)
    assert [lp["name"] for lp in loops] == ["ball_0", "ball_1", "ball_2"]
    for lp in loops:
        assert lp["type"] == "ball" and {lp["frame1"], lp["frame2"]} <= names
    total = p["M"] + 3 * p["m"] + p["payload"]["mass"]
    # the pistons carry EPS_MASS, as in the MJCF (forward dynamics needs a
    # positive definite mass matrix)
    assert abs(pin.computeTotalMass(pm) - total - 3 * export.EPS_MASS) < 1e-15
    # the visuals are there for viewers: base, 3 barrels, 3 pistons, 3
    # balls, the platform
    gm = pin.buildGeomFromUrdfString(pm, text, pin.GeometryType.VISUAL)
    assert gm.ngeoms == 11


@pytest.mark.parametrize("name,p,states", CASES, ids=IDS)
def test_urdf_kinematics_and_inverse_dynamics_are_rps3s(name, p, states):
    """Pinocchio's spanning tree, closed by the URDF's rps3:loop elements."""
    model = model_of(p)
    text = export.urdf(model)
    pm = pin_model(model)
    pd = pm.createData()
    loops = export.loops(text)
    st = states()
    out = model.inverse(*st)
    g = rps3.view.geometry(model, st[0])
    legs = [pm.joints[pm.getJointId(f"leg_{i}")].idx_v for i in range(3)]
    pins_v = [pm.joints[pm.getJointId(f"pin_{i}")].idx_v for i in range(3)]
    fr = p["friction"]
    for k in range(len(st[0])):
        jv = export.joint_values(model, st[0][k], st[1][k], st[2][k])
        q, v, a = (pin_q(pm, jv, pre) for pre in ("", "d", "dd"))
        pin.forwardKinematics(pm, pd, q, v, a)
        pin.updateFramePlacements(pm, pd)
        pin.computeJointJacobians(pm, pd, q)
        cols = []
        for i, lp in enumerate(loops):
            f1, f2 = pm.getFrameId(lp["frame1"]), pm.getFrameId(lp["frame2"])
            for f in (f1, f2):
                # the ball joint seen from the platform and from the leg
                assert np.max(np.abs(pd.oMf[f].translation - g.ball[k, i])) <= TOL_POS, \
                    (name, k, pm.frames[f].name)
            v1 = pin.getFrameVelocity(pm, pd, f1, pin.LOCAL_WORLD_ALIGNED).linear
            v2 = pin.getFrameVelocity(pm, pd, f2, pin.LOCAL_WORLD_ALIGNED).linear
            assert np.max(np.abs(v1 - v2)) <= TOL * max(np.max(np.abs(v1)), 1e-3)
            J1 = pin.getFrameJacobian(pm, pd, f1, pin.LOCAL_WORLD_ALIGNED)[:3]
            J2 = pin.getFrameJacobian(pm, pd, f2, pin.LOCAL_WORLD_ALIGNED)[:3]
            cols.append((J1 - J2).T)
        # the platform frame is rps3's
        P = pd.oMf[pm.getFrameId("platform")]
        assert np.max(np.abs(P.rotation - jv["rot"])) <= TOL_POS
        # generalised forces of the tree (RNEA: inertia, bias, gravity) and
        # the pin friction, balanced by the motors on the legs and the
        # three closures' reactions
        need = pin.rnea(pm, pd, q, v, a).copy()
        for j in pins_v:
            need[j] += fr["viscous"] * v[j] + fr["coulomb"] * np.sign(v[j])
        B = np.zeros((pm.nv, 3))
        for i, j in enumerate(legs):
            B[j, i] = 1.0
        x = np.linalg.solve(np.hstack(cols + [B]), need)
        assert rel(x[9:], out.force[k]) <= TOL, (name, k, x[9:], out.force[k])


def closures(pm, text):
    """Pinocchio's constraint models of the URDF's rps3:loop elements, as
    docs/visualisation.md builds them."""
    models = pin.StdVec_RigidConstraintModel()
    for lp in export.loops(text):
        f1 = pm.frames[pm.getFrameId(lp["frame1"])]
        f2 = pm.frames[pm.getFrameId(lp["frame2"])]
        models.append(pin.RigidConstraintModel(
            pin.ContactType.CONTACT_3D, pm, f1.parentJoint, f1.placement,
            f2.parentJoint, f2.placement, pin.ReferenceFrame.LOCAL))
    datas = pin.StdVec_RigidConstraintData()
    for c in models:
        datas.append(c.createData())
    return models, datas


def rps3_fwddyn(model, l, dl, F):
    """ddl of the library's forward dynamics (rps3_fwddyn), through cffi."""
    from rps3._rps3 import lib
    d = model._workspace()
    d.l[0:3], d.dl[0:3], d.F[0:3] = list(l), list(dl), list(F)
    assert lib.rps3_fwddyn(model._c, d) == lib.RPS3_OK
    return np.array(list(d.ddl))


@pytest.mark.parametrize("name,p,states", CASES, ids=IDS)
def test_urdf_closed_forward_dynamics_is_rps3s(name, p, states):
    """The URDF's tree closed by its loops accelerates the legs as
    rps3_fwddyn does, under high-entropy forces: Pinocchio's mass matrix
    (CRBA), bias forces (RNEA at zero acceleration) and frame Jacobians,
    the closures' J a = -(J' v) solved with the dynamics as one system
    (LU with pivoting: the pistons' EPS_MASS = 1e-12 kg makes M nearly
    singular, while the closed system is well-posed; it moves ddl by ~1e-11
    of it).  Pinocchio's own constraintDynamics agrees to CONSTRAINED_TOL:
    its Cholesky factors M itself and loses the digits the 1e-12 kg costs."""
    model = model_of(p)
    text = export.urdf(model)
    pm = pin_model(model)
    pd = pm.createData()
    models, datas = closures(pm, text)
    pin.initConstraintDynamics(pm, pd, models, datas)
    st = states()
    rng = np.random.default_rng(77)
    legs = [pm.joints[pm.getJointId(f"leg_{i}")].idx_v for i in range(3)]
    pins_v = [pm.joints[pm.getJointId(f"pin_{i}")].idx_v for i in range(3)]
    fr = p["friction"]
    frames = [(pm.getFrameId(lp["frame1"]), pm.getFrameId(lp["frame2"]))
              for lp in export.loops(text)]
    for k in range(len(st[0])):
        jv = export.joint_values(model, st[0][k], st[1][k])
        q, v = pin_q(pm, jv), pin_q(pm, jv, "d")
        F = rng.uniform(-2.0, 4.0, 3)
        tau = np.zeros(pm.nv)
        tau[legs] = F
        tau[pins_v] = -(fr["viscous"] * v[pins_v] + fr["coulomb"] * np.sign(v[pins_v]))
        want = rps3_fwddyn(model, [jv[f"leg_{i}"] for i in range(3)],
                           [jv[f"dleg_{i}"] for i in range(3)], F)
        M = pin.crba(pm, pd, q)
        M = np.triu(M) + np.triu(M, 1).T
        h = pin.rnea(pm, pd, q, v, np.zeros(pm.nv))
        pin.forwardKinematics(pm, pd, q, v, np.zeros(pm.nv))
        pin.computeJointJacobians(pm, pd, q)
        J, gamma = [], []
        for f1, f2 in frames:
            J.append(pin.getFrameJacobian(pm, pd, f1, pin.LOCAL_WORLD_ALIGNED)[:3] -
                     pin.getFrameJacobian(pm, pd, f2, pin.LOCAL_WORLD_ALIGNED)[:3])
            gamma.append(
                pin.getFrameClassicalAcceleration(pm, pd, f1, pin.LOCAL_WORLD_ALIGNED).linear -
                pin.getFrameClassicalAcceleration(pm, pd, f2, pin.LOCAL_WORLD_ALIGNED).linear)
        J, gamma = np.vstack(J), np.concatenate(gamma)
        kkt = np.block([[M, J.T], [J, np.zeros((9, 9))]])
        a = np.linalg.solve(kkt, np.concatenate([tau - h, -gamma]))[:pm.nv]
        assert rel(a[legs], want) <= TOL, (name, k, a[legs], want)
        a = pin.constraintDynamics(pm, pd, q, v, tau, models, datas)
        assert rel(a[legs], want) <= CONSTRAINED_TOL, (name, k, a[legs], want)


def test_the_docs_examples_run():
    """docs/visualisation.md's MuJoCo and Pinocchio examples, as written:
    MuJoCo's sites meet at the set pose, Pinocchio's loops are closed."""
    import re
    with open(os.path.join(oracle.ROOT, "docs", "visualisation.md")) as f:
        blocks = re.findall(r"```python\n(.*?)```", f.read(), re.S)
    ns = {"rps3": rps3, "model": rps3.Model(), "pose": [0.31, 0.12, 0.29],
          "dpose": [0.21, 0.03, 0.05]}
    ran = 0
    for block in blocks:
        if "export.mjcf" in block or "export.urdf" in block:
            exec(block, ns)
            ran += 1
    assert ran == 2
    m, d = ns["m"], ns["d"]
    mujoco.mj_kinematics(m, d)
    assert mujoco_model.closure_residual(m, d) <= TOL_POS
    pm, pd = ns["pm"], ns["pd"]
    for c, cd in zip(ns["loops"], ns["datas"]):
        c.calc(pm, pd, cd)
        assert np.linalg.norm(cd.c1Mc2.translation) <= TOL_POS
    assert np.isfinite(ns["a"]).all()


RENDER = r"""
import json, sys
import mujoco, numpy as np, rps3
model = rps3.Model()
m = mujoco.MjModel.from_xml_string(rps3.export.mjcf(model))
d = mujoco.MjData(m)
q = rps3.export.joint_values(model, [0.6, 0.12, 0.3])
for i in range(3):
    d.joint(f"pin_{i}").qpos = q[f"pin_{i}"]
    d.joint(f"leg_{i}").qpos = q[f"leg_{i}"]
d.joint("platform").qpos = [*q["c"], *q["quat"]]
mujoco.mj_forward(m, d)
cam = mujoco.MjvCamera()
cam.lookat[:] = [0, 0, 0.15]
cam.distance, cam.azimuth, cam.elevation = 0.9, -60, -20
r = mujoco.Renderer(m, 240, 320)
r.update_scene(d, cam)            # MuJoCo's default visibility (viewer's)
px = r.render().reshape(-1, 3).astype(int)
print(json.dumps({"px": px.tolist()}))
"""


def test_mujoco_renders_the_mechanism(tmp_path):
    """MuJoCo's own renderer (offscreen, EGL) shows the exported model at a
    pose: the platform's and the links' colours cover a good part of the
    320 x 240 image (measured: 1026 and 1175 pixels; the same model without
    its geoms, as the oracle's was, renders 0 and 0)."""
    import json
    import subprocess
    import sys
    env = dict(os.environ, MUJOCO_GL="egl")
    proc = subprocess.run([sys.executable, "-c", RENDER], capture_output=True, text=True,
                          env=env, timeout=300)
    if proc.returncode != 0:
        pytest.skip(f"MuJoCo cannot render offscreen here (EGL): "
                    f"{proc.stderr.strip().splitlines()[-1:]}")
    px = np.array(json.loads(proc.stdout)["px"])
    # lit colours vary: classify by hue (orange platform: R > G > B,
    # blue links: B > R)
    r, g, b = px[:, 0], px[:, 1], px[:, 2]
    platform = np.sum((r > 120) & (r > g + 20) & (g > b + 20))
    links = np.sum((b > 60) & (b > r + 30))
    assert platform > 500, platform
    assert links > 300, links


def test_urdf_of_general_bodies():
    """The URDF's inertias of a general model, read by Pinocchio: each
    body's mass, centre of mass and inertia about it in its frame, the
    legs' in the link frame at theta = 0 (E = [-u_i, axis_i, -u_i x
    axis_i]); the prismatic joints' friction as damping and rps3 elements."""
    model = general_model()
    text = export.urdf(model)
    pm = pin_model(model)
    b = model.bodies
    plat = pm.inertias[pm.getJointId("platform_free")]
    assert plat.mass == pytest.approx(b["platform"].mass, rel=1e-15)
    assert np.allclose(plat.lever, b["platform"].com, rtol=0, atol=1e-15)
    assert np.allclose(plat.inertia, b["platform"].inertia, rtol=1e-12, atol=1e-18)
    for i in range(3):
        psi = 2 * np.pi * i / 3
        u = np.array([np.cos(psi), np.sin(psi), 0.0])
        ax = np.array([-np.sin(psi), np.cos(psi), 0.0])
        E = np.column_stack([-u, ax, np.cross(-u, ax)])
        for joint, part in ((f"pin_{i}", "cylinder"), (f"leg_{i}", "piston")):
            body = b["legs"][i][part]
            Y = pm.inertias[pm.getJointId(joint)]
            assert Y.mass == pytest.approx(body.mass, rel=1e-12), (joint, part)
            assert np.allclose(Y.lever, E @ body.com, rtol=0, atol=1e-15)
            want = E @ body.inertia @ E.T
            got = Y.inertia - (np.eye(3) * export.EPS_INERTIA if part == "piston" else 0)
            assert np.allclose(got, want, rtol=1e-12, atol=1e-15), (joint, part)
        assert f'<rps3:prismatic_friction leg="{i}" viscous="0.40000000000000002"' in text

