"""The benchmark's generated anchor against the library.

build/anchor-check (tests/bench/anchor_check.c, built by `make check-py`)
compares the forces of the C that tests/bench/gen_anchor.py generates with
SymPy -- the paper's model written in the pose coordinates by virtual
power and solved through (dl/dq)^T F = Q, no multipliers -- with
rps3_inverse's (the multipliers of (23), (34)) on the paper's helix and
20000 random states, and the batched anchor with the scalar one.
Both derivations are exact: they must agree to rounding, 1e-13 of the sum
of the effects' magnitudes (measured 1.7e-14).  The generator's own checks
before it writes must fail on a wrong program.
"""

import importlib.util
import os
import subprocess

import pytest
import sympy as sp

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CHECK = os.path.join(ROOT, "build", "anchor-check")


def test_generated_anchor_matches_library():
    assert os.path.exists(CHECK), "build it first: make build/anchor-check"
    res = subprocess.run([CHECK, "1e-13"], capture_output=True, text=True,
                         timeout=120)
    assert res.returncode == 0, res.stdout + res.stderr
    assert "PASS" in res.stdout
    assert "21001 states" in res.stdout


def test_batched_anchor_matches_scalar():
    """The batched anchor (the generated assignments in a vectorised loop
    over structures of arrays, compiled with the batch kernel's flags; the
    benchmark's anchor_generated_batch) gives the scalar anchor's forces
    and statuses on the same 21001 states in one call."""
    assert os.path.exists(CHECK), "build it first: make build/anchor-check"
    res = subprocess.run([CHECK, "1e-13"], capture_output=True, text=True,
                         timeout=120)
    line = [x for x in res.stdout.splitlines() if "batched anchor" in x]
    assert len(line) == 1, res.stdout + res.stderr
    assert "21001 states in one call" in line[0]
    assert line[0].endswith("PASS"), line[0]


def _generator():
    """tests/bench/gen_anchor.py as a module"""
    path = os.path.join(ROOT, "tests", "bench", "gen_anchor.py")
    spec = importlib.util.spec_from_file_location("gen_anchor", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_generator_self_checks_fail_on_a_wrong_program():
    """The generator's checks before it writes (the ball joints in their
    pins' planes and (5)-(7), symbolically; the power balance F . l' =
    d(T + P)/dt numerically) pass on its program and fail when one
    assignment of it is wrong."""
    gen = _generator()
    D = gen.derive()
    gen.symbolic_checks(D)
    gen.power_check(D)
    P = D["P"]

    # a link's torque about its pin 1 % off: the power no longer balances
    T1 = sp.Symbol("T1", real=True)
    good = P.defs[T1]
    P.defs[T1] = sp.Rational(101, 100) * good
    with pytest.raises(SystemExit, match="power balance"):
        gen.power_check(D)
    P.defs[T1] = good

    # ball joint 1 a little higher: l_1^2 is no longer (5)
    Z1 = D["Zs"][0]
    good = P.defs[Z1]
    P.defs[Z1] = good + D["par"][0] * sp.Rational(1, 1000)
    with pytest.raises(SystemExit, match=r"\(5\)"):
        gen.symbolic_checks(D)
    P.defs[Z1] = good
