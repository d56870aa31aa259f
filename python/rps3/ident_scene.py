"""The identified model as a scene's ``manipulator:`` section
(docs/identification.md, "Data in, parameters out"): ``manipulator_yaml``
of a :class:`rps3.ident_io.Fit`, the general bodies rounded onto real ones
(``scene_body``), and ``fitted_model``, the rps3.Model of what is written.
rps3.ident_io re-exports its public names."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from rps3 import ident as _id
from rps3.ident_io import Fit


def manipulator_yaml(result: Fit) -> str:
    """A ``manipulator:`` section with the fitted M, m, d, link_Ic,
    payload, friction (and the geometry's R, rho, g) that a scene can use
    as it is; or, when the fit does not map onto them, a YAML comment
    saying why and no section.  A general layout's fit: the general
    bodies of its consistent fit (:func:`scene_bodies`)."""
    if result.layout is not None:
        return _general_yaml(result)
    a = result.model_arguments
    if a is None:
        return f"# the fit does not map onto the manipulator section: {result.mapping}\n"
    g = result.geometry

    num = _num
    lines = ["# identified by rps3.ident (docs/identification.md)", "manipulator:",
             f"  R: {num(g.R)}", f"  rho: {num(g.rho)}", f"  M: {num(a['M'])}",
             f"  m: {num(a['m'])}", f"  d: {num(a['d'])}", f"  link_Ic: {num(a['link_Ic'])}",
             f"  g: {num(g.g)}"]
    if "payload" in a:
        p = a["payload"]
        lines += ["  payload:", f"    mass: {num(p['mass'])}",
                  f"    com: [{', '.join(num(x) for x in p['com'])}]",
                  f"    inertia: [{', '.join(num(x) for x in p['inertia'])}]"]
    if "friction" in a:
        fr = a["friction"]
        lines += ["  pin_friction:", f"    viscous: {num(fr['viscous'])}",
                  f"    coulomb: {num(fr['coulomb'])}"]
        if result.geometry.vreg > 0:
            lines.append(f"    vreg: {num(result.geometry.vreg)}")
    return "\n".join(lines) + "\n"


def _num(x: float) -> str:
    """A float as YAML reads it back exactly (repr), with a decimal point
    in the mantissa (YAML 1.1 readers take 1e-05 for a string)."""
    r = repr(float(x))
    if "e" in r and "." not in r:
        m, _, e = r.partition("e")
        r = f"{m}.0e{e}"
    return r


#: a body's mass at or below this fraction of its pseudo-inertia's largest
#: eigenvalue is written massless: its centre of mass, first moment over
#: mass, is then rounding over rounding
MASS_REL = 1e-12


@dataclass(frozen=True)
class SceneBody:
    """A body as a scene's ``manipulator:`` section gives it: mass [kg],
    com [m] (3,), inertia [Ixx, Ixy, Ixz, Iyy, Iyz, Izz] about the com
    [kg m^2] (6,); ``moved``: how far its standard parameters are from
    those it was made from, relative to its pseudo-inertia's largest
    eigenvalue (the projection onto a real body's, see
    :func:`scene_body`)."""

    mass: float
    com: np.ndarray
    inertia: np.ndarray
    moved: float


def scene_body(p10: Any) -> SceneBody:
    """The body of ten standard parameters (m, m c, inertia about the
    frame's origin) in a scene's terms, made acceptable to the library's
    check (rps3_model_init: the second moment about the centre of mass,
    Sigma_c = tr(I_c)/2 1 - I_c, positive semidefinite to 1e-12 of its
    trace).  A consistent fit's pseudo-inertia is positive semidefinite
    only to its eigenvalue tolerance, and its bodies often lie on the
    cone's boundary (a point mass or a rod: Sigma_c singular), where the
    parallel-axis theorem's cancellation, m |c|^2 against I_o, leaves
    Sigma_c's zero eigenvalues a rounding below zero: they are set to
    zero (Sigma_c's eigenvalues clipped at 0) and ``moved`` says by how
    much the standard parameters changed.  A mass <= 0, or at most
    MASS_REL of the pseudo-inertia's scale, is written as a massless body
    (com [0, 0, 0], the inertia about the origin)."""
    p = np.asarray(p10, float)
    J = _id.pseudo_inertia(p)
    big = max(float(np.abs(np.linalg.eigvalsh(J)).max()), 1e-300)
    Io = _id.inertia_matrix(p)
    if p[0] <= MASS_REL * big:
        mass, c, Ic = 0.0, np.zeros(3), Io
    else:
        mass = float(p[0])
        c = p[1:4] / mass
        Ic = Io - mass * (c @ c * np.eye(3) - np.outer(c, c))
    Sig = 0.5 * np.trace(Ic) * np.eye(3) - Ic
    w, V = np.linalg.eigh(0.5 * (Sig + Sig.T))
    Sig = (V * np.clip(w, 0.0, None)) @ V.T
    Ic = np.trace(Sig) * np.eye(3) - Sig
    six = np.array([Ic[0, 0], Ic[0, 1], Ic[0, 2], Ic[1, 1], Ic[1, 2], Ic[2, 2]])
    back = _id.body_parameters(mass, c, Ic)
    return SceneBody(mass, c, six, float(np.abs(back - p).max() / big))


def scene_bodies(result: Fit) -> dict[str, SceneBody]:
    """The layout's bodies (rps3.ident.Layout.bodies' names) of a general
    fit's consistent fit, as :func:`scene_body` writes them."""
    if result.layout is None or result.consistent_fit is None:
        raise ValueError("result: not a general layout's fit with a consistent fit")
    pi = result.consistent_fit.pi
    return {b: scene_body(pi[10 * k:10 * k + 10])
            for k, b in enumerate(result.layout.bodies)}


def _friction(result: Fit) -> dict[str, list[tuple[float, float]]]:
    """Per friction kind of the layout, (viscous, coulomb) per leg."""
    lay = result.layout
    assert lay is not None and result.standard is not None
    std = result.standard
    out = {}
    for k, kind in enumerate(_id.FRICTION_KINDS):
        if kind in lay.friction:
            j = _id.N_BODY_PARAMETERS + 6 * k
            # >= 0 columns of the fit: a square, exact; clipped anyway
            out[kind] = [(max(float(std[j + 2 * i]), 0.0), max(float(std[j + 2 * i + 1]), 0.0))
                         for i in range(3)]
    return out


def fitted_model(result: Fit, **kw: Any) -> Any:
    """An rps3.Model of the general fit's consistent bodies and friction
    as :func:`manipulator_yaml` writes them (the geometry's R, rho, g, the
    friction laws' vreg), the effects of the layout (the paper's four and
    its friction kinds) unless ``effects`` is given; kw passed on."""
    from rps3.body import Body
    from rps3.model import DEFAULT_EFFECTS, Model

    bodies = scene_bodies(result)
    lay = result.layout
    assert lay is not None
    B = {k: Body(b.mass, b.com, b.inertia) for k, b in bodies.items()}
    if lay.legs == "each":
        bd: dict[str, Any] = dict(platform=B["platform"], legs=[
            dict(cylinder=B[f"cylinder{i}"], piston=B[f"piston{i}"]) for i in (1, 2, 3)])
    else:
        bd = dict(platform=B["platform"], cylinder=B["cylinder"], piston=B["piston"])
    geo = result.geometry
    fr = {kind: [dict(viscous=v, coulomb=c, vreg=geo.vreg_of(kind)) for v, c in laws]
          for kind, laws in _friction(result).items()}
    effects = kw.pop("effects", [*DEFAULT_EFFECTS, *(f"{k}_friction" for k in fr)])
    return Model(R=geo.R, rho=geo.rho, g=geo.g, bodies=bd, friction=fr.get("pin"),
                 prismatic_friction=fr.get("prismatic"), effects=effects, **kw)


def _general_yaml(result: Fit) -> str:
    lay = result.layout
    assert lay is not None
    if result.consistent_fit is None or not result.consistent:
        why = result.consistency.splitlines()[0] if result.consistency else "no consistent fit"
        return f"# the fit has no physically consistent bodies to write: {why}\n"
    bodies = scene_bodies(result)
    geo = result.geometry
    fr = _friction(result)
    num = _num

    def vec(v: Any) -> str:
        return "[" + ", ".join(num(x) for x in v) + "]"

    def body(name: str, b: SceneBody, ind: str) -> list[str]:
        return [f"{ind}{name}: {{mass: {num(b.mass)}, com: {vec(b.com)}, "
                f"inertia: {vec(b.inertia)}}}"]

    def friction(kind: str, law: tuple[float, float], ind: str) -> list[str]:
        return [f"{ind}{kind}_friction: {{viscous: {num(law[0])}, coulomb: {num(law[1])}, "
                f"vreg: {num(geo.vreg_of(kind))}}}"]

    moved = max(b.moved for b in bodies.values())
    lines = ["# identified by rps3.ident (docs/identification.md): general bodies of the",
             f"# consistent fit of the layout legs={lay.legs}, friction="
             f"{','.join(lay.friction) or 'none'}; inertia about each body's centre of",
             "# mass; the bodies rounded onto real ones moved the standard parameters by",
             f"# at most {moved:.2g} of a body's pseudo-inertia scale"]
    if not result.consistent_fit.converged:
        lines.append("# warning: the consistent fit stopped short of its optimality test "
                     "(consistent, maybe not optimal): "
                     + " ".join(result.consistent_fit.message.split()))
    lines += ["manipulator:", f"  R: {num(geo.R)}", f"  rho: {num(geo.rho)}",
             f"  g: {num(geo.g)}", "  bodies: general"]
    lines += body("platform", bodies["platform"], "  ")
    shared = [k for k in fr if not lay.per_leg]
    if lay.legs == "identical" or shared:
        lines.append("  legs:")
        if lay.legs == "identical":
            lines += body("cylinder", bodies["cylinder"], "    ")
            lines += body("piston", bodies["piston"], "    ")
        for k in shared:
            lines += friction(k, fr[k][0], "    ")
    for i in (1, 2, 3):
        own = [k for k in fr if lay.per_leg]
        if lay.legs == "each" or own:
            lines.append(f"  leg{i}:")
        if lay.legs == "each":
            lines += body("cylinder", bodies[f"cylinder{i}"], "    ")
            lines += body("piston", bodies[f"piston{i}"], "    ")
        for k in own:
            lines += friction(k, fr[k][i - 1], "    ")
    text = "\n".join(lines) + "\n"
    # the library's own check, which the runner runs (rps3_model_init), on
    # the very numbers written (repr reads back exactly)
    try:
        fitted_model(result)
    except ValueError as exc:       # not expected: scene_body projects onto it
        return f"# the fitted bodies are refused by the library: {exc}\n"
    return text
