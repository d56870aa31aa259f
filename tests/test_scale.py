"""More cores, more machines: rps3-run -j N, --shard K/N + merge, and
rps3-run-mpi under mpirun all give the datasets of a single-process run,
bit for bit (only the root attributes created_utc, command_line and
history differ)."""

import os
import random
import shutil
import subprocess
import time

import h5py
import numpy as np
import pytest

from conftest import FAILING_SINE, ROOT, RUNNER, run, write_scene
from rps3 import h5io

RUNNER_MPI = os.path.join(ROOT, "build", "rps3-run-mpi")
MPIRUN = shutil.which("mpirun")
# attributes that say when and how a file was made, not what it holds
RUN_ATTRS = {"created_utc", "command_line", "history"}


def datasets(f):
    out = {}
    f.visititems(lambda name, obj: out.__setitem__(name, obj)
                 if isinstance(obj, h5py.Dataset) else None)
    return out


def plain_attrs(obj, skip=()):
    """Attributes other than the dimension-scale references."""
    return {k: v for k, v in obj.attrs.items()
            if k not in skip and k not in ("DIMENSION_LIST", "REFERENCE_LIST")}


def assert_same_content(a, b):
    """Every dataset of a and b equal bit for bit (NaN included), with the
    same attributes; the root attributes equal but for RUN_ATTRS."""
    with h5py.File(a, "r") as f, h5py.File(b, "r") as g:
        fa, ga = plain_attrs(f, RUN_ATTRS), plain_attrs(g, RUN_ATTRS)
        assert fa.keys() == ga.keys()
        for k in fa:
            assert fa[k] == ga[k], k
        A, B = datasets(f), datasets(g)
        assert A.keys() == B.keys()
        for name in A:
            x, y = A[name], B[name]
            assert x.dtype == y.dtype and x.shape == y.shape, name
            # a joined file's per-case datasets are virtual: no chunks
            if not (x.is_virtual or y.is_virtual):
                assert x.chunks == y.chunks, name
            u, v = x[()], y[()]
            if isinstance(u, np.ndarray) and u.dtype.kind in "fiu":
                assert u.tobytes() == v.tobytes(), name
            else:
                assert np.array_equal(u, v), name
            xa, ya = plain_attrs(x), plain_attrs(y)
            assert xa.keys() == ya.keys(), name
            for k in xa:
                assert np.array_equal(xa[k], ya[k]), (name, k)
            assert ([len(d) for d in x.dims] == [len(d) for d in y.dims]), name


def mixed_scene(tmp_path):
    """20 cases of 4001 samples (5 jobs of 4 cases), closed-form and
    multiroot theta, two cases that fail (the platform below the base)."""
    text = FAILING_SINE.replace("SAMPLES", "4001").replace(
        "solver: {theta: THETA}", "")
    text = text.replace(
        "  trajectory.amp[2]: [0.05, 0.2, 0.1]",
        "  trajectory.amp[2]: [0.05, 0.2, 0.1, 0.07, 0.02, 0.09, 0.03, 0.06,"
        " 0.08, 0.04]\n  solver.theta: [closed_form, multiroot]")
    return write_scene(tmp_path / "mixed.yaml", text)


def windows_scene(tmp_path):
    """3 cases longer than a tile (in windows, warm multiroot across them);
    case 1 fails in its third window."""
    text = FAILING_SINE.replace("SAMPLES", "40001").replace("THETA",
                                                            "multiroot")
    return write_scene(tmp_path / "windows.yaml", text)


def spans_scene(tmp_path):
    """12 cases of 5001 to 40001 samples (a sweep of the span with dt): the
    longer ones in windows, the chunks past each case's end never written
    (they read as the fill values); the amp[2] = 0.2 cases fail."""
    text = FAILING_SINE.replace("samples: SAMPLES", "dt: 0.0001").replace(
        "THETA", "closed_form").replace(
        "sweep:\n", "sweep:\n  trajectory.duration: [2, 0.5, 4, 1]\n")
    return write_scene(tmp_path / "spans.yaml", text)


SCENES = {"mixed": mixed_scene, "windows": windows_scene,
          "spans": spans_scene}


@pytest.fixture(scope="module", params=list(SCENES))
def reference(request, tmp_path_factory):
    """(scene, the file of a single-threaded whole run)."""
    tmp = tmp_path_factory.mktemp(request.param)
    scene = SCENES[request.param](tmp)
    out = tmp / "ref.h5"
    proc = run(scene, out, "-q")
    assert proc.returncode == 1, proc.stderr       # some cases fail
    with h5py.File(out, "r") as f:
        assert (f["status"][()] != 0).sum() >= 1
        assert (f["status"][()] == 0).sum() >= 2
    return scene, out


def test_threads_give_the_same_file(reference, tmp_path):
    scene, ref = reference
    for j in (2, 3, 7):
        out = tmp_path / f"j{j}.h5"
        proc = run(scene, out, "-q", "-j", str(j))
        assert proc.returncode == 1, proc.stderr
        assert_same_content(ref, out)


CHUNKED = ("force", "force_by_effect", "warn", "solve_niter", "case_time")


def stored_chunks(path):
    """{(name, chunk offset): (filter mask, stored bytes)} of the chunked
    per-sample datasets of a file."""
    out = {}
    with h5py.File(path, "r") as f:
        for name in CHUNKED:
            if name not in f:
                continue
            d = f[name].id
            for i in range(d.get_num_chunks()):
                off = d.get_chunk_info(i).chunk_offset
                out[name, off] = d.read_direct_chunk(off)
    return out


def hdf5_filtered_chunks(path, tmp):
    """The same chunks as HDF5's own fletcher32 filter stores them: h5py
    writes each dataset's values, with its chunks and fill value, into a
    new file; {(name, offset): (mask, bytes)} of the chunks path holds."""
    ref = {}
    with h5py.File(path, "r") as f, h5py.File(tmp, "w") as g:
        for name in CHUNKED:
            if name not in f:
                continue
            x = f[name]
            y = g.create_dataset(name, data=x[()], chunks=x.chunks,
                                 fletcher32=True, fillvalue=x.fillvalue)
            for i in range(x.id.get_num_chunks()):
                off = x.id.get_chunk_info(i).chunk_offset
                ref[name, off] = y.id.read_direct_chunk(off)
    return ref


@pytest.mark.parametrize("gzip", ["0", "4"])
def test_packed_chunks_are_the_chunks_hdf5_stores(reference, tmp_path,
                                                  gzip):
    """The runner stores chunks it made itself (out_pack: with -j N the
    workers deflate and checksum them; uncompressed, also at -j 1, full
    chunks straight from the tile): every stored chunk, filters applied,
    is byte for byte the one HDF5's own filters store -- at -j 1 for
    --gzip (HDF5's deflate there), and as h5py's HDF5 stores the same
    values uncompressed (the data and its Fletcher-32 checksum)."""
    scene, _ = reference
    one, two = tmp_path / "j1.h5", tmp_path / "j2.h5"
    for out, j in ((one, "1"), (two, "2")):
        proc = run(scene, out, "-q", "-j", j, "--gzip", gzip)
        assert proc.returncode == 1, proc.stderr
    a, b = stored_chunks(one), stored_chunks(two)
    assert a.keys() == b.keys() and len(a) >= 10
    ref = hdf5_filtered_chunks(one, tmp_path / "h5py.h5") if gzip == "0" \
        else a
    for key in a:
        assert a[key][0] == b[key][0] == ref[key][0] == 0, key
        assert a[key][1] == b[key][1] == ref[key][1], key
    assert_same_content(one, two)


def test_shards_merge_to_the_same_file(reference, tmp_path):
    scene, ref = reference
    parts = []
    for k in range(3):
        part = tmp_path / f"part{k}.h5"
        # part 1 on threads and compressed: chunks are copied as stored
        extra = ["-j", "2", "--gzip", "3"] if k == 1 else []
        proc = run(scene, part, "-q", "--shard", f"{k}/3", *extra)
        assert proc.returncode in (0, 1), proc.stderr
        with h5py.File(part, "r") as f:
            assert f.attrs["shard"] == f"{k}/3"
        parts.append(str(part))
    random.Random(2385).shuffle(parts)
    # --copy: one self-contained file
    out = tmp_path / "merged.h5"
    proc = subprocess.run([RUNNER, "merge", str(out), "--copy"] + parts,
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 1, proc.stderr       # the failed cases
    assert "merged 3 parts" in proc.stderr
    with h5py.File(out, "r") as f:
        assert "shard" not in f.attrs
        assert "merge" in f.attrs["command_line"]
        for name in ("force", "theta", "energy_residual"):
            assert f[name].compression is None, name
            assert not f[name].is_virtual
    assert_same_content(ref, out)
    # the default: virtual datasets over the parts, from another directory
    (tmp_path / "elsewhere").mkdir()
    vds = tmp_path / "joined.h5"
    proc = subprocess.run([RUNNER, "merge", "../joined.h5"] +
                          [os.path.join("..", os.path.basename(p))
                           for p in parts],
                          capture_output=True, text=True, timeout=60,
                          cwd=tmp_path / "elsewhere")
    assert proc.returncode == 1, proc.stderr
    assert "joined 3 parts into ../joined.h5 (" in proc.stderr
    with h5py.File(vds, "r") as f:
        assert "shard" not in f.attrs
        for name in ("force", "status", "message", "scene_resolved"):
            assert f[name].is_virtual, name
            # stored relative to the joined file: the directory may move
            assert {m.file_name for m in f[name].virtual_sources()} == {
                "part0.h5", "part1.h5", "part2.h5"}
        samples = h5io.dims(f["force"])[1]        # time, or sample
        assert not f[samples].is_virtual and not f["scene"].is_virtual
    # the samples stay in the parts
    assert vds.stat().st_size < out.stat().st_size / 10
    assert_same_content(ref, vds)
    (tmp_path / "elsewhere").rmdir()
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "joined.h5", "merged.h5", "part0.h5", "part1.h5", "part2.h5"]
    moved = tmp_path.parent / (tmp_path.name + "-moved")
    shutil.copytree(tmp_path, moved)
    assert_same_content(ref, moved / "joined.h5")
    shutil.rmtree(moved)


def test_a_part_alone_holds_its_cases_only(tmp_path):
    scene = mixed_scene(tmp_path)
    part = tmp_path / "p.h5"
    assert run(scene, part, "-q", "--shard", "1/2").returncode in (0, 1)
    with h5py.File(part, "r") as f:
        status = f["status"][()]
        chunk = f["status"].chunks[0]
        mine = (np.arange(len(status)) // chunk) % 2 == 1
        assert (status[~mine] == -1000).all()       # fill value: not run
        assert (status[mine] >= 0).all()
        assert np.isnan(f["force"][np.flatnonzero(~mine)[0]]).all()


def test_merge_refuses_what_does_not_fit(tmp_path):
    scene = mixed_scene(tmp_path)
    p = {}
    for k in range(3):
        p[k] = str(tmp_path / f"p{k}.h5")
        assert run(scene, p[k], "-q", "--shard", f"{k}/3").returncode in (0, 1)
    whole = str(tmp_path / "whole.h5")
    run(scene, whole, "-q")
    other = write_scene(tmp_path / "other.yaml",
                        open(scene).read().replace("duration: 2",
                                                   "duration: 2.5"))
    o2 = str(tmp_path / "o2.h5")
    assert run(other, o2, "-q", "--shard", "2/3").returncode in (0, 1)

    def merge(*parts):
        return subprocess.run([RUNNER, "merge", str(tmp_path / "m.h5"),
                               *parts], capture_output=True, text=True)

    bad = [((p[0], p[1]), 2, "2 parts given, the run has 3 shards\n"
            "rps3-run merge: 1 of 3 shards to run again: 2\n"),
           ((p[0], p[1], p[1]), 2, "are both shard 1/3"),
           ((p[0], p[1], whole), 2, "not a part file"),
           ((p[0], p[1], o2), 3, "not a part of the same scene"),
           ((p[0], p[1], str(tmp_path / "nope.h5")), 2, "cannot open")]
    for parts, code, msg in bad:
        proc = merge(*parts)
        assert proc.returncode == code, (parts, proc.stderr)
        assert msg in proc.stderr, proc.stderr
        assert not (tmp_path / "m.h5").exists()
    assert not [x for x in os.listdir(tmp_path) if ".tmp." in x]


def test_merge_names_what_to_run_again(tmp_path):
    """Missing and incomplete parts: their shard numbers as a list for
    sbatch --array, and the command that makes each again, which does."""
    scene = mixed_scene(tmp_path)
    parts = tmp_path / "parts"
    parts.mkdir()
    for k in range(5):
        proc = run(scene, parts / f"grid.{k}.h5", "-q", "--shard", f"{k}/5")
        assert proc.returncode in (0, 1), proc.stderr
    # part 3 lost a case: its status back at the fill value
    with h5py.File(parts / "grid.3.h5", "r+") as f:
        chunk = f["status"].chunks[0]
        f["status"][3 * chunk + 1] = -1000
    given = [str(parts / f"grid.{k}.h5") for k in (0, 2, 3)]
    proc = subprocess.run([RUNNER, "merge", str(tmp_path / "m.h5"), *given],
                          capture_output=True, text=True)
    assert proc.returncode == 2, proc.stderr
    assert f"grid.3.h5: case {3 * chunk + 1} was never written" in proc.stderr
    assert "3 of 5 shards to run again: 1,3,4\n" in proc.stderr
    lines = [x.strip() for x in proc.stderr.splitlines()
             if x.startswith("  ") and "--shard" in x]
    assert len(lines) == 3, proc.stderr
    for k, line in zip((1, 3, 4), lines):
        assert f"-o {parts}/grid.{k}.h5 -q --shard {k}/5" in line, line
        (parts / f"grid.{k}.h5").unlink(missing_ok=True)
        # the command as printed makes the part again
        assert subprocess.run(line, shell=True).returncode in (0, 1)
    proc = subprocess.run([RUNNER, "merge", str(tmp_path / "m.h5"),
                           *map(str, parts.iterdir())],
                          capture_output=True, text=True)
    assert proc.returncode == 1, proc.stderr
    whole = tmp_path / "whole.h5"
    run(scene, whole, "-q")
    assert_same_content(whole, tmp_path / "m.h5")


def test_bad_thread_and_shard_arguments(tmp_path):
    scene = mixed_scene(tmp_path)
    for args in (["-j", "0"], ["-j", "x"], ["-j", "100000"],
                 ["--shard", "3/3"], ["--shard", "1"], ["--shard", "-1/2"],
                 ["--shard", "0/0"], ["--shard", "1/2x"]):
        proc = run(scene, tmp_path / "x.h5", *args)
        assert proc.returncode == 2, (args, proc.stderr)
    assert os.listdir(tmp_path) == ["mixed.yaml"]


def test_plain_runner_under_mpirun_says_which_binary(tmp_path):
    scene = mixed_scene(tmp_path)
    env = dict(os.environ, OMPI_COMM_WORLD_SIZE="3")
    proc = run(scene, tmp_path / "x.h5", env=env)
    assert proc.returncode == 2
    assert "rps3-run-mpi" in proc.stderr


def mpirun(n, *args, timeout=120):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1",
               OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    return subprocess.run([MPIRUN, "--oversubscribe", "-n", str(n),
                           *map(str, args)], capture_output=True, text=True,
                          timeout=timeout, env=env)


@pytest.mark.skipif(MPIRUN is None, reason="mpirun (openmpi-bin) missing")
def test_mpirun_gives_the_same_file(reference, tmp_path):
    scene, ref = reference
    assert os.access(RUNNER_MPI, os.X_OK), "make runner-mpi"
    out = tmp_path / "mpi.h5"
    proc = mpirun(3, RUNNER_MPI, scene, "-o", out, "-j", "2")
    assert proc.returncode == 1, proc.stderr      # the failed cases
    # the size estimate and one summary line, from rank 0, for all the
    # cases (and, in windows, the warning that -j 2 has one job per rank)
    said = [x for x in proc.stderr.splitlines()
            if x.startswith("rps3-run: ") and "warning: -j 2" not in x
            and "first failure" not in x]
    assert len(said) == 2, proc.stderr
    # and the first failure's reason, at most once per rank that had one
    first = proc.stderr.count("rps3-run: first failure: case ")
    assert 1 <= first <= 3, proc.stderr
    with h5py.File(ref, "r") as f:
        n = len(f["status"])
    assert f"{n}/{n} cases" in proc.stderr
    assert_same_content(ref, out)
    # by default the ranks' parts stay, joined by virtual datasets; they
    # are parts like those of --shard
    names = [f"mpi.h5.part{r}of3" for r in range(3)]
    assert sorted(x.name for x in tmp_path.iterdir()) == ["mpi.h5"] + names
    with h5py.File(out, "r") as f:
        assert f["force"].is_virtual
    proc = subprocess.run([RUNNER, "merge", str(tmp_path / "m.h5"),
                           *[str(tmp_path / x) for x in names]],
                          capture_output=True, text=True)
    assert proc.returncode == 1, proc.stderr
    assert_same_content(ref, tmp_path / "m.h5")
    # --copy: one self-contained file, the parts gone
    out = tmp_path / "copy" / "mpi.h5"
    out.parent.mkdir()
    proc = mpirun(3, RUNNER_MPI, scene, "-o", out, "-j", "2", "--copy")
    assert proc.returncode == 1, proc.stderr
    with h5py.File(out, "r") as f:
        assert not f["force"].is_virtual
    assert_same_content(ref, out)
    assert sorted(x.name for x in out.parent.iterdir()) == ["mpi.h5"]


@pytest.mark.skipif(MPIRUN is None, reason="mpirun (openmpi-bin) missing")
def test_mpirun_bad_scene_and_shard(tmp_path):
    scene = write_scene(tmp_path / "bad.yaml", "manipulator: {R: -1}\n")
    proc = mpirun(2, RUNNER_MPI, scene, "-o", tmp_path / "x.h5")
    assert proc.returncode == 2
    # said once, by rank 0
    assert proc.stderr.count("bad.yaml:1:") == 1, proc.stderr
    good = mixed_scene(tmp_path)
    proc = mpirun(2, RUNNER_MPI, good, "-o", tmp_path / "x.h5",
                  "--shard", "0/2")
    assert proc.returncode == 2 and "--shard" in proc.stderr
    proc = run(good, tmp_path / "x.h5", "--copy")
    assert proc.returncode == 2 and "--copy is for" in proc.stderr
    assert sorted(os.listdir(tmp_path)) == ["bad.yaml", "mixed.yaml"]


def test_jobs_are_counted_and_too_many_shards_refused(tmp_path):
    """mixed: 20 cases of 4001 samples, tiles of 4 cases: 5 jobs.  A shard
    beyond the jobs could hold nothing: --shard K/N with N > 5 is refused
    (exit 2, nothing written), naming the job count; -j beyond the jobs is
    a warning."""
    scene = mixed_scene(tmp_path)
    proc = run(scene, None, "--check")
    assert proc.returncode == 0, proc.stderr
    assert "5 work units of up to 4 cases: at most 5 shards" in proc.stdout
    assert "warning" not in proc.stderr
    for args in (["--check", "--shard", "0/8"], ["--shard", "6/8"],
                 ["-q", "--shard", "1/6"]):
        out = [] if "--check" in args else [tmp_path / "p.h5"]
        proc = run(scene, *out, *args)
        assert proc.returncode == 2, (args, proc.stderr)
        assert "the sweep has 5 work units (tiles of up to 4 cases), so at most " \
               "5 shards can have work: use --shard K/5 or fewer" \
            in proc.stderr, proc.stderr
    assert sorted(os.listdir(tmp_path)) == ["mixed.yaml"]
    proc = run(scene, tmp_path / "p4.h5", "-q", "--shard", "4/5")
    assert proc.returncode == 0, proc.stderr
    proc = run(scene, tmp_path / "p1.h5", "--shard", "1/2", "-j", "4")
    assert "-j 4 but this shard has 2 work units: 2 threads stay idle" \
        in proc.stderr
    assert "8/8 cases" in proc.stderr and ", 2 of 5 work units" in proc.stderr
    proc = run(scene, tmp_path / "all.h5", "-j", "2")
    assert "warning" not in proc.stderr
    assert proc.stderr.rstrip().endswith(", 5 work units"), proc.stderr


@pytest.mark.skipif(MPIRUN is None, reason="mpirun (openmpi-bin) missing")
def test_more_ranks_than_jobs_warn_and_join(tmp_path):
    """mpirun -n N is often set by the allocation: ranks beyond the jobs
    write empty parts and the join still gives the whole file."""
    scene = write_scene(tmp_path / "two.yaml",
                        FAILING_SINE.replace("SAMPLES", "9001").replace(
                            "THETA", "closed_form").replace(
                            "[0.05, 0.2, 0.1]", "[0.05, 0.1]"))
    out = tmp_path / "mpi.h5"
    proc = mpirun(3, RUNNER_MPI, scene, "-o", out)
    assert proc.returncode == 0, proc.stderr
    assert "3 ranks but the sweep has 2 work units" in proc.stderr
    assert "ranks 2-2 compute nothing; use at most 2" in proc.stderr
    with h5py.File(out, "r") as f:
        assert (f["status"][()] == 0).all()
        assert not np.isnan(f["force"][()]).any()


def test_resume_skips_complete_parts_only(reference, tmp_path):
    scene, ref = reference
    parts = [tmp_path / f"p{k}.h5" for k in range(3)]
    for k, p in enumerate(parts):
        assert run(scene, p, "-q", "--shard", f"{k}/3").returncode in (0, 1)
    parts[1].unlink()                               # a cancelled task
    with h5py.File(parts[2], "r+") as f:            # a part gone wrong
        f["status"][2 * f["status"].chunks[0]] = -1000  # not computed
    before = parts[0].stat().st_mtime_ns
    said = {}
    for k, p in enumerate(parts):
        proc = run(scene, p, "--shard", f"{k}/3", "--resume", "--failed-ok")
        assert proc.returncode == 0, proc.stderr
        said[k] = proc.stderr
    assert "complete" in said[0] and "not run again" in said[0]
    assert parts[0].stat().st_mtime_ns == before     # not written
    assert "not run again" not in said[1]
    assert "was never written: the part is incomplete: running shard 2/3 " \
           "again" in said[2]
    out = tmp_path / "m.h5"
    proc = subprocess.run([RUNNER, "merge", out, *parts, "--failed-ok"],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr        # complete, cases failed
    assert_same_content(ref, out)
    # a part of another scene is no part of this one
    other = write_scene(tmp_path / "other.yaml",
                        open(scene).read().replace("duration: 2",
                                                   "duration: 2.5"))
    proc = run(other, parts[0], "--shard", "0/3", "--resume", "-q")
    assert "not a part of the same scene: running shard 0/3 again" \
        in proc.stderr
    proc = run(scene, tmp_path / "x.h5", "--resume")
    assert proc.returncode == 2 and "--resume is for --shard" in proc.stderr


def test_failed_ok_maps_failed_cases_to_success(tmp_path):
    scene = mixed_scene(tmp_path)
    assert run(scene, tmp_path / "a.h5", "-q").returncode == 1
    assert run(scene, tmp_path / "b.h5", "-q",
               "--failed-ok").returncode == 0
    with h5py.File(tmp_path / "b.h5", "r") as f:
        assert (f["status"][()] != 0).sum() >= 1     # the same file
    bad = write_scene(tmp_path / "bad.yaml", "manipulator: {R: -1}\n")
    assert run(bad, tmp_path / "c.h5", "--failed-ok").returncode == 2


def _host():
    import re
    import socket
    return re.sub(r"[^A-Za-z0-9_-]", "_", socket.gethostname().split(".")[0])


def test_temporaries_are_named_by_owner_and_cleaned(tmp_path):
    """kill -9 leaves OUT.tmp.HOST.PID.jobJOB.rankR; the next run of OUT
    removes it (its process is gone); --clean removes those of dead
    processes, --force those of other hosts too, never a live one's."""
    text = FAILING_SINE.replace("SAMPLES", "40001").replace("THETA",
                                                            "multiroot")
    scene = write_scene(tmp_path / "long.yaml", text.replace(
        "trajectory.amp[2]: [0.05, 0.2, 0.1]",
        "trajectory.amp[2]: [" + ", ".join(["0.05"] * 40) + "]"))
    out = tmp_path / "out.h5"
    env = dict(os.environ, SLURM_ARRAY_JOB_ID="77", SLURM_ARRAY_TASK_ID="3")
    proc = subprocess.Popen([RUNNER, scene, "-o", out, "-q"], env=env)
    try:
        for _ in range(600):
            tmps = [x for x in os.listdir(tmp_path) if ".tmp." in x]
            if tmps:
                break
            time.sleep(0.01)
    finally:
        proc.kill()
        proc.wait()
    assert tmps == [f"out.h5.tmp.{_host()}.{proc.pid}.job77_3.rank0"], tmps
    small = mixed_scene(tmp_path)
    done = run(small, out, "-q")
    assert done.returncode == 1, done.stderr
    assert f"removed {tmp_path}/{tmps[0]} (process {proc.pid}" in done.stderr
    assert not [x for x in os.listdir(tmp_path) if ".tmp." in x]

    gone = subprocess.Popen(["true"])
    gone.wait()
    names = {"dead": f"out.h5.tmp.{_host()}.{gone.pid}.jobnone.rank0",
             "alive": f"out.h5.tmp.{_host()}.{os.getpid()}.jobnone.rank1",
             "other": "out.h5.tmp.elsewhere.123.job9.rank0",
             "unknown": "out.h5.tmp.4242"}
    for n in names.values():
        (tmp_path / n).write_bytes(b"x")
    proc = subprocess.run([RUNNER, "--clean", out], capture_output=True,
                          text=True)
    assert proc.returncode == 0, proc.stderr
    left = set(os.listdir(tmp_path))
    assert names["dead"] not in left
    assert {names["alive"], names["other"], names["unknown"]} <= left
    assert "its process is running" in proc.stderr
    assert "written on another host, not checked" in proc.stderr
    proc = subprocess.run([RUNNER, "--clean", out, "--force"],
                          capture_output=True, text=True)
    left = set(os.listdir(tmp_path))
    assert names["alive"] in left
    assert not {names["other"], names["unknown"]} & left
    assert subprocess.run([RUNNER, "--clean"]).returncode == 2


def test_plain_runner_under_srun_refuses(tmp_path):
    scene = mixed_scene(tmp_path)
    env = dict(os.environ, SLURM_PROCID="1", SLURM_STEP_NUM_TASKS="2",
               SLURM_NTASKS="2")
    proc = run(scene, tmp_path / "x.h5", env=env)
    assert proc.returncode == 2
    assert "2 tasks by srun" in proc.stderr and "rps3-run-mpi" in proc.stderr
    # the batch script of a 2-task job runs one process: that is fine
    env = dict(os.environ, SLURM_NTASKS="2", SLURM_JOB_ID="5")
    assert run(scene, tmp_path / "x.h5", "-q", env=env).returncode == 1
    if os.access(RUNNER_MPI, os.X_OK):
        env = dict(os.environ, SLURM_PROCID="0", SLURM_STEP_NUM_TASKS="2")
        proc = subprocess.run([RUNNER_MPI, scene, "--check"],
                              capture_output=True, text=True, env=env)
        assert proc.returncode == 2 and "srun --mpi=pmix" in proc.stderr
