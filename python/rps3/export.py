"""The manipulator as a model for other tools: MJCF (MuJoCo) and URDF
(Pinocchio, ROS), and the joint values of a pose in their terms.

    import rps3
    model = rps3.Model()
    open("rps3.xml", "w").write(rps3.export.mjcf(model))    # MuJoCo
    open("rps3.urdf", "w").write(rps3.export.urdf(model))   # Pinocchio, ROS
    q = rps3.export.joint_values(model, [0.3, 0.1, 0.3])    # by joint name

Both describe the same tree (docs/visualisation.md), world frame = rps3's
base frame (Z up, X towards pin 1):

- ``link_i``: a body at pin P_i with the revolute joint ``pin_i`` about the
  pin axis; at angle 0 the link points inwards along -u_i (u_i the pin's
  radial direction), so the joint's angle is theta_i.  Its mass m sits at d
  along the link, with the centroidal moment link_Ic about every axis.
- ``piston_i``: a child of ``link_i`` with the prismatic joint ``leg_i``
  along the link; its value is the link length l_i.  Massless in rps3.  Its
  frame ``ball_i_link`` is ball joint i's centre, seen from the leg.
- ``platform``: a free body (MJCF joint ``platform``, URDF floating joint
  ``platform_free``) at the platform centre, axes as
  rps3's platform frame; the uniform disc of (21) (mass M, moments M r^2/4,
  M r^2/4, M r^2/2); frames ``ball_i`` at r_i, ball joint i seen from the
  platform; the payload (its mass, centre of mass and principal moments)
  fixed to it.
- the three loops close at the ball joints: ``ball_i`` and ``ball_i_link``
  coincide.  MJCF says so with equality ``connect`` constraints (MuJoCo
  simulates the closed mechanism); URDF cannot express a loop, so the
  closures are ``<rps3:loop>`` elements (namespace ``urn:rps3``) that URDF
  parsers skip and a Pinocchio user turns into RigidConstraintModels
  (docs/visualisation.md shows how).

A model of general bodies (``Model(bodies=...)``) is exported with its
bodies: the platform's inertial (centre of mass and full inertia tensor)
in its frame, each cylinder's in its link's frame and each piston's in
its own (the legs' axes at theta = 0 are E = [-u_i, axis_i, -u_i x
axis_i]), each pin's and prismatic joint's viscous friction as the joint's
damping.

What the formats cannot hold: rps3's effect selection (the exports are the
whole physical mechanism: compare them with every effect selected), and the
Coulomb friction (MuJoCo's frictionloss is a soft constraint, not the
library's law): the pins' is written as the custom number
``rps3_pin_coulomb`` (three numbers where the legs differ) in MJCF and as
the ``coulomb`` attribute of ``<rps3:pin_friction>`` in URDF, the prismatic
joints' as ``rps3_prismatic_coulomb`` and ``<rps3:prismatic_friction>``.
The viscous part is the joints' damping.  Masses: MuJoCo refuses moving
bodies without mass and Pinocchio's forward dynamics needs a positive
definite mass matrix, so the pistons (and in MJCF massless links or
platform) carry EPS_MASS = 1e-12 kg, 1e-11 N at 10 m/s^2 against forces of
~1 N.  URDF carries no gravity: set Pinocchio's ``model.gravity`` from
``Model.g``.

Geoms and visuals are drawings only (no mass, no contacts): the link's
cylinder from the pin, ``barrel`` long (R by default, as in rps3.view), the
piston from the ball joint, ``barrel`` long, spheres at the ball joints,
the platform disc, the pin shafts and the base triangle.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from rps3._core import FloatArray, strerror
from rps3._rps3 import lib
from rps3.model import Model

# MuJoCo refuses moving bodies lighter than mjMINVAL (1e-15); the massless
# pistons (and massless links) get this much, 1e-12 kg: 1e-11 N at 10 m/s^2
# against forces of ~1 N
EPS_MASS = 1e-12
EPS_INERTIA = 1e-12

#: the namespace of the loop closures and other rps3 elements in the URDF
URDF_NS = "urn:rps3"


def _fmt(v: Any) -> str:
    return " ".join(f"{x:.17g}" for x in np.atleast_1d(np.asarray(v, float)))


def _params(model: Model, barrel: float | None) -> dict[str, Any]:
    """The model's inputs and the drawing sizes."""
    c = model._c
    R = float(c.R)
    b = R if barrel is None else float(barrel)
    if not (math.isfinite(b) and b > 0):
        raise ValueError(f"barrel: expected a length > 0 m, got {barrel!r}")
    p = {"R": R, "r": float(c.rho) * R, "M": float(c.M), "m": float(c.m),
         "d": float(c.d), "Ic": float(c.link_Ic), "g": float(c.g),
         "pl_mass": float(c.payload.mass), "pl_com": list(c.payload.com),
         "pl_inertia": list(c.payload.inertia),
         "viscous": float(c.friction.viscous), "coulomb": float(c.friction.coulomb),
         "barrel": b, "general": int(c.bodies) == int(lib.RPS3_BODIES_GENERAL)}
    # each joint's friction: the pins' law (one for the paper's bodies),
    # the prismatic joints'
    p["pin"] = [(float(c.pinf[i].viscous), float(c.pinf[i].coulomb)) for i in range(3)]
    p["prismatic"] = [(float(c.leg[i].prismatic.viscous), float(c.leg[i].prismatic.coulomb))
                      for i in range(3)]
    p["bodies"] = _bodies(c, p)
    return p


def _body(b: Any) -> tuple[float, FloatArray, FloatArray]:
    """An rps3_body's mass, centre of mass and 3 x 3 inertia about it."""
    I = np.array([[b.inertia[0], b.inertia[1], b.inertia[2]],
                  [b.inertia[1], b.inertia[3], b.inertia[4]],
                  [b.inertia[2], b.inertia[4], b.inertia[5]]], float)
    return float(b.mass), np.array(list(b.com), float), I


def _bodies(c: Any, p: dict[str, Any]) -> dict[str, Any]:
    """The inertials in the exported frames (mass, centre of mass, 3 x 3
    inertia about it): the platform's (its own axes), and per leg the
    link's and the piston's, in the link's frame at theta = 0 (world axes:
    the link along -u_i), where the leg's axes are E = [-u_i, axis_i,
    -u_i x axis_i] (docs/identification.md, "The model")."""
    r = p["r"]
    if not p["general"]:
        M, m, Ic = p["M"], p["m"], p["Ic"]
        out: dict[str, Any] = {
            "platform": (M, np.zeros(3), np.diag([M * r * r / 4, M * r * r / 4, M * r * r / 2])),
            "link": [], "piston": []}
        for i in range(3):
            u, _ = _dirs(i)
            out["link"].append((m, -p["d"] * u, np.eye(3) * Ic))
            out["piston"].append((0.0, np.zeros(3), np.zeros((3, 3))))
        return out
    out = {"platform": _body(c.platform), "link": [], "piston": []}
    for i in range(3):
        u, ax = _dirs(i)
        E = np.column_stack([-u, ax, np.cross(-u, ax)])
        for key, b in (("link", c.leg[i].cylinder), ("piston", c.leg[i].piston)):
            mass, com, I = _body(b)
            out[key].append((mass, E @ com, E @ I @ E.T))
    return out


def _mj_inertial(spec: tuple[float, FloatArray, FloatArray], indent: str) -> str:
    """An MJCF inertial of (mass, centre of mass, inertia about it), made
    positive where MuJoCo needs it (EPS_MASS, EPS_INERTIA)."""
    mass, com, I = spec
    I = I + np.eye(3) * EPS_INERTIA * (np.trace(I) <= 3 * EPS_INERTIA)
    full = [I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]]
    return (f'{indent}<inertial pos="{_fmt(com)}" mass="{max(mass, EPS_MASS):.17g}" '
            f'fullinertia="{_fmt(full)}"/>')


def _dirs(i: int) -> tuple[FloatArray, FloatArray]:
    """Pin i's radial direction u_i and axis (-sin psi_i, cos psi_i, 0)."""
    psi = 2 * np.pi * i / 3
    return (np.array([np.cos(psi), np.sin(psi), 0.0]),
            np.array([-np.sin(psi), np.cos(psi), 0.0]))


def mjcf(model: Model, *, barrel: float | None = None, timestep: float = 1e-4) -> str:
    """MJCF text of the manipulator (see the module doc), for MuJoCo.

    Args:
        model: the manipulator.
        barrel: length of the drawn link cylinders and pistons [m]; None: R.
        timestep: MuJoCo's time step [s] (RK4 integrator).

    Returns:
        The MJCF document: bodies with inertias and geoms, hinges ``pin_i``,
        slides ``leg_i``, a free joint ``platform``, sites ``ball_i`` and
        ``ball_i_link``, equality ``connect`` constraints closing the loops,
        motors ``F_i`` on the legs (F > 0 extends).
    """
    if not (math.isfinite(timestep) and timestep > 0):
        raise ValueError(f"timestep: expected a number > 0 s, got {timestep!r}")
    p = _params(model, barrel)
    R, r, bl = p["R"], p["r"], p["barrel"]
    Ic = max(p["Ic"], EPS_INERTIA)
    bd = p["bodies"]
    links, sites, eqs, acts, shafts = [], [], [], [], []
    for i in range(3):
        u, ax = _dirs(i)
        if p["general"]:
            link_in = _mj_inertial(bd["link"][i], "      ")
            piston_in = _mj_inertial(bd["piston"][i], "        ")
        else:
            link_in = (f'      <inertial pos="{_fmt(-p["d"] * u)}" '
                       f'mass="{max(p["m"], EPS_MASS):.17g}"\n'
                       f'                diaginertia="{_fmt([Ic] * 3)}"/>')
            piston_in = (f'        <inertial pos="0 0 0" mass="{EPS_MASS}" '
                         f'diaginertia="{_fmt([EPS_INERTIA] * 3)}"/>')
        slide_damp = (f' damping="{p["prismatic"][i][0]:.17g}"'
                      if p["prismatic"][i][0] else "")
        links.append(f"""
    <body name="link_{i}" pos="{_fmt(R * u)}">
      <joint name="pin_{i}" type="hinge" axis="{_fmt(ax)}" damping="{p['pin'][i][0]:.17g}"/>
{link_in}
      <geom name="barrel_{i}" class="barrel" fromto="0 0 0 {_fmt(-bl * u)}"/>
      <body name="piston_{i}">
        <joint name="leg_{i}" type="slide" axis="{_fmt(-u)}"{slide_damp}/>
{piston_in}
        <geom name="piston_{i}" class="piston" fromto="0 0 0 {_fmt(bl * u)}"/>
        <geom name="ball_{i}_link" class="ball" pos="0 0 0"/>
        <site name="ball_{i}_link" pos="0 0 0"/>
      </body>
    </body>""")
        shafts.append(f'    <geom name="pin_{i}" class="pin" '
                      f'fromto="{_fmt(R * u - 0.12 * R * ax)} {_fmt(R * u + 0.12 * R * ax)}"/>')
        sites.append(f'      <site name="ball_{i}" pos="{_fmt(r * u)}"/>')
        eqs.append(f'    <connect name="ball_{i}" site1="ball_{i}_link" site2="ball_{i}"/>')
        acts.append(f'    <motor name="F_{i}" joint="leg_{i}" gear="1"/>')
        j = (i + 1) % 3
        shafts.append(f'    <geom name="base_{i}{j}" class="base" '
                      f'fromto="{_fmt(R * u)} {_fmt(R * _dirs(j)[0])}"/>')
    payload = ""
    if p["pl_mass"] > 0:
        pl_I = np.maximum(p["pl_inertia"], EPS_INERTIA)
        payload = f"""
      <body name="payload" pos="{_fmt(p['pl_com'])}">
        <inertial pos="0 0 0" mass="{p['pl_mass']:.17g}" diaginertia="{_fmt(pl_I)}"/>
        <geom name="payload" class="payload"/>
      </body>"""
    defaults = "\n".join(
        f'    <default class="{name}"><geom type="{kind}"{size} rgba="{rgba}"/></default>'
        for name, kind, size, rgba in (
            ("barrel", "cylinder", f' size="{0.035 * R:.6g}"', "0.12 0.37 0.66 1"),
            ("piston", "cylinder", f' size="{0.018 * R:.6g}"', "0.56 0.72 0.91 1"),
            ("ball", "sphere", f' size="{0.05 * R:.6g}"', "0.75 0.22 0.17 1"),
            ("pin", "cylinder", f' size="{0.03 * R:.6g}"', "0.1 0.1 0.1 1"),
            ("base", "capsule", f' size="{0.015 * R:.6g}"', "0.3 0.3 0.3 1"),
            ("platform", "cylinder", "", "0.9 0.64 0.24 0.8"),
            ("payload", "sphere", f' size="{0.04 * R:.6g}"', "0.4 0.6 0.3 1")))
    M = p["M"]
    Ip = np.maximum([M * r * r / 4, M * r * r / 4, M * r * r / 2], EPS_INERTIA)
    platform_in = (_mj_inertial(bd["platform"], "      ") if p["general"] else
                   f'      <inertial pos="0 0 0" mass="{max(M, EPS_MASS):.17g}" '
                   f'diaginertia="{_fmt(Ip)}"/>')
    pin_c = sorted({c for _, c in p["pin"]})
    coulomb = (f'    <numeric name="rps3_pin_coulomb" data="{p["pin"][0][1]:.17g}"/>'
               if len(pin_c) == 1 else
               f'    <numeric name="rps3_pin_coulomb" data="{_fmt([c for _, c in p["pin"]])}"/>')
    if any(c for _, c in p["prismatic"]):
        coulomb += ('\n    <!-- Coulomb friction force in each prismatic joint [N] -->\n'
                    f'    <numeric name="rps3_prismatic_coulomb" '
                    f'data="{_fmt([c for _, c in p["prismatic"]])}"/>')
    return f"""<mujoco model="rps3">
  <!-- rps3 {_version()}: the 3-RPS manipulator of Lee & Shah (1988); SI units.
       Geoms are drawings only (no mass: inertias are explicit; no contacts). -->
  <compiler angle="radian" inertiafromgeom="false"/>
  <option gravity="0 0 {-p['g']:.17g}" integrator="RK4" timestep="{timestep:.17g}"/>
  <visual><headlight ambient="0.35 0.35 0.35" diffuse="0.6 0.6 0.6"/></visual>
  <custom>
    <!-- Coulomb pin friction torque [N m] (each pin's where they differ),
         not modelled by MuJoCo here -->
{coulomb}
  </custom>
  <default>
    <geom contype="0" conaffinity="0" group="1"/>
{defaults}
  </default>
  <worldbody>
    <light name="top" pos="0 0 {4 * R:.6g}" dir="0 0 -1"/>
{chr(10).join(shafts)}{''.join(links)}
    <body name="platform">
      <freejoint name="platform"/>
{platform_in}
      <geom name="platform" class="platform" size="{r:.17g} {0.01 * R:.6g}"/>
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


def _version() -> str:
    from rps3._rps3 import ffi
    return str(ffi.string(lib.rps3_version()).decode())


def _rpy_along(v: FloatArray) -> str:
    """URDF rpy turning a cylinder's axis (z) onto the horizontal direction v."""
    return _fmt([0.0, np.pi / 2, math.atan2(v[1], v[0])])


def _inertial(mass: float, pos: Any, diag: Any) -> str:
    I = np.asarray(diag, float)
    I = np.diag(I) if I.shape == (3,) else I
    return (f'    <inertial><origin xyz="{_fmt(pos)}"/><mass value="{mass:.17g}"/>'
            f'<inertia ixx="{I[0, 0]:.17g}" ixy="{I[0, 1]:.17g}" ixz="{I[0, 2]:.17g}" '
            f'iyy="{I[1, 1]:.17g}" iyz="{I[1, 2]:.17g}" izz="{I[2, 2]:.17g}"/></inertial>')


def urdf(model: Model, *, barrel: float | None = None) -> str:
    """URDF text of the manipulator's spanning tree (see the module doc),
    with the three loop closures as ``<rps3:loop>`` elements.

    Args:
        model: the manipulator.
        barrel: length of the drawn link cylinders and pistons [m]; None: R.

    Returns:
        The URDF document.  Joints: revolute ``pin_i`` (theta_i, limits 0
        to pi), prismatic ``leg_i`` (l_i, limits 0 to 10 R), floating
        ``platform_free`` (Pinocchio: a free flyer; a joint's name differs
        from every link's, so that each names one Pinocchio frame), fixed
        joints ``ball_i_fixed`` and ``ball_i_link_fixed`` to the frames
        ``ball_i`` and ``ball_i_link``.  Each closure reads
        ``<rps3:loop name="ball_i" type="ball" frame1="ball_i"
        frame2="ball_i_link"/>``: the origins of the two frames coincide
        (a ball joint: 3 constraints, the rotation free).  Effort and
        velocity limits are not part of rps3's model and are written as 0.
    """
    p = _params(model, barrel)
    R, r, bl = p["R"], p["r"], p["barrel"]
    out = ['<?xml version="1.0"?>',
           f'<!-- rps3 {_version()}: the 3-RPS manipulator of Lee & Shah (1988); SI units.',
           '     URDF holds a tree: the loops close at the ball joints, listed as',
           '     rps3:loop elements at the end (docs/visualisation.md). -->',
           f'<robot name="rps3" xmlns:rps3="{URDF_NS}">',
           '  <material name="base"><color rgba="0.3 0.3 0.3 1"/></material>',
           '  <material name="barrel"><color rgba="0.12 0.37 0.66 1"/></material>',
           '  <material name="piston"><color rgba="0.56 0.72 0.91 1"/></material>',
           '  <material name="ball"><color rgba="0.75 0.22 0.17 1"/></material>',
           '  <material name="platform"><color rgba="0.9 0.64 0.24 1"/></material>',
           '  <link name="base">',
           f'    <visual><origin xyz="0 0 {-0.005 * R:.6g}"/><geometry><cylinder radius="{R:.17g}" '
           f'length="{0.01 * R:.6g}"/></geometry><material name="base"/></visual>',
           '  </link>']
    ball = f'<geometry><sphere radius="{0.05 * R:.6g}"/></geometry><material name="ball"/>'
    for i in range(3):
        u, ax = _dirs(i)
        out += [
            f'  <link name="link_{i}">',
            (_inertial(*p["bodies"]["link"][i]) if p["general"] else
             _inertial(p["m"], -p["d"] * u, [p["Ic"]] * 3)),
            f'    <visual><origin xyz="{_fmt(-bl / 2 * u)}" rpy="{_rpy_along(-u)}"/>'
            f'<geometry><cylinder radius="{0.035 * R:.6g}" length="{bl:.17g}"/></geometry>'
            f'<material name="barrel"/></visual>',
            '  </link>',
            f'  <joint name="pin_{i}" type="revolute">',
            f'    <parent link="base"/><child link="link_{i}"/>',
            f'    <origin xyz="{_fmt(R * u)}" rpy="0 0 0"/><axis xyz="{_fmt(ax)}"/>',
            f'    <limit lower="0" upper="{np.pi:.17g}" effort="0" velocity="0"/>',
            f'    <dynamics damping="{p["pin"][i][0]:.17g}"/>',
            '  </joint>',
            f'  <link name="piston_{i}">',
            (_inertial(max(p["bodies"]["piston"][i][0], EPS_MASS),
                       p["bodies"]["piston"][i][1],
                       p["bodies"]["piston"][i][2] + np.eye(3) * EPS_INERTIA)
             if p["general"] else _inertial(EPS_MASS, [0, 0, 0], [EPS_INERTIA] * 3)),
            f'    <visual><origin xyz="{_fmt(bl / 2 * u)}" rpy="{_rpy_along(u)}"/>'
            f'<geometry><cylinder radius="{0.018 * R:.6g}" length="{bl:.17g}"/></geometry>'
            f'<material name="piston"/></visual>',
            '  </link>',
            f'  <joint name="leg_{i}" type="prismatic">',
            f'    <parent link="link_{i}"/><child link="piston_{i}"/>',
            f'    <origin xyz="0 0 0"/><axis xyz="{_fmt(-u)}"/>',
            f'    <limit lower="0" upper="{10 * R:.17g}" effort="0" velocity="0"/>',
            *([f'    <dynamics damping="{p["prismatic"][i][0]:.17g}"/>']
              if p["prismatic"][i][0] else []),
            '  </joint>',
            f'  <link name="ball_{i}_link"><visual>{ball}</visual></link>',
            f'  <joint name="ball_{i}_link_fixed" type="fixed">',
            f'    <parent link="piston_{i}"/><child link="ball_{i}_link"/><origin xyz="0 0 0"/>',
            '  </joint>']
    M = p["M"]
    out += ['  <link name="platform">',
            (_inertial(*p["bodies"]["platform"]) if p["general"] else
             _inertial(M, [0, 0, 0], [M * r * r / 4, M * r * r / 4, M * r * r / 2])),
            f'    <visual><geometry><cylinder radius="{r:.17g}" length="{0.02 * R:.6g}"/>'
            f'</geometry><material name="platform"/></visual>',
            '  </link>',
            '  <joint name="platform_free" type="floating">',
            '    <parent link="base"/><child link="platform"/><origin xyz="0 0 0"/>',
            '  </joint>']
    for i in range(3):
        u, _ = _dirs(i)
        out += [f'  <link name="ball_{i}"/>',
                f'  <joint name="ball_{i}_fixed" type="fixed">',
                f'    <parent link="platform"/><child link="ball_{i}"/>'
                f'<origin xyz="{_fmt(r * u)}"/>',
                '  </joint>']
    if p["pl_mass"] > 0:
        out += ['  <link name="payload">',
                _inertial(p["pl_mass"], [0, 0, 0], p["pl_inertia"]),
                '  </link>',
                '  <joint name="payload_fixed" type="fixed">',
                f'    <parent link="platform"/><child link="payload"/>'
                f'<origin xyz="{_fmt(p["pl_com"])}"/>',
                '  </joint>']
    out += ['  <!-- loop closures: the origins of frame1 and frame2 coincide (ball joints) -->']
    out += [f'  <rps3:loop name="ball_{i}" type="ball" frame1="ball_{i}" frame2="ball_{i}_link"/>'
            for i in range(3)]
    if len(set(p["pin"])) == 1:
        out += [f'  <rps3:pin_friction viscous="{p["pin"][0][0]:.17g}" '
                f'coulomb="{p["pin"][0][1]:.17g}"/>']
    else:
        out += [f'  <rps3:pin_friction leg="{i}" viscous="{v:.17g}" coulomb="{c:.17g}"/>'
                for i, (v, c) in enumerate(p["pin"])]
    out += [f'  <rps3:prismatic_friction leg="{i}" viscous="{v:.17g}" coulomb="{c:.17g}"/>'
            for i, (v, c) in enumerate(p["prismatic"]) if v or c]
    out += ['</robot>', '']
    return "\n".join(out)


def loops(urdf_text: str) -> list[dict[str, str]]:
    """The loop closures of an rps3 URDF: one dict per ``<rps3:loop>``
    element (name, type, frame1, frame2)."""
    import xml.etree.ElementTree as ET
    root = ET.fromstring(urdf_text)
    return [dict(e.attrib) for e in root.iter(f"{{{URDF_NS}}}loop")]


def _quat(rot: FloatArray) -> FloatArray:
    """Unit quaternion (w, x, y, z) of a rotation matrix, w >= 0."""
    m = np.asarray(rot, float)
    tr = m[0, 0] + m[1, 1] + m[2, 2]
    # the largest of 4w^2, 4x^2, 4y^2, 4z^2 is the one divided by
    k = int(np.argmax([tr, m[0, 0], m[1, 1], m[2, 2]]))
    if k == 0:
        s = 2 * math.sqrt(1 + tr)
        q = [s / 4, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s]
    elif k == 1:
        s = 2 * math.sqrt(1 + m[0, 0] - m[1, 1] - m[2, 2])
        q = [(m[2, 1] - m[1, 2]) / s, s / 4, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s]
    elif k == 2:
        s = 2 * math.sqrt(1 - m[0, 0] + m[1, 1] - m[2, 2])
        q = [(m[0, 2] - m[2, 0]) / s, (m[0, 1] + m[1, 0]) / s, s / 4, (m[1, 2] + m[2, 1]) / s]
    else:
        s = 2 * math.sqrt(1 - m[0, 0] - m[1, 1] + m[2, 2])
        q = [(m[1, 0] - m[0, 1]) / s, (m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, s / 4]
    qa = np.array(q)
    qa /= np.linalg.norm(qa)
    return qa if qa[0] >= 0 else -qa


def joint_values(model: Model, pose: ArrayLike, dpose: ArrayLike | None = None,
                 ddpose: ArrayLike | None = None) -> dict[str, Any]:
    """The exported models' joint values at one pose, by the library's
    kinematics: ``pin_i`` = theta_i [rad], ``leg_i`` = l_i [m] and the
    ``platform`` free joint (position c [m], quaternion ``quat`` (w, x, y,
    z)); with dpose (and ddpose), their rates (and accelerations):
    ``dpin_i``, ``dleg_i``, the platform's linear velocity (world axes)
    ``v`` and angular velocity ``omega_body`` (platform axes), and
    ``dd...``, ``a``, ``domega_body`` likewise.  MuJoCo's free joint takes
    (c, quat) in qpos and (v, omega_body) in qvel; Pinocchio's takes (c,
    x, y, z, w) and, in its local frame, (rot^T v, omega_body).

    Raises:
        ValueError: the library refuses the pose or the rates (its message).
    """
    c = model._c
    d = model._workspace()
    q = np.asarray(pose, float).reshape(-1)
    if q.size != 3:
        raise ValueError(f"pose: expected 3 numbers, got {np.shape(pose)}")
    d.pose[0:3] = [float(x) for x in q]
    out: dict[str, Any] = {}

    def stage(fn: Any, name: str, value: Any) -> None:
        s = fn(c, d)
        if s != lib.RPS3_OK:
            raise ValueError(f"{name}: {np.asarray(value).tolist()}: {strerror(s)}")

    stage(lib.rps3_ik, "pose", pose)
    rot = np.array([list(d.rot[i]) for i in range(3)])
    for i in range(3):
        out[f"pin_{i}"] = float(d.theta[i])
        out[f"leg_{i}"] = float(d.l[i])
    out["c"] = np.array(list(d.c))
    out["rot"] = rot
    out["quat"] = _quat(rot)
    if dpose is None:
        return out
    d.dpose[0:3] = [float(x) for x in np.asarray(dpose, float).reshape(3)]
    stage(lib.rps3_velocity, "dpose", dpose)
    for i in range(3):
        out[f"dpin_{i}"] = float(d.dtheta[i])
        out[f"dleg_{i}"] = float(d.dl[i])
    out["v"] = np.array(list(d.vc))
    out["omega_body"] = rot.T @ np.array(list(d.omega))
    if ddpose is None:
        return out
    d.ddpose[0:3] = [float(x) for x in np.asarray(ddpose, float).reshape(3)]
    stage(lib.rps3_acceleration, "ddpose", ddpose)
    for i in range(3):
        out[f"ddpin_{i}"] = float(d.ddtheta[i])
        out[f"ddleg_{i}"] = float(d.ddl[i])
    out["a"] = np.array(list(d.ac))
    # d/dt (rot^T omega) = rot^T domega: the omega x omega term vanishes
    out["domega_body"] = rot.T @ np.array(list(d.domega))
    return out
