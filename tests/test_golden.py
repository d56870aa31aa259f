"""Frozen answers: the paper's case at fixed significant digits, compared
as numbers (RTOL below), not as text.

A change to the library or the runner that moves any of these numbers by
more than RTOL fails here, even if every identity still
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


def parse(text):
    """The rows of a dump as a float array (comment lines skipped)."""
    rows = [line.split() for line in text.splitlines()
            if line.strip() and not line.startswith("#")]
    return np.array(rows, float)


# 10 significant digits round to half a unit of the 10th: <= 5e-10 of the
# value; RTOL leaves room for libm differences between machines and fails
# on any change a reader of the figures could see
RTOL = 1e-9


def test_paper_matches_golden(paper_h5):
    got = dump(paper_h5)
    if os.environ.get("RPS3_UPDATE_GOLDEN"):
        with open(GOLDEN, "w") as fh:
            fh.write(got)
    with open(GOLDEN) as fh:
        want = parse(fh.read())
    g = parse(got)
    assert g.shape == want.shape, f"golden has {want.shape}, run gives {g.shape}"
    # case and time exactly; every other column to RTOL of the value (for
    # values near 0, of 1e-3 of the column's largest magnitude)
    assert (g[:, :2] == want[:, :2]).all()
    scale = np.maximum(np.abs(want[:, 2:]),
                       np.max(np.abs(want[:, 2:]), axis=0) * 1e-3)
    rel = np.abs(g[:, 2:] - want[:, 2:]) / scale
    if not (rel <= RTOL).all():
        r, c = np.unravel_index(np.argmax(rel), rel.shape)
        raise AssertionError(
            f"golden mismatch (rel {rel[r, c]:.3g} > {RTOL:g}) at case "
            f"{g[r, 0]:g}, t = {g[r, 1]:g} s, column {c + 2}:\n"
            f" got  {g[r, 2:]}\n want {want[r, 2:]}")
