"""Throughput and peak memory of rps3-run, HDF5 writes included.

Runs build/rps3-run on sweeps of 10^3 to 10^7 trajectory points (the
paper's helix, Table II, 1000 samples a case, the default effects, closed
form theta, Lagrange, the energy certificate on; cases are a sweep of m/M)
with 1 and 2 threads, and one warm multiroot sweep.  Each run is a fresh
process; its wall time comes from the monotonic clock around it, its peak
RSS from GNU time (/usr/bin/time), its CPU time (user + system, the
runner's and GNU time's own, about a millisecond) from wait4 on GNU time,
to the microsecond (GNU time prints hundredths).  A table on stdout, the
figures in an HDF5 file (one dataset per column along a `run` dimension
scale, `units` and `doc` on each).  Medians over the repeats; timings are
never asserted.

--against OLD runs another build of rps3-run on the same rows, its runs
interleaved with the runner's (old, new, old, new, ...: a shared machine's
load falls on both alike), and prints its table and the ratios of CPU
time; only the runner's rows go to the HDF5 file.

    python tests/bench/runner_bench.py [-o out/bench_runner.h5]
        [--runner build/rps3-run] [--against OLD/rps3-run]
        [--max-points 1e7] [--repeats 3] [--only closed_1e6_j1,...]
"""

import argparse
import datetime
import os
import platform
import shutil
import statistics
import subprocess
import tempfile
import time

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(
    __file__))))
SAMPLES = 1000
# the goals of docs/performance.md, "Goals and today's numbers"
TARGET_RATE = 1e6       # points per second per core
TARGET_RSS_MIB = 64.0   # peak RSS at 10^7 points
GNU_TIME = "/usr/bin/time"  # Debian package `time`

SCENE = """\
# runner_bench.py: the paper's helix (Table II), {ncase} case(s) of {samples}
# samples; the default effects, closed-form theta, Lagrange, certificate on
manipulator: {{R: 0.2286, rho: 0.5, M: 0.18, m_over_M: 0.5, d: 0.1524}}
trajectory: {{kind: helix, radius: 0.000266, pitch: 0.03048, z0: 0.3048,
             period: 10.0, blend: 1.0, samples: {samples}}}
solver: {{theta: {theta}}}
sweep:
  manipulator.m_over_M: {sweep}
"""


def scene_text(ncase, theta):
    sweep = "[0.5]" if ncase == 1 else f"{{from: 0, to: 0.5, num: {ncase}}}"
    return SCENE.format(ncase=ncase, samples=SAMPLES, theta=theta,
                        sweep=sweep)


def raw_bytes(path):
    """(samples, bytes) of the data a runner file holds: every per-sample
    variable at its element size times the samples of the cases (not the
    NaN past a shorter case's end), the per-case variables (strings at
    their length); no chunk index, no metadata.  The file's size over this
    is its overhead."""
    with h5py.File(path, "r") as f:
        ncase = f["case"].shape[0]
        if "case_time" in f:
            samples = int((~np.isnan(f["case_time"][()])).sum())
        else:
            samples = ncase * f["time"].shape[0]
        raw = 0
        for name, ds in f.items():
            if name == "case" or ds.ndim == 0 or ds.shape[0] != ncase:
                continue
            if ds.ndim >= 2:
                raw += samples * ds.dtype.itemsize * int(np.prod(
                    ds.shape[2:]))
            elif ds.dtype.kind == "O":
                raw += sum(len(x) for x in ds[()])
            else:
                raw += ncase * ds.dtype.itemsize
        return samples, raw


# the per-sample fields rps3_inverse_batch returns: a file of only these
# is computed by the batch (its vectorised kernel here)
BATCH_FIELDS = ("force,force_by_effect,length,theta,alpha,beta,z_c,lambda,"
                "energy_residual,condition,solve_niter,warn")


def run_once(runner, scene, out, threads, gzip=0, fields=None):
    """One run: (wall s, user + sys s, peak RSS MiB, file bytes, raw
    bytes of its data, raw_bytes()).

    GNU time runs the runner and reports its CPU time and peak RSS: the
    rusage of a child forked from Python would start from Python's own
    resident size (ru_maxrss survives exec)."""
    cmd = [runner, scene, "-o", out, "-q", "-j", str(threads)]
    if gzip:
        cmd += ["--gzip", str(gzip)]
    if fields:
        cmd += ["--fields", fields]
    with tempfile.TemporaryFile(mode="w+") as err:
        t0 = time.monotonic()
        p = subprocess.Popen([GNU_TIME, "-f", "%M"] + cmd, stderr=err)
        # the rusage of GNU time includes the runner's (its waited-for
        # child), in microseconds
        _, status, ru = os.wait4(p.pid, 0)
        wall = time.monotonic() - t0
        p.returncode = os.waitstatus_to_exitcode(status)
        err.seek(0)
        stderr = err.read()
    if p.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)}: exit {p.returncode}: {stderr}")
    rss_kib = stderr.split()[-1]
    size = os.path.getsize(out)
    raw = raw_bytes(out)[1]
    os.unlink(out)
    return (wall, ru.ru_utime + ru.ru_stime, float(rss_kib) / 1024.0, size,
            raw)


def cpu_model():
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
        for line in out.splitlines():
            if line.startswith("Model name:"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def plan(max_points, repeats):
    """(label, points, threads, theta, repeats, gzip level, --fields) of
    each row; the small, noisier runs are repeated more."""
    rows = []
    n = 1000
    while n <= max_points:
        rep = repeats if n >= 10**6 else 2 * repeats + 1
        for j in (1, 2):
            rows.append((f"closed_1e{len(str(n)) - 1}_j{j}", n, j,
                         "closed_form", rep, 0, None))
        n *= 10
    if max_points >= 10**6:
        rows.append(("multiroot_1e6_j1", 10**6, 1, "multiroot", repeats, 0,
                     None))
        # --fields: the batch's fields, and the forces alone
        for label, fields in (("fields_batch", BATCH_FIELDS),
                              ("fields_force", "force")):
            rows.append((f"{label}_1e6_j1", 10**6, 1, "closed_form",
                         repeats, 0, fields))
        # the cost of --gzip: level 1 and 4, on one and two threads
        for level in (1, 4):
            for j in (1, 2):
                rows.append((f"gzip{level}_1e6_j{j}", 10**6, j,
                             "closed_form", repeats, level, None))
    return rows


def row_of(label, points, threads, theta, rep, gzip, fields, runs):
    """The table's row of one run label from its runs (run_once)."""
    wall = [r[0] for r in runs]
    cpu = [r[1] for r in runs]
    rss = [r[2] for r in runs]
    med = statistics.median(wall)
    return dict(
        run=label, points=points, cases=points // SAMPLES, threads=threads,
        gzip=gzip, fields=fields or "all",
        theta=theta, repeats=rep, wall_s=med, wall_min_s=min(wall),
        wall_max_s=max(wall), cpu_s=statistics.median(cpu),
        cpu_min_s=min(cpu), cpu_max_s=max(cpu),
        points_per_s=points / med,
        points_per_s_per_thread=points / med / threads,
        points_per_cpu_s=points / statistics.median(cpu),
        rss_mib=max(rss), file_bytes=runs[0][3],
        bytes_per_point=runs[0][3] / points,
        raw_bytes_per_point=runs[0][4] / points)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", default=os.path.join(ROOT, "out",
                                                          "bench_runner.h5"))
    ap.add_argument("--runner", default=os.path.join(ROOT, "build",
                                                     "rps3-run"))
    ap.add_argument("--against", help="another rps3-run, run interleaved "
                    "with --runner on the same rows (its table and the CPU "
                    "time ratios are printed, not stored)")
    ap.add_argument("--max-points", type=float, default=1e7)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--only", help="comma-separated run labels to run "
                    "(default: all)")
    args = ap.parse_args()
    runners = [args.runner] + ([args.against] if args.against else [])
    only = set(args.only.split(",")) if args.only else None

    outdir = os.path.dirname(os.path.abspath(args.output))
    os.makedirs(outdir, exist_ok=True)
    # the runs' files next to the output (a real disk, not a tmpfs)
    work = tempfile.mkdtemp(prefix="runner_bench.", dir=outdir)
    rows = {r: [] for r in runners}
    try:
        for label, points, threads, theta, rep, gzip, fields in plan(
                int(args.max_points), args.repeats):
            if only is not None and label not in only:
                continue
            scene = os.path.join(work, f"{label}.yaml")
            with open(scene, "w") as f:
                f.write(scene_text(points // SAMPLES, theta))
            runs = {r: [] for r in runners}
            for _ in range(rep):
                for r in runners:
                    runs[r].append(run_once(r, scene,
                                            os.path.join(work, "o.h5"),
                                            threads, gzip, fields))
            for r in runners:
                rows[r].append(row_of(label, points, threads, theta, rep,
                                      gzip, fields, runs[r]))
    finally:
        shutil.rmtree(work, ignore_errors=True)

    print_table(rows[args.runner])
    if args.against:
        print(f"\n--against {args.against} (runs interleaved with the "
              f"above):")
        print_table(rows[args.against])
        print(f"\n{'run':22s} {'CPU s new':>10s} {'CPU s old':>10s} "
              f"{'new/old':>8s}")
        for a, b in zip(rows[args.runner], rows[args.against]):
            print(f"{a['run']:22s} {a['cpu_s']:10.3f} {b['cpu_s']:10.3f} "
                  f"{a['cpu_s'] / b['cpu_s']:8.3f}")
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs "
          f"at the end")
    if rows[args.runner]:
        write_h5(args.output, rows[args.runner])


def print_table(rows):
    print(f"{'run':22s} {'points':>9s} {'j':>2s} {'wall s':>8s} "
          f"{'CPU s':>7s} {'min-max CPU s':>15s} {'Mpt/s':>7s} "
          f"{'Mpt/s/j':>8s} {'Mpt/cpu-s':>9s} {'min-max':>11s} "
          f"{'RSS MiB':>8s} {'file MB':>8s} {'B/pt':>6s} {'raw':>6s}")
    for r in rows:
        print(f"{r['run']:22s} {r['points']:9d} {r['threads']:2d} "
              f"{r['wall_s']:8.3f} {r['cpu_s']:7.3f} "
              f"{r['cpu_min_s']:7.3f}-{r['cpu_max_s']:7.3f} "
              f"{r['points_per_s'] / 1e6:7.2f} "
              f"{r['points_per_s_per_thread'] / 1e6:8.2f} "
              f"{r['points_per_cpu_s'] / 1e6:9.2f} "
              f"{r['points'] / r['cpu_max_s'] / 1e6:5.2f}-"
              f"{r['points'] / r['cpu_min_s'] / 1e6:5.2f} "
              f"{r['rss_mib']:8.1f} "
              f"{r['file_bytes'] / 1e6:8.1f} {r['bytes_per_point']:6.1f} "
              f"{r['raw_bytes_per_point']:6.1f}")
    if not rows:
        return
    big = [r for r in rows if r["points"] >= 10**6
           and r["theta"] == "closed_form" and r["gzip"] == 0
           and r["fields"] == "all"]
    j1 = [r["points_per_s"] for r in big if r["threads"] == 1]
    if j1:
        print(f"target >= {TARGET_RATE / 1e6:.1f} Mpt/s per core: one thread "
              f"at 10^6 points and up: {min(j1) / 1e6:.2f}-"
              f"{max(j1) / 1e6:.2f} Mpt/s (ratio {min(j1) / TARGET_RATE:.2f}"
              f"-{max(j1) / TARGET_RATE:.2f})")
    # below 10^5 points the file's fixed part (superblock, attributes,
    # scales, the scene: ~100 kB) outweighs the data
    for r in rows:
        if r["points"] >= 10**6 and r["gzip"] == 0 and r["threads"] == 1 \
                and r["theta"] == "closed_form":
            print(f"target >= 3 Mpt per CPU-s, {r['run']} "
                  f"(--fields {r['fields']}): "
                  f"{r['points_per_cpu_s'] / 1e6:.2f} Mpt/cpu-s "
                  f"({r['points'] / r['cpu_max_s'] / 1e6:.2f}-"
                  f"{r['points'] / r['cpu_min_s'] / 1e6:.2f}; ratio "
                  f"{r['points_per_cpu_s'] / 3e6:.2f})")
    over = [r["bytes_per_point"] / r["raw_bytes_per_point"] for r in rows
            if r["gzip"] == 0 and r["points"] >= 10**5
            and r["fields"] == "all"]
    if over:
        print(f"target file <= 1.10 x its raw data (uncompressed, 10^5 "
              f"points and up): {min(over):.3f}-{max(over):.3f} x")
    top = max(r["points"] for r in rows)
    rss = max(r["rss_mib"] for r in rows if r["points"] == top)
    print(f"target peak RSS <= {TARGET_RSS_MIB:.0f} MiB at 10^7 points: "
          f"{rss:.1f} MiB at {top:.0e} points (ratio "
          f"{rss / TARGET_RSS_MIB:.2f}); smallest run "
          f"{min(r['rss_mib'] for r in rows):.1f} MiB")


COLUMNS = [
    ("points", "1", "trajectory points in the sweep (cases x samples)"),
    ("cases", "1", "cases of the sweep (1000 samples each)"),
    ("threads", "1", "rps3-run -j"),
    ("gzip", "1", "rps3-run --gzip level (0: uncompressed)"),
    ("repeats", "1", "runs of this row; the times are their median"),
    ("wall_s", "s", "median wall time of the whole run, HDF5 file included"),
    ("wall_min_s", "s", "fastest run"),
    ("wall_max_s", "s", "slowest run"),
    ("cpu_s", "s", "median user + system CPU time of the process"),
    ("cpu_min_s", "s", "least CPU time of the repeats"),
    ("cpu_max_s", "s", "most CPU time of the repeats"),
    ("points_per_s", "1/s", "points / median wall time"),
    ("points_per_s_per_thread", "1/s", "points_per_s / threads"),
    ("points_per_cpu_s", "1/s", "points / median CPU time"),
    ("rss_mib", "MiB", "peak resident set size, largest over the repeats"),
    ("file_bytes", "B", "size of the HDF5 file written"),
    ("bytes_per_point", "B", "file_bytes / points"),
    ("raw_bytes_per_point", "B",
     "bytes of the data the file holds (every variable at its element size, "
     "strings at their length) / points: the floor of bytes_per_point"),
]


def write_h5(path, rows):
    tmp = path + ".tmp"
    with h5py.File(tmp, "w") as f:
        f.attrs["machine"] = f"{cpu_model()}, {os.cpu_count()} CPUs, " \
                             f"{platform.platform()}"
        f.attrs["created_utc"] = datetime.datetime.now(
            datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
        f.attrs["scene"] = scene_text(10, "closed_form")
        f.attrs["targets"] = (f"points_per_s_per_thread >= {TARGET_RATE:g} "
                              f"with one thread; rss_mib <= "
                              f"{TARGET_RSS_MIB:g} at 1e7 points")
        run = f.create_dataset("run", data=np.array(
            [r["run"] for r in rows], dtype=h5py.string_dtype()))
        run.attrs["units"] = "1"
        run.attrs["doc"] = "closed_1eN_jJ: 10^N points, closed-form theta, " \
                           "J threads; multiroot_*: warm multiroot theta; " \
                           "gzipL_*: --gzip L; fields_*: --fields (the " \
                           "batch's fields, or force)"
        run.make_scale("run")
        theta = f.create_dataset("theta", data=np.array(
            [r["theta"] for r in rows], dtype=h5py.string_dtype()))
        theta.attrs["units"] = "1"
        theta.attrs["doc"] = "solver.theta of the scene"
        theta.dims[0].attach_scale(run)
        fields = f.create_dataset("fields", data=np.array(
            [r["fields"] for r in rows], dtype=h5py.string_dtype()))
        fields.attrs["units"] = "1"
        fields.attrs["doc"] = "rps3-run --fields of the run (all: none given)"
        fields.dims[0].attach_scale(run)
        for name, units, doc in COLUMNS:
            ds = f.create_dataset(name, data=np.array([r[name] for r in rows]))
            ds.attrs["units"] = units
            ds.attrs["doc"] = doc
            ds.dims[0].attach_scale(run)
    os.replace(tmp, path)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
