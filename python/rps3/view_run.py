"""What rps3.view draws from an rps3-run file: the scene's model and one
case's poses and times (``python -m rps3.view FILE.h5``)."""

from __future__ import annotations

import os
from typing import Any

import numpy as np

from rps3._core import FloatArray
from rps3.model import Model


def model_from_scene(scene: dict[str, Any]) -> Model:
    """The Model of an rps3-run scene (a dict, e.g. a file's
    ``scene_resolved`` read with yaml): its ``manipulator`` block and
    ``effects``."""
    man = dict(scene.get("manipulator") or {})
    keys: dict[str, Any] = {k: man[k] for k in ("R", "rho", "M", "m_over_M", "m",
                                                "d", "link_Ic", "g") if k in man}
    if "payload" in man:
        keys["payload"] = man["payload"]
    if "pin_friction" in man:
        keys["friction"] = {k: v for k, v in man["pin_friction"].items()
                            if k in ("viscous", "coulomb")}
    if "effects" in scene:
        keys["effects"] = scene["effects"]
    return Model(**keys)


def read_run(path: str | os.PathLike[str], case: int = 0, *, reference: bool = False
             ) -> tuple[Model, FloatArray, FloatArray]:
    """The model, poses (n, 3) and times (n,) [s] of one case of an rps3-run
    HDF5 file (docs/hdf5.md; a simulation's too: the plant's pose), up to
    its last sample.  The model is the scene's ``manipulator`` (the plant).
    A file without the pose (written with ``--fields``) gives it through
    the forward kinematics of its ``length``; a sample whose pose is NaN
    (a failed point) is kept, drawn as refused.  reference: the poses of a
    simulation's reference (``alpha_ref``, ``beta_ref``, ``z_c_ref``)
    instead of the plant's.

    Raises:
        ValueError: the file lacks a dataset, or the case is out of range.
    """
    import h5py
    import yaml
    name = os.fspath(path)
    names = ("alpha_ref", "beta_ref", "z_c_ref") if reference else ("alpha", "beta", "z_c")
    with h5py.File(path, "r") as f:
        has_pose = all(k in f for k in names)
        if reference and not has_pose:
            raise ValueError(f"{name}: no dataset 'alpha_ref': not a simulation's "
                             f"output, no reference to draw (docs/runner.md)")
        # the times: time, or case_time where the cases' grids differ
        times = "case_time" if "case_time" in f else "time"
        for key in ("scene_resolved", times, names[0] if has_pose else "length"):
            if key not in f:
                raise ValueError(f"{name}: no dataset {key!r}: not an rps3-run output "
                                 f"file with poses or link lengths (docs/hdf5.md)")
        ncase = f["scene_resolved"].shape[0]
        if not 0 <= case < ncase:
            raise ValueError(f"case: {case} is out of range: {name} "
                             f"has {ncase} case(s), 0 to {ncase - 1}")
        if has_pose:
            pose = np.stack([f[k][case] for k in names], axis=1)
            lengths = None
        else:
            lengths = np.asarray(f["length"][case], float)
        t = f[times][case] if times == "case_time" else f[times][()]
        raw = f["scene_resolved"][case]
    scene = yaml.safe_load(raw.decode() if isinstance(raw, bytes) else str(raw))
    model = model_from_scene(scene)
    # samples past a failure (or a case's last time) are NaN
    keep = np.isfinite(t)
    if lengths is not None:
        # a file written with --fields without the pose: forward kinematics
        keep &= np.isfinite(lengths).all(axis=1)
        pose = np.full((len(t), 3), np.nan)
        fk = model.fk(lengths[keep])
        pose[keep] = np.where(fk.ok[:, None], fk.pose, np.nan)
    return model, pose[keep], np.asarray(t[keep], float)
