"""Frozen answers: the paper's case at fixed significant digits.

A change to the library or the runner that moves any of these numbers by
more than the last printed digit fails here, even if every identity still
holds (an identity cannot see a wrong but self-consistent model).  After a
deliberate, reviewed change, regenerate with

    RPS3_UPDATE_GOLDEN=1 .venv/bin/python -m pytest tests/test_golden.py

and commit tests/golden/paper.txt with the change that explains it.
"""

import os

import h5py
import numpy as np

GOLDEN = os.path.join(os.path.dirname(__file__), "golden", "paper.txt")
DIGITS = 10  # doubles carry ~16; 10 leaves room for libm differences
STRIDE = 50  # every 50th sample of the 1001


def dump(path):
    lines = ["# case t_s  l_i [m] x3  theta_i [rad] x3  F_i [N] x3  lambda [N/m] x3"]
    with h5py.File(path, "r") as f:
        t = f["time"][...] if f["time"].ndim == 1 else None
        for c in range(f["force"].shape[0]):
            tt = t if t is not None else f["case_time"][c]
            for k in range(0, f["force"].shape[1], STRIDE):
                row = [f"{c:d}", f"{tt[k]:.6g}"]
                for name in ("length", "theta", "force", "lambda"):
                    row += [f"{v:.{DIGITS}g}" for v in f[name][c, k]]
                lines.append(" ".join(row))
    return "\n".join(lines) + "\n"


def test_paper_matches_golden(paper_h5):
    got = dump(paper_h5)
    if os.environ.get("RPS3_UPDATE_GOLDEN"):
        with open(GOLDEN, "w") as fh:
            fh.write(got)
    with open(GOLDEN) as fh:
        want = fh.read()
    if got != want:
        # report the first difference with its relative size
        for gl, wl in zip(got.splitlines(), want.splitlines()):
            if gl != wl:
                g = np.array(gl.split()[2:], float)
                w = np.array(wl.split()[2:], float)
                rel = np.max(np.abs(g - w) / np.maximum(np.abs(w), 1e-300))
                raise AssertionError(
                    f"golden mismatch (max rel {rel:.3g}):\n got  {gl}\n want {wl}")
        raise AssertionError("golden file has a different number of lines")
