"""A rigid body of the general model (rps3.Model(bodies=...)): its mass,
centre of mass and inertia about it in its own frame (docs/identification.md,
"The model"), as the library's rps3_body holds it."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from rps3._core import FloatArray, real_array, real_number

#: a body's inertia as the library holds it: the tensor's Ixx, Ixy, Ixz,
#: Iyy, Iyz, Izz (rps3_body.inertia)
_TENSOR = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))


@dataclass(frozen=True, eq=False)
class Body:
    """A rigid body of the general model (include/rps3.h rps3_body), in
    its own frame (docs/identification.md, "The model"): the platform's
    is the platform centre with the platform axes; a cylinder's its pin
    with e1 along the link to the platform, e2 the pin axis, e3 = e1 x e2;
    a piston's its ball joint with the cylinder's axes.

    Args:
        mass: [kg].
        com: centre of mass from the frame's origin, body axes (3,) [m].
        inertia: inertia tensor about the centre of mass, body axes
            [kg m^2]: a symmetric (3, 3) array, its six elements (Ixx,
            Ixy, Ixz, Iyy, Iyz, Izz) (tensor elements: Ixy is the
            tensor's, minus the product of inertia), or three principal
            moments along the body axes (3,).  The library checks that
            some mass distribution has it (positive semidefinite second
            moment, the triangle inequality).
    """

    mass: float = 0.0
    com: Any = (0.0, 0.0, 0.0)
    inertia: Any = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", _number(self.mass, "mass"))
        object.__setattr__(self, "com", np.array(_vector(self.com, "com")))
        object.__setattr__(self, "inertia", _tensor(self.inertia, "inertia"))

    @classmethod
    def from_parameters(cls, p10: ArrayLike) -> Body:
        """The body of ten standard parameters (m, m c, inertia about the
        frame's origin: rps3.ident.STANDARD_NAMES' order), by the
        parallel-axis theorem.

        Raises:
            ValueError: a mass <= 0 with a first moment not zero."""
        p = real_array(p10, "p10").reshape(-1)
        if p.size != 10:
            raise ValueError(f"p10: expected 10 standard parameters, got {p.size}")
        mass, h = float(p[0]), p[1:4]
        if mass <= 0:
            if np.any(h != 0):
                raise ValueError(f"p10: mass {mass} with first moment {h.tolist()}")
            c = np.zeros(3)
        else:
            c = h / mass
        I0 = np.array([[p[4], p[5], p[6]], [p[5], p[7], p[8]], [p[6], p[8], p[9]]])
        return cls(mass, c, I0 - mass * (c @ c * np.eye(3) - np.outer(c, c)))

    @property
    def parameters(self) -> FloatArray:
        """The ten standard parameters (m, m c, inertia about the frame's
        origin, tensor elements), as rps3_std_params orders them."""
        c, m = self.com, self.mass
        I0 = self.inertia + m * (c @ c * np.eye(3) - np.outer(c, c))
        return np.array([m, *(m * c), *(I0[i, j] for i, j in _TENSOR)])

    def _set(self, cb: Any) -> None:
        cb.mass = self.mass
        for k in range(3):
            cb.com[k] = float(self.com[k])
        for k, (i, j) in enumerate(_TENSOR):
            cb.inertia[k] = float(self.inertia[i, j])

    @classmethod
    def _get(cls, cb: Any) -> Body:
        I = np.zeros((3, 3))
        for k, (i, j) in enumerate(_TENSOR):
            I[i, j] = I[j, i] = cb.inertia[k]
        return cls(float(cb.mass), [float(x) for x in cb.com], I)


def _number(value: Any, name: str) -> float:
    # TypeError for complex numbers, strings and other objects
    return real_number(value, name)


def _vector(value: Any, name: str) -> list[float]:
    v = real_array(value, name).reshape(-1)
    if v.size != 3:
        raise ValueError(f"{name}: expected 3 numbers, got {value!r}")
    return [float(x) for x in v]


def _tensor(value: Any, name: str) -> FloatArray:
    """A symmetric 3 x 3 inertia from a (3, 3) array, its six elements or
    three principal moments."""
    a = real_array(value, name)
    if a.shape == (3,):
        return np.diag(a)
    if a.shape == (6,):
        I = np.zeros((3, 3))
        for k, (i, j) in enumerate(_TENSOR):
            I[i, j] = I[j, i] = a[k]
        return I
    if a.shape == (3, 3):
        if not np.all(np.abs(a - a.T) <= 1e-12 * np.abs(a).max()):
            raise ValueError(f"{name}: the (3, 3) inertia is not symmetric")
        return 0.5 * (a + a.T)
    raise ValueError(f"{name}: expected a (3, 3) tensor, its 6 elements "
                     f"(Ixx, Ixy, Ixz, Iyy, Iyz, Izz) or 3 principal moments, "
                     f"got shape {a.shape}")


def _as_body(value: Any, name: str) -> Body:
    if isinstance(value, Body):
        return value
    if isinstance(value, dict):
        unknown = set(value) - {"mass", "com", "inertia"}
        if unknown:
            raise ValueError(f"{name}: unknown keys {sorted(unknown)}")
        try:
            return Body(**value)
        except (TypeError, ValueError) as e:
            raise type(e)(f"{name}.{e}") from None
    raise TypeError(f"{name}: expected an rps3.Body or a dict of mass, com, "
                    f"inertia, got {value!r}")
