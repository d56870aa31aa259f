"""The Python package's inverse dynamics against the C batch call under it.

For 10^6 points of the paper's helix (Table II, the default effects,
closed-form theta, Lagrange, certificate on), in one process:
  - anchor: rps3_inverse_batch called directly through the package's cffi
    module on arrays prepared (and touched) beforehand: the C loop alone;
  - package: rps3.Model.inverse(pose, dpose, ddpose) on the trajectory's
    (n, 3) arrays, views of a component-major block that it passes to the
    library as they are, with its argument checks, workspace and fresh
    result arrays;
  - package on C-ordered (n, 3) copies of the same arrays, which it
    transposes into the library's layout first (a numpy user's arrays).
The repeats alternate the three, so that a change in the machine's load
reaches all of them alike.  Medians over the repeats with min-max, wall
and CPU time; the ratios of the medians are the package's overhead (the
goal: within 1.5x).  Timings are never asserted.

    python tests/bench/python_bench.py [-n 1000000] [--repeats 7]
"""

import argparse
import statistics
import time

import numpy as np

import rps3
from rps3._rps3 import ffi, lib

GOAL = 1.5  # package / C batch (docs/performance.md)


def timed(fns, repeats):
    """{name: (wall, cpu)} lists in seconds over the repeats of each fn(),
    the fns taking turns within each repeat."""
    times = {name: ([], []) for name in fns}
    for _ in range(repeats):
        for name, fn in fns.items():
            w0, c0 = time.perf_counter(), time.process_time()
            fn()
            times[name][0].append(time.perf_counter() - w0)
            times[name][1].append(time.process_time() - c0)
    return times


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
    return (f"{name:<34} {med:8.3f} s  [{min(wall):.3f}-{max(wall):.3f}]  "
            f"cpu {statistics.median(cpu):7.3f} s "
            f"[{min(cpu):.3f}-{max(cpu):.3f}]  {1e9 * med / n:6.1f} ns/point")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=1_000_000)
    ap.add_argument("--repeats", type=int, default=7)
    args = ap.parse_args()

    model = rps3.Model()
    traj = rps3.trajectory.helix(samples=args.n)
    rows = [np.ascontiguousarray(a) for a in (traj.pose, traj.dpose, traj.ddpose)]
    call, F = c_batch(model, traj.pose, traj.dpose, traj.ddpose)
    call()  # warm: pages touched, caches filled
    # the same numbers by every route, or the timing compares nothing
    for args_ in ((traj.pose, traj.dpose, traj.ddpose), rows):
        assert np.array_equal(model.inverse(*args_).force, F.T)

    fns = {"C rps3_inverse_batch": call,
           "rps3.Model.inverse": lambda: model.inverse(
               traj.pose, traj.dpose, traj.ddpose),
           "rps3.Model.inverse, C-ordered": lambda: model.inverse(*rows)}
    times = timed(fns, args.repeats)
    print(f"inverse dynamics, {args.n} points, {args.repeats} repeats "
          "(median [min-max] wall, CPU)")
    for name, (wall, cpu) in times.items():
        print(row(name, wall, cpu, args.n))
    anchor = [statistics.median(x) for x in times["C rps3_inverse_batch"]]
    for name in list(fns)[1:]:
        wall, cpu = (statistics.median(x) for x in times[name])
        ratio = cpu / anchor[1]
        print(f"ratio {name} / C batch: CPU {ratio:.3f}, wall "
              f"{wall / anchor[0]:.3f} (goal <= {GOAL}: "
              f"{'met' if ratio <= GOAL else 'NOT met'} in CPU time)")


if __name__ == "__main__":
    main()
