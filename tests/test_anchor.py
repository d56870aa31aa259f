"""The benchmark's generated anchor against the library.

build/anchor-check (tests/bench/anchor_check.c, built by `make check-py`)
compares the forces of the C that tests/bench/gen_anchor.py generates with
SymPy -- the paper's model written in the pose coordinates by virtual
power and solved through (dl/dq)^T F = Q, no multipliers -- with
rps3_inverse's (the multipliers of (23), (34)) on the paper's helix and
20000 random states.
Both derivations are exact: they must agree to rounding, 1e-13 of the sum
of the effects' magnitudes (measured 1.7e-14).
"""

import os
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CHECK = os.path.join(ROOT, "build", "anchor-check")


def test_generated_anchor_matches_library():
    assert os.path.exists(CHECK), "build it first: make build/anchor-check"
    res = subprocess.run([CHECK, "1e-13"], capture_output=True, text=True,
                         timeout=120)
    assert res.returncode == 0, res.stdout + res.stderr
    assert "PASS" in res.stdout
    assert "21001 states" in res.stdout
