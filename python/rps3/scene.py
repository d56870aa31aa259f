"""Running a scene file (rps3-run's YAML, docs/runner.md) from Python: the
runner program writes its HDF5 file into a temporary directory, which is
read back as an xarray Dataset (rps3.open_dataset), loaded into memory,
and removed.

    ds = rps3.scene.run("configs/paper.yaml")
    ds.force.sel(m_over_M=0.5)                # (time, link) [N]

The runner is found by :func:`find_runner`, in this order: the ``runner``
argument; the environment variable ``RPS3_RUN``; the rps3-run of the build
the package was compiled against (``PREFIX/bin/rps3-run`` for a package
built with RPS3_PREFIX, else the repository's ``build/rps3-run``), when it
exists; ``rps3-run`` on the PATH.  A runner whose ``--version`` is not the
package's raises ``RuntimeError``.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
from collections.abc import Sequence
from typing import TYPE_CHECKING

from rps3._core import text
from rps3._rps3 import lib
from rps3.io import open_dataset

if TYPE_CHECKING:  # xarray is imported by open_dataset alone: the figures'
    import xarray as xr  # environment (make paper) does without it

_VERSION = text(lib.rps3_version())


class RunnerError(RuntimeError):
    """rps3-run failed.  Attributes: ``returncode`` (1: some cases failed,
    2: bad scene or usage, 3: cannot write), ``stderr`` (the runner's
    messages, ``FILE:LINE:COL: key: message`` for a scene error) and
    ``dataset`` (exit 1: the complete file, the failed cases' status
    set; else None)."""

    def __init__(self, message: str, returncode: int, stderr: str,
                 dataset: xr.Dataset | None = None) -> None:
        super().__init__(message)
        self.returncode = returncode
        self.stderr = stderr
        self.dataset = dataset


class SceneError(RunnerError, ValueError):
    """rps3-run rejected the scene (exit 2): the message names file, line,
    column and key."""


def _candidates(runner: str | os.PathLike[str] | None) -> list[tuple[str, str]]:
    if runner is not None:
        return [("runner argument", os.fspath(runner))]
    out = []
    env = os.environ.get("RPS3_RUN")
    if env:
        return [("RPS3_RUN", env)]
    hint = text(lib.rps3py_runner_hint())
    if os.access(hint, os.X_OK):
        out.append(("the build's runner", hint))
    found = shutil.which("rps3-run")
    if found:
        out.append(("PATH", found))
    return out


def find_runner(runner: str | os.PathLike[str] | None = None) -> str:
    """The path of the rps3-run program to use (order: module docstring).

    Raises:
        FileNotFoundError: none found, or the one named is not executable.
        RuntimeError: its version is not the package's.
    """
    cands = _candidates(runner)
    if not cands:
        raise FileNotFoundError(
            "rps3-run not found: pass runner=, set RPS3_RUN, build it "
            f"(`make runner`, expected at {text(lib.rps3py_runner_hint())}) "
            "or put it on the PATH")
    where, path = cands[0]
    if not (os.path.isfile(path) and os.access(path, os.X_OK)):
        raise FileNotFoundError(f"rps3-run ({where}): {path} is not an "
                                f"executable file")
    proc = subprocess.run([path, "--version"], capture_output=True, text=True,
                          timeout=30)
    # GNU --version: the first line ends in the version
    first = (proc.stdout.strip().splitlines() or [""])[0]
    version = first.rsplit(" ", 1)[-1]
    if proc.returncode != 0 or version != _VERSION:
        raise RuntimeError(f"rps3-run ({where}): {path} is version "
                           f"{first or '?'}, the package "
                           f"{_VERSION}")
    return path


def run(scene: str | os.PathLike[str], *, runner: str | os.PathLike[str] | None = None,
        jobs: int = 1, fields: Sequence[str] | None = None,
        failed_ok: bool = False, timeout: float | None = None) -> xr.Dataset:
    """Run a scene file with rps3-run and return its output as a Dataset.

    Args:
        scene: the scene's YAML file (its relative paths, e.g. a table's
            CSV, are relative to it, as for the runner).
        runner: the rps3-run program; None: :func:`find_runner`.
        jobs: threads of the runner (``-j``); the output is the same.
        fields: write only these per-sample fields (``--fields``).
        failed_ok: return the dataset when some cases failed (their
            ``status`` says which) instead of raising RunnerError.
        timeout: seconds before the runner is stopped (TimeoutExpired).

    Returns:
        The runner's file as rps3.open_dataset gives it (swept keys as
        dimensions; docs/hdf5.md), loaded into memory.

    Raises:
        FileNotFoundError: the scene or the runner is missing.
        SceneError: the runner rejected the scene (its message).
        RunnerError: the runner failed otherwise (exit 1 and 3).
    """
    path = os.fspath(scene)
    if not os.path.isfile(path):
        raise FileNotFoundError(f"scene: {path}: no such file")
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise ValueError(f"jobs: expected an integer >= 1, got {jobs!r}")
    exe = find_runner(runner)
    with tempfile.TemporaryDirectory(prefix="rps3-scene-") as tmp:
        out = os.path.join(tmp, "out.h5")
        cmd = [exe, path, "-o", out, "-q", "-j", str(jobs)]
        if fields is not None:
            if isinstance(fields, str):
                raise TypeError("fields: expected a list of field names")
            cmd += ["--fields", ",".join(fields)]
        proc = subprocess.run(cmd, capture_output=True, text=True,
                              timeout=timeout)
        err = proc.stderr.strip()
        if proc.returncode == 2:
            raise SceneError(err or f"rps3-run rejected {path}", 2, proc.stderr)
        if proc.returncode not in (0, 1) or not os.path.exists(out):
            raise RunnerError(f"rps3-run exited {proc.returncode}: {err}",
                              proc.returncode, proc.stderr)
        with open_dataset(out) as ds:
            data = ds.load()
        if proc.returncode == 1 and not failed_ok:
            raise RunnerError(f"rps3-run: some cases of {path} failed: {err}",
                              1, proc.stderr, data)
    return data
