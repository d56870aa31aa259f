"""Scaling of one compute-bound sweep on this machine: threads, a Slurm-style
array of shards + merge, and MPI, against one process.

    .venv/bin/python tests/bench/scaling.py [--cases N] [--samples S]
                                            [--repeats R] [-o TABLE.md]
    make scaling

The sweep: a sine scene whose theta comes from the multiroot solve started
cold at every sample (hybridsj, tol 1e-13) and whose forces come from the
Newton-Euler route, so that computing, not writing, dominates; N cases of
S samples (default 300 x 10,000 = 3 M points; a case is one job, so the
shards get equal work).  Per repetition, in this order:

  j1     rps3-run -j 1                         one process, one thread
  j2     rps3-run -j 2                         one process, two threads
  array  rps3-run --shard 0/2 and 1/2 at once, then `rps3-run merge`
         (the join by virtual datasets): wall from the start of the shards
         to the end of the merge, what a Slurm array + afterok merge costs
         without the queue
  mpi    mpirun -n 2 rps3-run-mpi              two ranks, rank 0 joins

Wall time by time.perf_counter around the commands; CPU time (user +
system) of every process they ran, from getrusage(RUSAGE_CHILDREN).
Speed-up = wall(j1) / wall(X) within the same repetition, efficiency =
speed-up / 2 cores.  Medians over the repetitions with min-max.  The
outputs of the first repetition are compared with j1's (every dataset of
the per-case data, bit for bit) before they are deleted.  The load average
is recorded before each repetition: on a shared machine, read the table
with it.
"""

import argparse
import os
import platform
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(
    os.path.abspath(__file__))))
RUN = os.path.join(ROOT, "build", "rps3-run")
RUN_MPI = os.path.join(ROOT, "build", "rps3-run-mpi")

SCENE = """\
# tests/bench/scaling.py: a compute-bound sweep (cold multiroot theta
# solve at every sample, Newton-Euler forces)
manipulator: {{R: 0.2286, rho: 0.5, M: 0.18, m: 0.09, d: 0.1524,
              link_Ic: 0.0002}}
trajectory:
  kind: sine
  mean: [0.0, 0.08, 0.30]
  amp: [1.0, 0.05, 0.03]
  freq: [0.5, 1.0, 2.0]
  phase: [0.0, 0.0, 1.5708]
  duration: 2.0
  samples: {samples}
solver: {{theta: multiroot, solver: hybridsj, tolerance: 1e-13,
         warm_start: false, method: newton_euler}}
sweep:
  trajectory.amp[0]: [{amps}]
  trajectory.mean[1]: [{means}]
"""

CONFIGS = ("j1", "j2", "array", "mpi")
LABEL = {
    "j1": "one process, `-j 1`",
    "j2": "one process, `-j 2`",
    "array": "array of 2 shards at once + `merge` (VDS)",
    "mpi": "`mpirun -n 2 rps3-run-mpi`",
}


def scene_text(cases, samples):
    """cases = na x nm with nm = 10 (or fewer): amp[0] x mean[1]."""
    nm = 10 if cases % 10 == 0 else 1
    na = cases // nm
    amps = ", ".join(f"{0.5 + 0.9 * k / max(na - 1, 1):.6g}" for k in range(na))
    means = ", ".join(f"{0.06 + 0.04 * k / max(nm - 1, 1):.6g}"
                      for k in range(nm))
    return SCENE.format(samples=samples, amps=amps, means=means)


def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def check(p, what):
    if p.returncode != 0:
        sys.exit(f"{what} failed ({p.returncode}):\n{p.stderr}")


def run_config(name, scene, d):
    """Wall and CPU seconds of one configuration; the output path and, for
    the array, the merge's own wall time."""
    out = os.path.join(d, f"{name}.h5")
    c0, t0 = children_cpu(), time.perf_counter()
    merge = None
    if name in ("j1", "j2"):
        p = subprocess.run([RUN, scene, "-o", out, "-q", "-j", name[1]],
                           capture_output=True, text=True)
        check(p, name)
    elif name == "array":
        parts = [os.path.join(d, f"part{k}.h5") for k in range(2)]
        procs = [subprocess.Popen([RUN, scene, "-o", parts[k], "-q",
                                   "--shard", f"{k}/2"],
                                  stderr=subprocess.PIPE, text=True)
                 for k in range(2)]
        for k, pr in enumerate(procs):
            err = pr.communicate()[1]
            if pr.returncode != 0:
                sys.exit(f"shard {k} failed ({pr.returncode}):\n{err}")
        m0 = time.perf_counter()
        p = subprocess.run([RUN, "merge", out, *parts, "-q"],
                           capture_output=True, text=True)
        check(p, "merge")
        merge = time.perf_counter() - m0
    else:
        p = subprocess.run(["mpirun", "--allow-run-as-root", "-n", "2", RUN_MPI,
                            scene, "-o", out, "-q"],
                           capture_output=True, text=True)
        check(p, "mpirun")
    return time.perf_counter() - t0, children_cpu() - c0, out, merge


def same_data(a, b):
    """Every per-case dataset of b equals a's, bit for bit."""
    with h5py.File(a, "r") as fa, h5py.File(b, "r") as fb:
        names = [n for n, v in fa.items() if isinstance(v, h5py.Dataset)]
        for n in names:
            x, y = np.asarray(fa[n][()]), np.asarray(fb[n][()])
            if x.shape != y.shape:
                return n
            if x.dtype.kind == "f":
                if not np.array_equal(x.view(np.uint8), y.view(np.uint8)):
                    return n
            elif not np.array_equal(x, y):
                return n
    return None


def med(xs):
    return f"{statistics.median(xs):.3g} ({min(xs):.3g}-{max(xs):.3g})"


def machine():
    cpu = "unknown CPU"
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    osname = platform.platform()
    if os.path.exists("/etc/os-release"):
        with open("/etc/os-release") as f:
            m = re.search(r'PRETTY_NAME="([^"]*)"', f.read())
            osname = m.group(1) if m else osname
    mpi = subprocess.run(["mpirun", "--version"], capture_output=True,
                         text=True).stdout.splitlines()
    return (f"{os.cpu_count()} CPUs ({cpu}), {osname}, "
            f"{mpi[0] if mpi else 'no mpirun'}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", type=int, default=300)
    ap.add_argument("--samples", type=int, default=10000)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--dir", help="scratch directory (default: a temporary "
                    "one under /tmp)")
    ap.add_argument("-o", "--output", help="write the markdown table here")
    ap.add_argument("--wait-load", type=float, default=0.0, metavar="L",
                    help="before each repetition wait until the 1-minute "
                    "load average is below L (a shared machine)")
    ap.add_argument("--wait-max", type=float, default=600.0, metavar="S",
                    help="wait at most S seconds per repetition (600)")
    a = ap.parse_args()
    for exe in (RUN, RUN_MPI):
        if not os.access(exe, os.X_OK):
            sys.exit(f"{exe} is missing: make runner runner-mpi")
    d = tempfile.mkdtemp(prefix="rps3-scaling-", dir=a.dir)
    scene = os.path.join(d, "scaling.yaml")
    with open(scene, "w") as f:
        f.write(scene_text(a.cases, a.samples))
    points = a.cases * a.samples
    wall = {c: [] for c in CONFIGS}
    cpu = {c: [] for c in CONFIGS}
    speed = {c: [] for c in CONFIGS}
    merges, loads = [], []
    try:
        for rep in range(a.repeats):
            t_wait = time.monotonic()
            while (a.wait_load > 0 and os.getloadavg()[0] >= a.wait_load
                   and time.monotonic() - t_wait < a.wait_max):
                time.sleep(10)
            loads.append(os.getloadavg()[0])
            outs = {}
            for c in CONFIGS:
                w, u, out, merge = run_config(c, scene, d)
                wall[c].append(w)
                cpu[c].append(u)
                outs[c] = out
                if merge is not None:
                    merges.append(merge)
                print(f"rep {rep + 1}: {c}: wall {w:.2f} s, CPU {u:.2f} s",
                      file=sys.stderr, flush=True)
            for c in CONFIGS:
                speed[c].append(wall["j1"][-1] / wall[c][-1])
            if rep == 0:
                for c in CONFIGS[1:]:
                    bad = same_data(outs["j1"], outs[c])
                    if bad:
                        sys.exit(f"{c}: dataset {bad} differs from -j 1's")
            for name in os.listdir(d):
                if name.endswith(".h5") or ".h5." in name:
                    os.remove(os.path.join(d, name))
        loads.append(os.getloadavg()[0])
    finally:
        shutil.rmtree(d, ignore_errors=True)
    rows = [f"{points / 1e6:.3g} M points ({a.cases} cases x {a.samples} "
            f"samples), {a.repeats} repetitions; {machine()}; load average "
            f"(1 min) before each repetition and at the end: "
            + ", ".join(f"{x:.2f}" for x in loads) + ".",
            "",
            "| configuration | wall s | CPU s | speed-up | efficiency |",
            "|---|---:|---:|---:|---:|"]
    for c in CONFIGS:
        eff = [s / 2 for s in speed[c]]
        rows.append(f"| {LABEL[c]} | {med(wall[c])} | {med(cpu[c])} | "
                    f"{med(speed[c]) if c != 'j1' else '1'} | "
                    f"{med([100 * e for e in eff]) + ' %' if c != 'j1' else '-'} |")
    rows.append("")
    rows.append(f"The array's `merge` took {med(merges)} s of its wall time; "
                f"one process computes {points / statistics.median(wall['j1']) / 1e6:.3g} "
                "M points/s.")
    table = "\n".join(rows) + "\n"
    print(table)
    if a.output:
        with open(a.output, "w") as f:
            f.write(table)


if __name__ == "__main__":
    main()
