"""The Python package's inverse dynamics against the C batch call under it.

For 10^6 points of the paper's helix (Table II, the default effects,
closed-form theta, Lagrange, certificate on), in one process:
  - anchor: rps3_inverse_batch called directly through the package's cffi
    module on arrays prepared beforehand (the C loop alone);
  - package: rps3.Model.inverse(pose, dpose, ddpose) on (n, 3) arrays, with
    its argument checks, layout conversion, workspace and result arrays.
Medians over the repeats with min-max, wall and CPU time; the ratio of the
medians is the package's overhead (the goal: within 1.5x).  Timings are
never asserted.

    python tests/bench/python_bench.py [-n 1000000] [--repeats 5]
"""

import argparse
import statistics
import time

import numpy as np

import rps3
from rps3._rps3 import ffi, lib

GOAL = 1.5  # package / C batch, issue 10


def timed(fn, repeats):
    """(wall, cpu) lists in seconds over the repeats of fn()."""
    wall, cpu = [], []
    for _ in range(repeats):
        w0, c0 = time.perf_counter(), time.process_time()
        fn()
        wall.append(time.perf_counter() - w0)
        cpu.append(time.process_time() - c0)
    return wall, cpu


def c_batch(model, pose, dpose, ddpose):
    """A closure calling rps3_inverse_batch on prepared component-major
    arrays: what a C program would spend."""
    n = pose.shape[0]
    p, dp, ddp = (np.ascontiguousarray(a.T) for a in (pose, dpose, ddpose))
    F, lam, Fe = np.empty((3, n)), np.empty((3, n)), np.empty((6, 3, n))
    cond, res = np.empty(n), np.empty(n)
    l, th = np.empty((3, n)), np.empty((3, n))
    status, warn = np.empty(n, np.int32), np.empty(n, np.int32)
    dd = ffi.new("rps3_data **")
    assert lib.rps3_data_alloc(model._c, dd) == 0
    d = ffi.gc(dd[0], lib.rps3_data_free)
    cin, cout = ffi.new("rps3_batch_in *"), ffi.new("rps3_batch_out *")
    bufs = [ffi.from_buffer("double[]", a) for a in (p, dp, ddp)]
    cin.n, cin.pose, cin.dpose, cin.ddpose = n, *bufs
    outs = {"F": F, "lambda": lam, "F_effect": Fe, "cond": cond,
            "energy_residual": res, "l": l, "theta": th}
    keep = []
    for name, a in outs.items():
        keep.append(ffi.from_buffer("double[]", a))
        setattr(cout, name, keep[-1])
    for name, a in (("status", status), ("warn", warn)):
        keep.append(ffi.from_buffer("int[]", a))
        setattr(cout, name, keep[-1])

    alive = (p, dp, ddp, bufs, keep, outs, status, warn)  # what cin/cout point to

    def call():
        assert alive
        assert lib.rps3_inverse_batch(model._c, d, cin, cout) == 0
        assert cout.nfail == 0
    return call, F


def row(name, wall, cpu, n):
    med = statistics.median(wall)
    return (f"{name:<28} {med:8.3f} s  [{min(wall):.3f}-{max(wall):.3f}]  "
            f"cpu {statistics.median(cpu):8.3f} s  {1e9 * med / n:8.1f} ns/point")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=1_000_000)
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()

    model = rps3.Model()
    traj = rps3.trajectory.helix(samples=args.n)
    call, F = c_batch(model, traj.pose, traj.dpose, traj.ddpose)
    call()  # warm: pages touched, caches filled
    out = model.inverse(traj.pose, traj.dpose, traj.ddpose)
    # the same numbers by both routes, or the timing compares nothing
    assert np.array_equal(out.force, F.T)

    c_wall, c_cpu = timed(call, args.repeats)
    p_wall, p_cpu = timed(lambda: model.inverse(traj.pose, traj.dpose,
                                                traj.ddpose), args.repeats)
    ratio = statistics.median(p_wall) / statistics.median(c_wall)
    print(f"inverse dynamics, {args.n} points, {args.repeats} repeats "
          "(median [min-max] wall, median CPU)")
    print(row("C rps3_inverse_batch", c_wall, c_cpu, args.n))
    print(row("rps3.Model.inverse", p_wall, p_cpu, args.n))
    print(f"ratio package / C batch: {ratio:.3f} (goal <= {GOAL}: "
          f"{'met' if ratio <= GOAL else 'NOT met'})")


if __name__ == "__main__":
    main()
