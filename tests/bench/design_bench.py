"""What a design study costs in rps3-run (`make bench-design`): a study of
N designs (rho x stroke) over a grid of 10 x 10 x 10 poses, no task, run
with -j 1 and -j 2; wall and CPU time (user + system of the runner, from
getrusage), designs per CPU second, and the extrapolation to the target
study of 10^5 designs x 10^3 poses on 2 cores (docs/runner.md, "Design
studies").  The CPU time is the measure to read on a shared machine: the
wall time there measures the neighbours too (the load average is printed).

    python tests/bench/design_bench.py [--designs N] [--runner PATH]
"""

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(
    __file__))))

SCENE = """\
manipulator:
  R: 0.2286
  rho: 0.5
  M: 0.18
  m_over_M: 0.5
  d: 0.1524
  stroke: {{min: 0.2286, max: 0.4572}}
design:
  alpha: [-3.141592653589793, 3.141592653589793, 10]
  beta: [0.0, 0.6, 10]
  z_c: [0.1, 0.5, 10]
sweep:
  manipulator.rho: {{from: 0.3, to: 0.9, num: {nrho}}}
  manipulator.stroke.max: {{from: 0.3, to: 0.6, num: {nstroke}}}
"""

TARGET_DESIGNS = 100000


def timed(cmd):
    """(wall s, CPU s of the child) of running cmd."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        sys.exit(f"{' '.join(cmd)}: exit {proc.returncode}\n{proc.stderr}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime -
                                                 before.ru_stime)
    return wall, cpu


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", type=int, default=2000,
                    help="designs of the measured study (default 2000)")
    ap.add_argument("--runner", default=os.path.join(ROOT, "build",
                                                     "rps3-run"))
    args = ap.parse_args()
    nstroke = 20
    nrho = max(1, args.designs // nstroke)
    n = nrho * nstroke
    with tempfile.TemporaryDirectory() as tmp:
        scene = os.path.join(tmp, "bench.yaml")
        with open(scene, "w") as f:
            f.write(SCENE.format(nrho=nrho, nstroke=nstroke))
        print(f"design study: {n} designs x 1000 poses, no task; load "
              f"average {os.getloadavg()[0]:.2f} before")
        rows = []
        for j in (1, 2):
            out = os.path.join(tmp, f"j{j}.h5")
            wall, cpu = timed([args.runner, scene, "-o", out, "-q", "-j",
                               str(j)])
            rows.append((j, wall, cpu))
            print(f"  -j {j}: wall {wall:.2f} s, CPU {cpu:.2f} s, "
                  f"{n / cpu:.0f} designs per CPU second, "
                  f"{1e6 * cpu / (n * 1000):.2f} us a pose")
        cpu_per_design = min(r[2] for r in rows) / n
        target = cpu_per_design * TARGET_DESIGNS
        print(f"10^5 designs x 10^3 poses: {target:.0f} s of CPU, "
              f"{target / 2 / 60:.1f} min on 2 idle cores (target: 10 min); "
              f"load average {os.getloadavg()[0]:.2f} after")


if __name__ == "__main__":
    main()
