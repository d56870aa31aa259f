"""What joining the parts of a sharded run costs: `rps3-run merge` (virtual
datasets) and `rps3-run merge --copy` at 10, 100 and 1,000 shards.

A real run of 1,000 jobs holds 1,000 tiles of 16,384 samples (5 GB), so
the parts are made small instead: one single-process run of 1,000 short
cases (the paper's helix, 9 samples, a sweep of the pitch) is cut into N
part files with chunks of one case, part k holding the cases c with
c % N == k (chunk rows of one case: a job per case), with the layout,
attributes, dimension scales and fill values of the run's own files.  The
join sees what it sees at 1,000 real shards: N files, 2 N mappings per
dataset.  Each merge is checked against the run, value for value (NaN
and strings included), then timed (median of the repeats, min-max, CPU
time of the merge process beside wall time) with the joined file's size,
and the time to read every per-case dataset back through it.  A table on
stdout; timings are never asserted.

    python tests/bench/join_bench.py [--shards 10,100,1000] [--repeats 3]
        [--runner build/rps3-run] [--keep DIR]
"""

import argparse
import os
import platform
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(
    __file__))))
NCASE = 1000
SCALE_ATTRS = {"CLASS", "NAME", "DIMENSION_LIST", "REFERENCE_LIST"}

SCENE = """\
# join_bench.py: the paper's helix, {ncase} cases of 9 samples (pitch swept)
manipulator: {{R: 0.2286, rho: 0.5, M: 0.18, m_over_M: 0.5, d: 0.1524}}
trajectory: {{kind: helix, radius: 0.000266, pitch: 0.03048, z0: 0.3048,
             period: 10.0, blend: 1.0, samples: 9}}
sweep:
  trajectory.pitch: [{pitches}]
"""


def make_part(ref, path, k, n):
    """Part k of n of the run file `ref`, chunks of one case."""
    with h5py.File(ref, "r") as f, h5py.File(path, "w") as g:
        for a, v in f.attrs.items():
            g.attrs[a] = v
        g.attrs["shard"] = f"{k}/{n}"
        for name, ds in f.items():
            if ds.chunks:
                d = g.create_dataset(name, shape=ds.shape, dtype=ds.dtype,
                                     chunks=(1,) + ds.shape[1:],
                                     fillvalue=ds.fillvalue)
                for c in range(k, ds.shape[0], n):
                    d[c] = ds[c]
            else:
                d = g.create_dataset(name, data=ds[()], dtype=ds.dtype)
            for a, v in ds.attrs.items():
                if a not in SCALE_ATTRS:
                    d.attrs[a] = v
        for name, ds in f.items():
            if ds.attrs.get("CLASS") == b"DIMENSION_SCALE":
                g[name].make_scale(ds.attrs["NAME"].decode().rstrip("\0"))
        for name, ds in f.items():
            for i, dim in enumerate(ds.dims):
                for sc in dim.values():
                    g[name].dims[i].attach_scale(g[sc.name])


def same_values(a, b):
    """Every dataset of a equals b's, bit for bit for numbers."""
    with h5py.File(a, "r") as f, h5py.File(b, "r") as g:
        assert f.keys() == g.keys()
        for name in f:
            u, v = f[name][()], g[name][()]
            if isinstance(u, np.ndarray) and u.dtype.kind in "fiu":
                assert u.tobytes() == v.tobytes(), name
            else:
                assert np.array_equal(u, v), name


def timed(cmd):
    """(wall s, CPU s of the child) of one run of cmd, which must exit 0."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        sys.exit(f"{cmd[:3]}...: exit {proc.returncode}: {proc.stderr}")
    return wall, (after.ru_utime - before.ru_utime
                  + after.ru_stime - before.ru_stime)


def read_all(path):
    """Seconds to read every per-case dataset of a joined file."""
    t0 = time.monotonic()
    with h5py.File(path, "r") as f:
        for ds in f.values():
            if ds.ndim and ds.shape[0] == NCASE:
                ds[()]
    return time.monotonic() - t0


def fmt(xs):
    return (f"{statistics.median(xs):.3g} ({min(xs):.3g}-{max(xs):.3g})")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--shards", default="10,100,1000")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--runner", default=os.path.join(ROOT, "build",
                                                     "rps3-run"))
    ap.add_argument("--keep", help="make the files here and keep them")
    args = ap.parse_args()
    work = args.keep or tempfile.mkdtemp(prefix="join_bench.")
    os.makedirs(work, exist_ok=True)
    try:
        scene = os.path.join(work, "scene.yaml")
        with open(scene, "w") as fh:
            fh.write(SCENE.format(ncase=NCASE, pitches=", ".join(
                f"{0.001 + 1e-4 * i:.4f}" for i in range(NCASE))))
        ref = os.path.join(work, "ref.h5")
        subprocess.run([args.runner, scene, "-o", ref, "-q"], check=True)
        print(f"# {platform.node()}: {os.cpu_count()} cores, "
              f"{platform.platform()}; {NCASE} cases, parts made by "
              f"join_bench.py; median (min-max) of {args.repeats}")
        print("| shards | parts, total | join (VDS) wall s | CPU s | file |"
              " read back s | --copy wall s | CPU s | file | read back s |")
        print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        for n in map(int, args.shards.split(",")):
            pdir = os.path.join(work, f"parts{n}")
            os.makedirs(pdir, exist_ok=True)
            parts = [os.path.join(pdir, f"p{k}.h5") for k in range(n)]
            for k, p in enumerate(parts):
                make_part(ref, p, k, n)
            psize = sum(os.path.getsize(p) for p in parts)
            row = [str(n), f"{psize / 1e6:.3g} MB"]
            for extra in ([], ["--copy"]):
                out = os.path.join(work, f"joined{n}{''.join(extra)}.h5")
                ts = [timed([args.runner, "merge", out, *parts, "-q",
                             *extra]) for _ in range(args.repeats)]
                same_values(ref, out)
                row += [fmt([t[0] for t in ts]), fmt([t[1] for t in ts]),
                        f"{os.path.getsize(out) / 1e3:.3g} kB"]
                row.append(fmt([read_all(out) for _ in range(args.repeats)]))
            print("| " + " | ".join(row) + " |", flush=True)
            if not args.keep:
                shutil.rmtree(pdir)
    finally:
        if not args.keep:
            shutil.rmtree(work)


if __name__ == "__main__":
    main()
