"""Shards of one run read the same data: every output file records the
SHA-256 of each file its scene reads (root attribute input_files, one line
"KEY sha256:HEX PATH" a file), `merge` refuses parts computed from
different contents of a file (a table measured again between two shards)
and `--resume` computes such a part again; a part whose file changed and
changed back is kept.  And the failed cases a part, a resumed part and a
merge report are those of their own cases: the other shards' cases, not
computed in a part, are no failures.  Parts from another scene and parts of
an interrupted run: tests/test_scale.py."""

import hashlib
import os
import shutil
import subprocess

import h5py
import numpy as np
import pytest

from conftest import CONFIGS, FAILING_SINE, ROOT, RUNNER, run, write_scene
from test_scale import MPIRUN, RUNNER_MPI, assert_same_content, mpirun

NOT_COMPUTED = -1000        # status fill value: a case no shard wrote here
SWEEP = ("sweep:\n  manipulator.m_over_M: "
         "[0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.1]\n")


def csv_rows(path):
    """(comment and header lines, rows as lists of strings) of a CSV."""
    head, rows = [], []
    for line in open(path).read().splitlines():
        if line.startswith("#") or (not rows and len(head) == sum(
                x.startswith("#") for x in head)):
            head.append(line)       # comments, then the column names
        elif line.strip():
            rows.append(line.split(","))
    return head, rows


def remeasure_csv(path, delta):
    """The last column of a middle row moved by delta (a row measured
    again): still a valid table, another content."""
    head, rows = csv_rows(path)
    r = rows[len(rows) // 2]
    r[-1] = repr(float(r[-1]) + delta)
    path.write_text("\n".join(head + [",".join(x) for x in rows]) + "\n")


def csv_to_h5(src, dst):
    head, rows = csv_rows(src)
    names = [c.strip() for c in head[-1].split(",")]
    data = np.array([[float(x) for x in r] for r in rows])
    with h5py.File(dst, "w") as f:
        for i, n in enumerate(names):
            f[n] = data[:, i]


def remeasure_h5(path, delta):
    with h5py.File(path, "r+") as f:
        name = [k for k in f if k != "t"][-1]
        f[name][len(f[name]) // 2] += delta


def table_csv(tmp):
    shutil.copy(os.path.join(CONFIGS, "measured.csv"), tmp / "m.csv")
    text = open(os.path.join(CONFIGS, "measured.yaml")).read()
    scene = write_scene(tmp / "s.yaml", text.replace("measured.csv", "m.csv")
                        + SWEEP)
    return scene, tmp / "m.csv", remeasure_csv


def table_h5(tmp):
    csv_to_h5(os.path.join(CONFIGS, "measured.csv"), tmp / "m.h5")
    text = open(os.path.join(CONFIGS, "measured.yaml")).read()
    scene = write_scene(tmp / "s.yaml", text.replace("measured.csv", "m.h5")
                        + SWEEP)
    return scene, tmp / "m.h5", remeasure_h5


def path_csv(tmp):
    shutil.copy(os.path.join(CONFIGS, "path_table.csv"), tmp / "c.csv")
    text = open(os.path.join(CONFIGS, "path_table.yaml")).read()
    scene = write_scene(tmp / "s.yaml",
                        text.replace("path_table.csv", "c.csv").replace(
                            "dt: 0.005", "dt: 0.002") + SWEEP)
    return scene, tmp / "c.csv", remeasure_csv


# every file key of the key table, with a scene that reads a file by it
# (CSV and HDF5 for the kind table: both readers)
SCENES = {"trajectory.table.file": table_csv,
          "trajectory.table.file (HDF5)": table_h5,
          "trajectory.path.file": path_csv}


def file_keys():
    """The keys of type "file name" of `rps3-run --keys`."""
    out = subprocess.run([RUNNER, "--keys"], capture_output=True, text=True,
                         check=True).stdout
    return {line.split("`")[1] for line in out.splitlines()
            if line.startswith("| `") and "| file name |" in line}


#: file keys of scenes that are never sharded: identify.data (a fit of
#: measured data has no Monte Carlo to shard; its input_files record is
#: tested in test_ident_runner.py)
UNSHARDED = {"identify.data"}


def test_every_file_key_is_tested(runner):
    assert file_keys() - UNSHARDED == {k.split(" ")[0] for k in SCENES}


def record(path):
    """The file's input_files, the same on the root and on scene_resolved
    (what a case rerun alone read)."""
    with h5py.File(path, "r") as f:
        v = [f.attrs["input_files"], f["scene_resolved"].attrs["input_files"]]
    v = [x.decode() if isinstance(x, bytes) else x for x in v]
    assert v[0] == v[1]
    return v[0]


def sha256(path):
    return hashlib.sha256(open(path, "rb").read()).hexdigest()


def merge(out, *parts, cwd=None):
    return subprocess.run([RUNNER, "merge", str(out), *map(str, parts)],
                          capture_output=True, text=True, timeout=120,
                          cwd=cwd)


@pytest.mark.parametrize("which", list(SCENES))
def test_table_changed_between_shards(runner, tmp_path, which):
    scene, table, remeasure = SCENES[which](tmp_path)
    key = which.split(" ")[0]
    p0, p1 = tmp_path / "p0.h5", tmp_path / "p1.h5"
    assert run(scene, p0, "-q", "--shard", "0/2").returncode == 0
    old = sha256(table)
    # the record: the file's SHA-256 (hashlib's, not the runner's) by key
    assert record(p0) == f"{key} sha256:{old} {table}\n"
    remeasure(table, 1e-4)
    new = sha256(table)
    assert new != old
    assert run(scene, p1, "-q", "--shard", "1/2").returncode == 0
    assert record(p1) == f"{key} sha256:{new} {table}\n"

    # merge: refused, by virtual datasets and by copy, nothing written
    for extra in ([], ["--copy"]):
        proc = merge(tmp_path / "merged.h5", *extra, p1, p0)
        assert proc.returncode == 2, proc.stderr
        err = proc.stderr
        assert f"{key} {table}: the parts were computed from different " \
               "contents of it" in err, err
        assert f"SHA-256 {old[:16]}...: {p0}\n" in err, err
        assert f"SHA-256 {new[:16]}...: {p1}\n" in err, err
        assert f"the file now: SHA-256 {new[:16]}..." in err, err
        # the stale part is the one to compute again
        assert "1 of 2 shards to run again: 0\n" in err, err
        assert not (tmp_path / "merged.h5").exists()
        assert not [x for x in os.listdir(tmp_path) if ".tmp." in x]

    # --resume computes the stale part again, keeps the current one
    kept = p1.stat().st_mtime_ns
    proc = run(scene, p1, "--shard", "1/2", "--resume")
    assert proc.returncode == 0, proc.stderr
    assert "not run again" in proc.stderr and p1.stat().st_mtime_ns == kept
    proc = run(scene, p0, "--shard", "0/2", "--resume")
    assert proc.returncode == 0, proc.stderr
    assert f"{p0} read {key} {table} of SHA-256 {old[:16]}..., the file " \
           f"now has SHA-256 {new[:16]}...: computed from another content " \
           "of that file: running shard 0/2 again" in proc.stderr
    assert record(p0) == record(p1)
    proc = merge(tmp_path / "merged.h5", p0, p1)
    assert proc.returncode == 0, proc.stderr
    whole = tmp_path / "whole.h5"
    assert run(scene, whole, "-q").returncode == 0
    assert record(whole) == record(tmp_path / "merged.h5")
    assert_same_content(whole, tmp_path / "merged.h5")


def test_table_changed_and_changed_back_keeps_the_part(runner, tmp_path):
    """The content decides, not the file's time: a part of the same bytes
    is kept."""
    scene, table, remeasure = table_csv(tmp_path)
    p0 = tmp_path / "p0.h5"
    assert run(scene, p0, "-q", "--shard", "0/2").returncode == 0
    before = p0.stat().st_mtime_ns
    orig = table.read_bytes()
    remeasure(table, 1e-4)
    os.utime(table)
    table.write_bytes(orig)
    proc = run(scene, p0, "--shard", "0/2", "--resume")
    assert proc.returncode == 0, proc.stderr
    assert "complete (6 cases, 0 failed): not run again" in proc.stderr
    assert p0.stat().st_mtime_ns == before
    # the table moved elsewhere, same content: the same data
    moved = tmp_path / "sub"
    moved.mkdir()
    shutil.move(table, moved / table.name)
    shutil.move(scene, moved / scene.name)
    proc = run(moved / scene.name, p0, "--shard", "0/2", "--resume")
    assert proc.returncode == 0 and "not run again" in proc.stderr


def test_a_part_without_record_is_not_trusted(runner, tmp_path):
    """A part that does not say what it read (written before records were
    kept, or tampered with): merge refuses it, --resume computes it again."""
    scene, table, _ = table_csv(tmp_path)
    p = [tmp_path / f"p{k}.h5" for k in range(2)]
    for k in range(2):
        assert run(scene, p[k], "-q", "--shard", f"{k}/2").returncode == 0
    with h5py.File(p[1], "r+") as f:
        del f.attrs["input_files"]
    proc = merge(tmp_path / "merged.h5", *p)
    assert proc.returncode == 2, proc.stderr
    assert f"(not recorded): {p[1]}\n" in proc.stderr
    assert not (tmp_path / "merged.h5").exists()
    proc = run(scene, p[1], "--shard", "1/2", "--resume")
    assert proc.returncode == 0, proc.stderr
    assert "of unknown content (not recorded), the file now has SHA-256" \
        in proc.stderr, proc.stderr
    assert merge(tmp_path / "merged.h5", *p).returncode == 0
    # a record of one more file than the scene reads: not this run's data
    with h5py.File(p[0], "r+") as f:
        f.attrs["input_files"] = record(p[0]) + \
            f"trajectory.path.file sha256:{'0' * 64} {table}\n"
    proc = merge(tmp_path / "m2.h5", *p)
    assert proc.returncode == 2, proc.stderr
    assert f"no such file read: {p[1]}\n" in proc.stderr, proc.stderr
    assert not (tmp_path / "m2.h5").exists()


def failing_scene(tmp_path):
    """30 cases over 10 jobs of 3; the amp[2] = 0.2 cases fail (the platform
    below the base), and no other."""
    text = FAILING_SINE.replace("SAMPLES", "4001").replace(
        "THETA", "closed_form").replace(
        "  trajectory.amp[2]: [0.05, 0.2, 0.1]",
        "  trajectory.amp[2]: [0.05, 0.2, 0.1]\n"
        "  manipulator.M: [0.1, 0.12, 0.14, 0.16, 0.18, 0.2, 0.22, 0.24, "
        "0.26, 0.28]")
    return write_scene(tmp_path / "fail.yaml", text)


def test_failed_cases_are_the_shards_own(runner, tmp_path):
    """The summary of a part, of --resume of a complete part and of merge
    counts the cases it holds: a rerun of a finished, all-ok shard (a Slurm
    array run again) exits 0 and says so."""
    scene = failing_scene(tmp_path)
    whole = tmp_path / "whole.h5"
    assert run(scene, whole, "-q").returncode == 1
    with h5py.File(whole, "r") as f:
        status = f["status"][()]
        chunk = f["status"].chunks[0]
    nshard = 5
    shard_of = (np.arange(len(status)) // chunk) % nshard
    parts = []
    for k in range(nshard):
        mine = shard_of == k
        ncase, nfail = int(mine.sum()), int((status[mine] != 0).sum())
        p = tmp_path / f"p{k}.h5"
        parts.append(p)
        proc = run(scene, p, "--shard", f"{k}/{nshard}")
        assert proc.returncode == (1 if nfail else 0), proc.stderr
        assert f"rps3-run: {ncase}/{ncase} cases ({nfail} failed)" \
            in proc.stderr, proc.stderr
        with h5py.File(p, "r") as f:
            s = f["status"][()]
        assert (s[~mine] == NOT_COMPUTED).all() and (s[mine] >= 0).all()
        proc = run(scene, p, "--shard", f"{k}/{nshard}", "--resume")
        assert proc.returncode == (1 if nfail else 0), proc.stderr
        assert f"complete ({ncase} cases, {nfail} failed): not run again" \
            in proc.stderr, proc.stderr
    # the scene has all-ok shards and shards with failures
    assert {int((status[shard_of == k] != 0).any()) for k in
            range(nshard)} == {0, 1}
    proc = merge(tmp_path / "merged.h5", *parts)
    assert proc.returncode == 1, proc.stderr
    assert f"({int((status != 0).sum())} failed cases)" in proc.stderr
    proc = merge(tmp_path / "merged.h5", "--failed-ok", *parts)
    assert proc.returncode == 0, proc.stderr


@pytest.mark.skipif(not MPIRUN, reason="no mpirun")
def test_mpi_ranks_record_the_tables(runner, tmp_path):
    """Under mpirun every rank's part records the table; the joined and
    the copied file keep the record, equal to a one-process run's."""
    scene, table, _ = table_h5(tmp_path)
    want = f"trajectory.table.file sha256:{sha256(table)} {table}\n"
    for extra in ([], ["--copy"]):
        out = tmp_path / f"mpi{len(extra)}.h5"
        proc = mpirun(2, RUNNER_MPI, scene, "-o", out, "-q", *extra)
        assert proc.returncode == 0, proc.stderr
        assert record(out) == want
    assert record(tmp_path / "mpi0.h5.part1of2") == want


@pytest.fixture(scope="module")
def swap_shim(tmp_path_factory):
    """tests/swap_shim.c built as a shared library (LD_PRELOAD)."""
    so = tmp_path_factory.mktemp("shim") / "libswap_shim.so"
    subprocess.run(["cc", "-shared", "-fPIC", "-O1", "-Wall", "-Werror",
                    os.path.join(ROOT, "tests", "swap_shim.c"), "-o", str(so),
                    "-ldl"], check=True)
    return so


@pytest.mark.parametrize("which", list(SCENES))
def test_table_rewritten_while_read_is_refused(runner, swap_shim, tmp_path,
                                               which):
    """The table replaced by another content between the scene's read and
    its digest (the CSV reader opens it first, the digest second; the HDF5
    reader opens it through HDF5, the digest first): the digest would be of
    data the run did not use, so the run stops (exit 3) and writes
    nothing."""
    scene, table, remeasure = SCENES[which](tmp_path)
    key = which.split(" ")[0]
    new = tmp_path / ("new" + table.suffix)
    shutil.copy(table, new)
    remeasure(new, 1e-4)
    out = tmp_path / "p0.h5"
    env = dict(os.environ, LD_PRELOAD=str(swap_shim), SWAP_NAME=table.name,
               SWAP_WITH=str(new), SWAP_AT="1" if table.suffix == ".h5"
               else "2")
    proc = subprocess.run([RUNNER, str(scene), "-o", str(out), "-q",
                           "--shard", "0/2"], capture_output=True, text=True,
                          timeout=60, env=env)
    assert not new.exists()                     # the swap took place
    assert proc.returncode == 3, proc.stderr
    assert f"{key}: {table} changed while this run read it" in proc.stderr
    assert not out.exists()
    assert not [x for x in os.listdir(tmp_path) if ".tmp." in x]
    # the file as it is now is read and recorded as such
    assert run(scene, out, "-q", "--shard", "0/2").returncode == 0
    assert record(out) == f"{key} sha256:{sha256(table)} {table}\n"
