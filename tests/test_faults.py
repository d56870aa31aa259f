"""The runner under faults: full disk, file size limits, signals, bad -o
targets, closed standard streams, stale temporaries, fsync, strict options.
rps3-run (-j 1, -j 2, merge), rps3-run-mpi and rps3-study alike: nothing
lost, nothing left that looks like an output, no crash."""

import contextlib
import os
import resource
import shutil
import signal
import stat
import subprocess
import sys
import time

import h5py
import numpy as np
import pytest

from conftest import CONFIGS, RUNNER, run, write_scene, run_tmp

ROOT = os.path.dirname(RUNNER)
RUNNER_MPI = os.path.join(ROOT, "rps3-run-mpi")
STUDY = os.path.join(ROOT, "rps3-study")
SIMSTUDY = os.path.join(ROOT, "rps3-simstudy")
MPIRUN = shutil.which("mpirun")
PAPER = os.path.join(CONFIGS, "paper.yaml")

# a sweep of 100 cases x 1001 samples: about 33 MB uncompressed, and still
# more than 4 MB with --gzip 1 (the forces of a sine are not compressible
# to nothing)
SINE_SWEEP = """\
manipulator: {R: 0.2286, rho: 0.5, M: 0.18, m: 0.09, d: 0.1524}
trajectory:
  kind: sine
  mean: [0, 0.05, 0.15]
  amp: [0.1, 0, 0.05]
  freq: [0.5, 0, 0.5]
  duration: 2
  samples: 1001
sweep:
  trajectory.amp[2]: {from: 0.01, to: 0.05, num: 100}
"""


def long_scene(tmp_path, samples=20000):
    """Two cases long enough to be caught while running."""
    text = open(PAPER).read().replace("samples: 1001", f"samples: {samples}")
    return write_scene(tmp_path / "long.yaml", text)


def slow_scene(tmp_path):
    """A run a signal cannot miss: the paper's two cases at 10^5 samples
    with cold multiroot solves by finite differences (about 0.5 s of CPU,
    2.5 us a point), to be run with SLOW_FIELDS (5 MB, not 66).  The
    closed-form scene takes 20 ms, a window a loaded machine's scheduling
    can close between the temporary's appearance and the signal."""
    text = open(PAPER).read().replace("samples: 1001", "samples: 100000")
    text = text.replace("theta: closed_form",
                        "theta: multiroot\n  solver: hybrids\n"
                        "  warm_start: false")
    assert "warm_start: false" in text
    return write_scene(tmp_path / "long.yaml", text)


SLOW_FIELDS = ["--fields", "force"]


def mpirun(n, *args, timeout=120):
    cmd = [MPIRUN, "--oversubscribe", "-n", str(n)]
    if os.geteuid() == 0:
        cmd.insert(1, "--allow-run-as-root")
    return subprocess.run(cmd + [str(a) for a in args], capture_output=True,
                          text=True, timeout=timeout)


def names(d):
    return sorted(x.name for x in d.iterdir())


# --------------------------------------------------------------- full disk

@contextlib.contextmanager
def small_tmpfs(path, size):
    """A tmpfs of `size` at path (root only), unmounted afterwards."""
    if os.geteuid() != 0:
        pytest.skip("mounting a small tmpfs needs root: the full-disk test "
                    "runs as root (make check in the container) only")
    path.mkdir()
    proc = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}",
                           "tmpfs", str(path)], capture_output=True, text=True)
    if proc.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {proc.stderr.strip()}")
    try:
        yield path
    finally:
        subprocess.run(["umount", "-l", str(path)], check=True)


@pytest.mark.parametrize("how", ["-j1", "-j2", "mpi"])
def test_full_disk_exits_3_and_leaves_nothing(runner, tmp_path, how):
    """--gzip skips the free-space refusal (the compressed size is not
    known), so the disk fills during the run: HDF5's close then fails, and
    the process must still exit 3 (it died of SIGSEGV at exit before)."""
    scene = write_scene(tmp_path / "sweep.yaml", SINE_SWEEP)
    with small_tmpfs(tmp_path / "fs", "4m") as fs:
        out = fs / "out.h5"
        if how == "mpi":
            if MPIRUN is None:
                pytest.skip("mpirun (openmpi-bin) missing")
            proc = mpirun(2, RUNNER_MPI, scene, "-o", out, "-q", "--gzip", "1")
        else:
            proc = run(scene, out, "-q", "--gzip", "1", "-j", how[2:])
        assert proc.returncode == 3, proc.stderr
        assert "no space left on the device" in proc.stderr
        assert names(fs) == []


def test_full_disk_is_refused_before_the_run(runner, tmp_path):
    scene = write_scene(tmp_path / "sweep.yaml", SINE_SWEEP)
    with small_tmpfs(tmp_path / "fs", "4m") as fs:
        proc = run(scene, fs / "out.h5")
        assert proc.returncode == 2, proc.stderr
        assert "the output needs about 3" in proc.stderr
        assert "free: nothing written" in proc.stderr
        assert names(fs) == []


def test_study_on_a_full_disk(runner, tmp_path):
    with small_tmpfs(tmp_path / "fs", "1m") as fs:
        with open(fs / "filler", "wb") as f:
            with contextlib.suppress(OSError):
                while True:
                    f.write(b"\0" * 65536)
                    f.flush()
        proc = subprocess.run([STUDY, "workspace", "--quick", "-o",
                               fs / "ws.h5"], capture_output=True, text=True,
                              timeout=120)
        assert proc.returncode == 3, proc.stderr
        assert "no space left on the device" in proc.stderr
        assert names(fs) == ["filler"]


def test_an_output_larger_than_the_disk_is_refused(runner, tmp_path):
    """No root needed: one case of 2e9 samples needs ~700 GB."""
    text = open(PAPER).read().replace("samples: 1001", "samples: 2000000000")
    text = text.replace("manipulator.m_over_M: [0, 0.5]",
                        "manipulator.m_over_M: [0.5]")
    scene = write_scene(tmp_path / "huge.yaml", text)
    st = os.statvfs(tmp_path)
    if st.f_bavail * st.f_frsize > 600e9:
        pytest.skip("more than 600 GB free here")
    t0 = time.time()
    proc = run(scene, tmp_path / "huge.h5")
    assert proc.returncode == 2, proc.stderr
    assert "free: nothing written" in proc.stderr
    assert time.time() - t0 < 20
    assert names(tmp_path) == ["huge.yaml"]


def limit_file_size(nbytes):
    def set_limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (nbytes, nbytes))
    return set_limit


@pytest.mark.parametrize("threads", ["1", "2"])
def test_file_size_limit_exits_3(runner, tmp_path, threads):
    """ulimit -f: SIGXFSZ is ignored, the write fails with EFBIG."""
    proc = run(os.path.join(CONFIGS, "mass_ratio.yaml"), tmp_path / "x.h5",
               "-q", "-j", threads, preexec_fn=limit_file_size(1 << 20))
    assert proc.returncode == 3, proc.stderr
    assert "file too large" in proc.stderr
    assert names(tmp_path) == []


def test_study_file_size_limit_exits_3(runner, tmp_path):
    proc = subprocess.run([STUDY, "workspace", "--quick", "-o",
                           tmp_path / "ws.h5"], capture_output=True, text=True,
                          timeout=120, preexec_fn=limit_file_size(65536))
    assert proc.returncode == 3, proc.stderr
    assert "file too large" in proc.stderr
    assert names(tmp_path) == []


# ----------------------------------------------------------------- signals

def start(args, **kw):
    return subprocess.Popen([str(a) for a in args], stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, **kw)


def wait_for(path, timeout=20):
    deadline = time.time() + timeout
    while not path.exists() and time.time() < deadline:
        time.sleep(0.005)
    assert path.exists(), path


@pytest.mark.parametrize("sig", [signal.SIGHUP, signal.SIGINT,
                                 signal.SIGTERM])
def test_a_signal_ignored_at_start_stays_ignored(runner, tmp_path, sig):
    """nohup rps3-run ... &: the hangup must not end the run."""
    scene = long_scene(tmp_path, 5000)
    out = tmp_path / "out.h5"

    def ignore():
        signal.signal(sig, signal.SIG_IGN)
    p = start([RUNNER, scene, "-o", out, "-q"], preexec_fn=ignore)
    # Popen returns after the exec: the signal hits the runner itself
    while p.poll() is None:
        p.send_signal(sig)
        time.sleep(0.01)
    assert p.returncode == 0, p.stderr.read()
    assert names(tmp_path) == ["long.yaml", "out.h5"]
    with h5py.File(out, "r") as f:
        assert (f["status"][()] == 0).all()


@pytest.mark.parametrize("sig,code", [(signal.SIGHUP, -signal.SIGHUP),
                                      (signal.SIGUSR1, -signal.SIGUSR1),
                                      (signal.SIGUSR2, -signal.SIGUSR2),
                                      (signal.SIGALRM, -signal.SIGALRM),
                                      (signal.SIGQUIT, -signal.SIGQUIT),
                                      (signal.SIGPIPE, 3)])
def test_signals_remove_the_temporary(runner, tmp_path, sig, code):
    scene = slow_scene(tmp_path)
    out = tmp_path / "out.h5"

    def default():
        # as from a terminal: under `nohup make check` SIGHUP arrives
        # ignored, and an ignored signal stays ignored (test above)
        signal.signal(sig, signal.SIG_DFL)
    p = start([RUNNER, scene, "-o", out, "-q"] + SLOW_FIELDS,
              preexec_fn=default)
    wait_for(run_tmp(tmp_path / "out.h5", p.pid))
    p.send_signal(sig)
    p.wait(timeout=30)
    assert p.returncode == code
    assert names(tmp_path) == ["long.yaml"]


def test_sigxfsz_from_outside_is_ignored(runner, tmp_path):
    scene = slow_scene(tmp_path)
    p = start([RUNNER, scene, "-o", tmp_path / "out.h5", "-q"] + SLOW_FIELDS)
    wait_for(run_tmp(tmp_path / "out.h5", p.pid))
    p.send_signal(signal.SIGXFSZ)
    p.wait(timeout=30)
    assert p.returncode == 0
    assert names(tmp_path) == ["long.yaml", "out.h5"]


def test_closed_pipe_on_stderr(runner, tmp_path):
    """rps3-run ... 2>&1 | head -1: the reader is gone before the last
    line; the run still completes with its own exit code."""
    out = tmp_path / "out.h5"
    p = subprocess.Popen([RUNNER, PAPER, "-o", str(out)],
                         stderr=subprocess.PIPE, stdout=subprocess.DEVNULL)
    p.stderr.readline()
    p.stderr.close()
    assert p.wait(timeout=60) == 0
    assert names(tmp_path) == ["out.h5"]


def test_study_signal_removes_the_temporary(runner, tmp_path):
    # the full workspace grid: ~1 s computing, then ~9 MB to write
    p = start([STUDY, "workspace", "-o", tmp_path / "ws.h5"])
    wait_for(run_tmp(tmp_path / "ws.h5", p.pid), timeout=60)
    p.send_signal(signal.SIGTERM)
    p.wait(timeout=30)
    assert p.returncode == -signal.SIGTERM
    assert names(tmp_path) == []


def test_simstudy_signal_removes_the_temporary(runner, tmp_path):
    """rps3-simstudy writes under the runner's temporary name (tmpout.h):
    a signal that ends it leaves nothing."""
    p = start([SIMSTUDY, "--quick", "-o", tmp_path / "sim.h5"])
    wait_for(run_tmp(tmp_path / "sim.h5", p.pid), timeout=60)
    p.send_signal(signal.SIGTERM)
    p.wait(timeout=30)
    assert p.returncode == -signal.SIGTERM
    assert names(tmp_path) == []


def dead_pid():
    p = subprocess.Popen(["true"])
    p.wait()
    return p.pid


def test_stale_temporaries_are_reported(runner, tmp_path):
    out = tmp_path / "out.h5"
    pid = dead_pid()
    stale = tmp_path / f"out.h5.tmp.{pid}"
    stale.write_bytes(b"half a file")
    part = tmp_path / f"out.h5.tmp.{pid}.part1"
    part.write_bytes(b"half a part")
    live = tmp_path / f"out.h5.tmp.{os.getpid()}"  # this process runs
    live.write_bytes(b"in use")
    proc = run(PAPER, out)
    assert proc.returncode == 0, proc.stderr
    assert f"{stale} is the temporary file of process {pid}" in proc.stderr
    assert f"{part} is the temporary file" in proc.stderr
    assert str(live) not in proc.stderr
    # reported, not removed: the file may belong to another machine
    assert stale.exists() and part.exists()


# --------------------------------------------------------------- -o checks

def test_bad_output_targets_are_refused_before_computing(runner, tmp_path):
    scene = write_scene(tmp_path / "scene.yaml", open(PAPER).read())
    before = scene.read_text()
    (tmp_path / "dir").mkdir()
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    link = tmp_path / "link.h5"
    link.symlink_to(tmp_path / "target.h5")
    hard = tmp_path / "hard.yaml"
    os.link(scene, hard)
    cases = {"": "needs a file name",
             str(tmp_path / "dir") + "/": "names a directory",
             str(tmp_path / "dir"): "is a directory",
             str(tmp_path / "new") + "/x.h5": "No such file or directory",
             str(fifo): "is a FIFO",
             str(link): "is a symbolic link",
             "/dev/null": "is a character device",
             str(scene): "is the input",
             str(hard): "is the input"}
    for out, why in cases.items():
        for extra in ([], ["-j", "2"]):
            t0 = time.time()
            proc = subprocess.run([RUNNER, str(scene), "-o", out] + extra,
                                  capture_output=True, text=True, timeout=60)
            assert proc.returncode == 2, (out, proc.stderr)
            assert why in proc.stderr, (out, proc.stderr)
            assert time.time() - t0 < 5
    assert scene.read_text() == before
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    assert os.path.islink(link) and not (tmp_path / "target.h5").exists()
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)
    assert names(tmp_path) == ["dir", "fifo", "hard.yaml", "link.h5",
                               "scene.yaml"]


def test_bad_output_targets_of_merge_and_study(runner, tmp_path):
    scene = write_scene(tmp_path / "s.yaml", SINE_SWEEP.replace("num: 100", "num: 40"))
    a, b = tmp_path / "a.h5", tmp_path / "b.h5"
    assert run(scene, a, "-q", "--shard", "0/2").returncode == 0
    assert run(scene, b, "-q", "--shard", "1/2").returncode == 0
    proc = subprocess.run([RUNNER, "merge", str(b), str(a), str(b)],
                          capture_output=True, text=True)
    assert proc.returncode == 2 and "is the input" in proc.stderr
    proc = subprocess.run([RUNNER, "merge", str(tmp_path), str(a), str(b)],
                          capture_output=True, text=True)
    assert proc.returncode == 2 and "is a directory" in proc.stderr
    proc = subprocess.run([STUDY, "workspace", "--quick", "-o",
                           str(tmp_path) + "/"], capture_output=True, text=True)
    assert proc.returncode == 2 and "names a directory" in proc.stderr
    assert names(tmp_path) == ["a.h5", "b.h5", "s.yaml"]


def test_rename_is_preceded_by_fsync(runner, tmp_path):
    """The file, then (after the rename) its directory reach the disk."""
    strace = shutil.which("strace")
    if strace is None:
        pytest.skip("strace missing (the Makefile installs it)")
    out = tmp_path / "out.h5"
    proc = subprocess.run([strace, "-f", "-e", "trace=openat,fsync,rename",
                           RUNNER, PAPER, "-o", str(out), "-q"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    calls = [ln for ln in proc.stderr.splitlines()
             if "fsync(" in ln or "rename(" in ln or
             (str(tmp_path) in ln and "openat(" in ln)]
    text = "\n".join(calls)
    i_file = text.index("fsync(")
    i_rename = text.index("rename(")
    i_dir = text.index("fsync(", i_rename)
    assert i_file < i_rename < i_dir, text
    assert "O_DIRECTORY" in text


# --------------------------------------------------------- standard streams

def test_closed_standard_streams(runner, tmp_path, paper_h5):
    """2>&- (and 0, 1 closed): the output file must not get fd 2."""
    out = tmp_path / "out.h5"
    proc = subprocess.run(["sh", "-c", 'exec "$0" "$@" <&- >&- 2>&-', RUNNER,
                           PAPER, "-o", str(out)], timeout=60)
    assert proc.returncode == 0
    with h5py.File(out, "r") as f, h5py.File(paper_h5, "r") as g:
        np.testing.assert_array_equal(f["force"][()], g["force"][()])
        assert f["status"][()].tolist() == [0, 0]
    with open(out, "rb") as f:
        assert b"rps3-run:" not in f.read()


# ----------------------------------------------------------- strict options

@pytest.mark.parametrize("args", [
    ["--shard", "0/ -1"], ["--shard", "1/18446744073709551616"],
    ["--shard", "+0/2"],
    ["--shard", "0/2x"], ["--shard", "0x0/2"], ["--shard", "-0/2"],
    ["--shard", "2/2"], ["--shard", "0/0"], ["--shard", "0/"],
    ["-j", "2x"], ["-j", "+2"], ["-j", " 2"], ["-j", "0"], ["-j", ""],
    ["--gzip", "4 "], ["--gzip", "-1"], ["--gzip", "0x4"]])
def test_strict_numbers_on_the_command_line(runner, tmp_path, args):
    proc = run(PAPER, tmp_path / "x.h5", *args)
    assert proc.returncode == 2, (args, proc.stderr)
    assert args[0] in proc.stderr
    assert names(tmp_path) == []


def test_a_huge_shard_count_is_refused(runner, tmp_path):
    """--shard 1/18446744073709551615 (a job loop that wrapped around
    would start at job 0): N above the jobs is refused, with the job count."""
    scene = write_scene(tmp_path / "s.yaml",
                        SINE_SWEEP.replace("num: 100", "num: 40"))
    out = tmp_path / "p.h5"
    proc = run(scene, out, "-q", "--shard", "1/18446744073709551615")
    assert proc.returncode == 2, proc.stderr
    assert "the sweep has 3 work units (tiles of up to 14 cases)" in proc.stderr
    assert names(tmp_path) == ["s.yaml"]


@pytest.mark.parametrize("args", [
    ["accuracy", "--samples", "10abc"], ["accuracy", "--samples", "9"],
    ["accuracy", "--repeats", "1e3"], ["accuracy", "--repeats", "-1"],
    ["accuracy", "--samples"], ["workspace", "--quick", "--bogus"],
    ["bogus"]])
def test_study_strict_options(runner, tmp_path, args):
    proc = subprocess.run([STUDY] + args + ["-o", str(tmp_path / "s.h5")],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2, (args, proc.stderr)
    assert names(tmp_path) == []


def test_study_help_and_version(runner):
    for flag in ("--help", "-h"):
        proc = subprocess.run([STUDY, flag], capture_output=True, text=True)
        assert proc.returncode == 0
        assert "usage: rps3-study accuracy" in proc.stdout
        assert "--samples N" in proc.stdout
    proc = subprocess.run([STUDY, "--version"], capture_output=True, text=True)
    assert proc.returncode == 0 and proc.stdout.startswith("rps3-study (rps3) ")


# ------------------------------------------------------------ scene files

def refused(scene, *args):
    t0 = time.time()
    proc = run(scene, None, "--check", *args, timeout=30)
    assert proc.returncode == 2, proc.stderr
    assert time.time() - t0 < 5, "refusing a scene takes seconds at most"
    return proc.stderr.strip()


def test_scene_encodings_are_named(runner, tmp_path):
    text = open(PAPER).read()
    for enc, name in (("utf-16", "UTF-16 (little-endian)"),
                      ("utf-16-be", "UTF-16 (big-endian)"),
                      ("utf-32", "UTF-32 (little-endian)")):
        scene = tmp_path / f"{enc}.yaml"
        scene.write_bytes(text.encode(enc))
        assert refused(scene) == (f"{scene}: (file): is {name} text: save the "
                                  "scene as UTF-8 (e.g. iconv -f UTF-16 -t "
                                  "UTF-8)")


def test_invalid_utf8_and_nul_have_line_and_column(runner, tmp_path):
    lines = open(PAPER).read().split("\n")
    bad = list(lines)
    bad[17] += " # caf\xe9"            # Latin-1 e-acute on line 18
    scene = tmp_path / "latin1.yaml"
    scene.write_bytes("\n".join(bad).encode("latin-1"))
    col = len(lines[17]) + 7
    assert refused(scene).startswith(
        f"{scene}:18:{col}: (file): invalid UTF-8 (byte ")
    scene = tmp_path / "nul.yaml"
    data = "\n".join(lines).encode()
    at = data.index(b"rho")
    scene.write_bytes(data[:at] + b"\0" + data[at:])
    line = data[:at].count(b"\n") + 1
    col = at - data[:at].rfind(b"\n")
    assert refused(scene) == (f"{scene}:{line}:{col}: (file): a NUL byte "
                              f"(byte {at}): not a text file")
    # multi-byte characters count as one column, as libyaml counts them
    scene = tmp_path / "greek.yaml"
    scene.write_bytes("# \u03c1\u03c1\n".encode() + b"\xc3\x28\n")
    assert refused(scene).startswith(f"{scene}:2:1: (file): invalid UTF-8")


def test_non_regular_and_oversized_scenes(runner, tmp_path):
    fifo = tmp_path / "fifo.yaml"
    os.mkfifo(fifo)
    assert refused(fifo).endswith("is a FIFO: a scene is a regular file "
                                  "(YAML text)")
    assert refused("/dev/zero").endswith("is a character device: a scene is "
                                         "a regular file (YAML text)")
    assert refused(tmp_path).endswith("is a directory: a scene is a regular "
                                      "file (YAML text)")
    big = tmp_path / "big.yaml"
    big.write_text(open(PAPER).read() + "#" * (1 << 20) + "\n")
    assert "a scene is at most 1048576 bytes" in refused(big)


def test_deep_nesting_is_refused_at_once(runner, tmp_path):
    """100k nested [ took libyaml 30-58 s to reject (quadratic)."""
    scene = tmp_path / "deep.yaml"
    scene.write_text("[" * 100000 + "\n")
    assert refused(scene) == (f"{scene}:1:65: [0][0][0][0]...: nested more "
                              "than 64 levels deep: a scene needs 3")


def test_core_numeric_tags_are_accepted(runner, tmp_path):
    text = open(PAPER).read().replace("R: 0.2286", "R: !!float 0.2286")
    text = text.replace("samples: 1001", "samples: !!int 1001")
    assert text != open(PAPER).read()
    scene = write_scene(tmp_path / "tagged.yaml", text)
    proc = run(scene, None, "--check")
    assert proc.returncode == 0, proc.stderr


# ------------------------------------------------------------------ merge

def two_parts(tmp_path, *extra):
    scene = write_scene(tmp_path / "s.yaml",
                        SINE_SWEEP.replace("num: 100", "num: 40"))
    parts = [tmp_path / f"p{k}.h5" for k in range(2)]
    for k, p in enumerate(parts):
        proc = run(scene, p, "-q", "--shard", f"{k}/2", *extra)
        assert proc.returncode == 0, proc.stderr
    return parts


def damage_a_chunk(path, name="force"):
    """Flip bytes inside the first stored chunk of dataset `name`."""
    with h5py.File(path, "r") as f:
        ds = f[name]
        assert ds.fletcher32            # the runner checksums every chunk
        infos = [ds.id.get_chunk_info(i) for i in range(ds.id.get_num_chunks())]
    info = infos[0]
    with open(path, "r+b") as f:
        f.seek(info.byte_offset + info.size // 2)
        b = f.read(8)
        f.seek(info.byte_offset + info.size // 2)
        f.write(bytes(x ^ 0x5A for x in b))


# -j 2: the chunks are deflated and checksummed on the worker threads
@pytest.mark.parametrize("extra", [[], ["--gzip", "1"], ["-j", "2"],
                                   ["-j", "2", "--gzip", "1"]])
@pytest.mark.parametrize("copy", [[], ["--copy"]])
def test_merge_refuses_a_damaged_part(runner, tmp_path, extra, copy):
    parts = two_parts(tmp_path, *extra)
    damage_a_chunk(parts[1])
    out = tmp_path / "all.h5"
    proc = subprocess.run([RUNNER, "merge", str(out)] + [str(p) for p in parts]
                          + copy, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 3, proc.stderr
    # 40 cases in 3 jobs of 14, 14, 12 cases: part 1 holds rows 14-27
    assert f"{parts[1]}: dataset force is damaged at rows 14-27" in proc.stderr
    assert not out.exists()
    assert names(tmp_path) == ["p0.h5", "p1.h5", "s.yaml"]


def test_merge_refuses_parts_of_other_versions(runner, tmp_path):
    parts = two_parts(tmp_path)
    for attr in ("rps3_version", "gsl_version", "hdf5_version",
                 "yaml_version"):
        with h5py.File(parts[1], "r+") as f:
            keep = f.attrs[attr]
            f.attrs[attr] = "9.9.9"
        proc = subprocess.run([RUNNER, "merge", str(tmp_path / "all.h5")] +
                              [str(p) for p in parts], capture_output=True,
                              text=True, timeout=120)
        assert proc.returncode == 2, proc.stderr
        assert f"{parts[1]} has {attr} 9.9.9" in proc.stderr
        assert "parts written by different versions" in proc.stderr
        with h5py.File(parts[1], "r+") as f:
            f.attrs[attr] = keep
    assert names(tmp_path) == ["p0.h5", "p1.h5", "s.yaml"]


def test_not_computed_is_not_an_error_code(runner, tmp_path):
    """A case that failed with RPS3_EINVAL (-1) is a computed case: merge
    keeps it (exit 1); only -1000 means "not computed"."""
    parts = two_parts(tmp_path)
    with h5py.File(parts[0], "r") as f:
        assert (f["status"][14:28] == -1000).all()     # shard 1's cases
        assert f["status"].fillvalue == -1000
    with h5py.File(parts[1], "r+") as f:
        f["status"][16] = -1                           # RPS3_EINVAL
    for copy in ([], ["--copy"]):
        out = tmp_path / f"all{len(copy)}.h5"
        proc = subprocess.run([RUNNER, "merge", str(out)] +
                              [str(p) for p in parts] + copy,
                              capture_output=True, text=True, timeout=120)
        assert proc.returncode == 1, proc.stderr
        assert "(1 failed case)" in proc.stderr
        with h5py.File(out, "r") as f:
            assert f["status"][16] == -1
            assert (np.delete(f["status"][()], 16) == 0).all()


# ------------------------------------------------------------ sizes, words

def test_threads_are_capped_at_the_cores(runner, tmp_path, paper_h5):
    cores = os.cpu_count()
    proc = run(PAPER, tmp_path / "x.h5", "-q", "-j", "1024")
    assert proc.returncode == 0, proc.stderr
    assert (f"-j 1024 on {cores} core{'s' if cores > 1 else ''}: computing "
            f"on {cores} thread") in proc.stderr
    with h5py.File(tmp_path / "x.h5", "r") as f, h5py.File(paper_h5) as g:
        np.testing.assert_array_equal(f["force"][()], g["force"][()])


def paper_with(tmp_path, old, new):
    text = open(PAPER).read()
    assert old in text
    return write_scene(tmp_path / "s.yaml", text.replace(old, new))


SWEEP = "manipulator.m_over_M: [0, 0.5]"


@pytest.mark.parametrize("old,new,expect", [
    ("samples: 1001", "dt: 1e-12",
     ":18:7: trajectory.dt: case 0: dt = 1e-12 s over the span 10 s is "
     "1e+13 steps: at most 2147483646 samples per case"),
    (SWEEP, "manipulator.rho: {from: -1e308, to: 1e308, num: 3}",
     ":24:20: manipulator.rho: must be > 0, got -1e+308"),
    (SWEEP, "manipulator.rho: {from: -1e308, to: 1e308, step: 1e307}",
     "manipulator.rho.step: to - from overflows (-1e308 to 1e308)"),
    (SWEEP, "manipulator.m_over_M: {from: 0, to: 1, num: 1000000000}",
     "manipulator.m_over_M.num: 1000000000 values make the sweep more than "
     "10000000 cases"),
    (SWEEP, "manipulator.m_over_M: {from: 0, to: 1, num: 1000}\n"
            "  manipulator.rho: {from: 0.3, to: 0.9, num: 100000}",
     "manipulator.rho.num: 100000 values make the sweep more than 10000000 "
     "cases"),
    (SWEEP, "manipulator.m_over_M: {from: 0, to: 1, step: 1e-9}",
     "gives 1e+09 values: the sweep would have more than 10000000 cases"),
])
def test_absurd_scenes_answer_at_once_with_the_cause(runner, tmp_path, old,
                                                     new, expect):
    scene = paper_with(tmp_path, old, new)
    t0 = time.time()
    proc = subprocess.run([RUNNER, str(scene), "--check"], capture_output=True,
                          text=True, timeout=60,
                          preexec_fn=lambda: resource.setrlimit(
                              resource.RLIMIT_AS, (1 << 30, 1 << 30)))
    assert proc.returncode == 2, proc.stderr
    assert expect in proc.stderr, proc.stderr
    assert time.time() - t0 < 5
