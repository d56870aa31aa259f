"""rps3: kinematics and inverse dynamics of the 3-DOF in-parallel actuated
manipulator of Lee & Shah (1988), computed by librps3 over numpy arrays.

    import rps3
    model = rps3.Model(m_over_M=0.5, effects=["platform_gravity", "link_gravity"])
    traj = rps3.trajectory.helix()                 # the paper's, Table II
    out = model.inverse(traj.pose, traj.dpose, traj.ddpose)
    out.force                                      # (n, 3) [N]
    ds = rps3.open_dataset("out/paper.h5")         # rps3-run's output

SI units throughout; see the repository's README.md and include/rps3.h.
"""

from rps3 import control, design, dynamics, errors, export, h5io, scene, sim, trajectory, velocity
from rps3._core import strerror
from rps3._rps3 import ffi as _ffi
from rps3._rps3 import lib as _lib
from rps3.errors import Rps3Error
from rps3.io import open_dataset
from rps3.model import (
    DEFAULT_EFFECTS,
    EFFECTS,
    OUTPUTS,
    Body,
    Dynamics,
    Kinematics,
    Model,
    Pose,
)

__version__: str = _ffi.string(_lib.rps3_version()).decode()

# the library linked in must be the one whose header the binding was built
# against
if __version__ != _ffi.string(_lib.rps3py_header_version()).decode():
    raise ImportError(f"rps3: library {__version__} does not match its header")

__all__ = ["DEFAULT_EFFECTS", "EFFECTS", "OUTPUTS", "Body", "Dynamics", "Kinematics", "Model",
           "h5io", "Pose", "open_dataset", "strerror", "trajectory",
           "Rps3Error", "control", "dynamics", "errors", "scene", "sim", "velocity",
           "export", "design", "ident", "plot", "view"]


def __getattr__(name: str) -> object:
    # rps3.view and rps3.plot on first use: matplotlib stays optional,
    # and `python -m rps3.view` does not find its module already imported;
    # rps3.ident likewise (scipy and cvxpy, the `ident` extra)
    if name in ("plot", "view", "ident"):
        import importlib
        return importlib.import_module("rps3." + name)
    raise AttributeError(f"module 'rps3' has no attribute {name!r}")
