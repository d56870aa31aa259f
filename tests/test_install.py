"""`make install` / `make uninstall`, and programs outside the tree built
against the installed library through pkg-config and through CMake.

The library is installed twice: directly into a temporary PREFIX (as
`make install PREFIX=/usr/local` would, the pkg-config build) and staged
with DESTDIR (the CMake package finds its files from its own place).  Both
programs must print what the same source prints when built in the tree.
"""

import os
import re
import shutil
import subprocess

import pytest

from conftest import ROOT

CONSUMER = os.path.join(ROOT, "tests", "install")
HEADER = os.path.join(ROOT, "include", "rps3.h")


def header_version():
    """(VERSION_STRING, MAJOR) read from include/rps3.h."""
    text = open(HEADER).read()
    version = re.search(r'#define RPS3_VERSION_STRING "([^"]+)"', text).group(1)
    return version, version.split(".")[0]


def clean_env(**extra):
    """The environment without the calling make's jobserver variables."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("MAKEFLAGS", "MFLAGS", "MAKELEVEL", "MAKEOVERRIDES")}
    env.update(extra)
    return env


def sh(cmd, **kw):
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=300,
                          **kw)
    assert proc.returncode == 0, f"{cmd}\n{proc.stdout}\n{proc.stderr}"
    return proc.stdout


def make(*args):
    return sh(["make", "-C", ROOT, "--no-print-directory", *args],
              env=clean_env())


def needed(path):
    """DT_NEEDED entries of an ELF file."""
    out = sh(["readelf", "-d", str(path)])
    return re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", out)


def soname(path):
    out = sh(["readelf", "-d", str(path)])
    m = re.search(r"\(SONAME\)\s+Library soname: \[([^\]]+)\]", out)
    return m.group(1) if m else None


@pytest.fixture(scope="module")
def in_tree_output(tmp_path_factory):
    """What consumer.c prints when built in the tree (static library)."""
    exe = tmp_path_factory.mktemp("intree") / "consumer"
    gsl = sh(["gsl-config", "--libs"]).split()
    sh(["cc", "-std=c99", "-Wall", "-Werror", "-I", os.path.join(ROOT, "include"),
        os.path.join(CONSUMER, "consumer.c"), "-o", str(exe),
        os.path.join(ROOT, "build", "librps3.a"), *gsl])
    return sh([str(exe)])


@pytest.fixture(scope="module")
def prefix(tmp_path_factory):
    """rps3 installed with `make install PREFIX=...` (no DESTDIR)."""
    pre = tmp_path_factory.mktemp("prefix") / "usr-local"
    make("install", f"PREFIX={pre}")
    return pre


def test_installed_files_and_links(prefix):
    version, major = header_version()
    lib = prefix / "lib"
    for rel in ("include/rps3.h", "lib/librps3.a", "lib/pkgconfig/rps3.pc",
                "lib/cmake/rps3/rps3-config.cmake",
                "lib/cmake/rps3/rps3-config-version.cmake",
                "bin/rps3-run", "bin/rps3-study", "bin/rps3-simstudy",
                "share/doc/rps3/LICENSE"):
        assert (prefix / rel).is_file(), rel
    # the SONAME carries the major version; the links lead to the file
    assert os.readlink(lib / "librps3.so") == f"librps3.so.{major}"
    assert os.readlink(lib / f"librps3.so.{major}") == f"librps3.so.{version}"
    assert not (lib / f"librps3.so.{version}").is_symlink()
    assert soname(lib / f"librps3.so.{version}") == f"librps3.so.{major}"
    assert os.access(prefix / "bin" / "rps3-run", os.X_OK)
    pc = (lib / "pkgconfig" / "rps3.pc").read_text()
    assert f"Version: {version}" in pc
    assert "Requires.private: gsl" in pc
    # the installed header is the tree's
    assert (prefix / "include" / "rps3.h").read_text() == open(HEADER).read()


def test_every_installed_program_has_its_man_page(prefix):
    """share/man/man1/PROG.1 for each program in bin/, readable by man."""
    progs = sorted(os.listdir(prefix / "bin"))
    assert {"rps3-run", "rps3-study", "rps3-simstudy"} <= set(progs)
    man1 = prefix / "share" / "man" / "man1"
    assert sorted(p[:-2] for p in os.listdir(man1)) == progs
    for p in progs:
        page = (man1 / f"{p}.1").read_text()
        assert f".TH {p.upper()} 1 " in page
        assert f"\\fB\\-\\-help\\fR" in page
    if shutil.which("man"):
        out = sh(["man", "-M", str(prefix / "share" / "man"), "rps3-run"],
                 env=clean_env(MANPAGER="cat", PAGER="cat", MANWIDTH="80"))
        assert "rps3-run - run the scenes" in out and "--gzip" in out


def test_installed_runner_runs(prefix, tmp_path):
    out = tmp_path / "paper.h5"
    sh([str(prefix / "bin" / "rps3-run"),
        os.path.join(ROOT, "configs", "paper.yaml"), "-o", str(out), "-q"])
    assert out.stat().st_size > 0


def test_pkg_config_build(prefix, tmp_path, in_tree_output):
    """cc consumer.c $(pkg-config --cflags --libs rps3), run it."""
    env = clean_env(PKG_CONFIG_PATH=str(prefix / "lib" / "pkgconfig"))
    flags = sh(["pkg-config", "--cflags", "--libs", "rps3"], env=env).split()
    assert f"-L{prefix}/lib" in flags and "-lrps3" in flags
    exe = tmp_path / "consumer"
    sh(["cc", "-std=c99", "-Wall", "-Werror",
        os.path.join(CONSUMER, "consumer.c"), "-o", str(exe), *flags])
    # linked by SONAME to the shared library, found where it was installed
    assert f"librps3.so.{header_version()[1]}" in needed(exe)
    out = sh([str(exe)], env=clean_env(LD_LIBRARY_PATH=str(prefix / "lib")))
    assert out == in_tree_output
    # a static link through pkg-config pulls GSL in (Requires.private)
    static = sh(["pkg-config", "--static", "--libs", "rps3"], env=env).split()
    assert "-lgsl" in static


def test_cmake_build_from_staged_install(tmp_path, in_tree_output):
    """find_package(rps3) -> rps3::rps3 from a DESTDIR-staged install."""
    if shutil.which("cmake") is None:
        pytest.fail("cmake is missing: `make check` installs it")
    version, _ = header_version()
    stage = tmp_path / "stage"
    make("install", f"DESTDIR={stage}", "PREFIX=/opt/rps3")
    pre = stage / "opt" / "rps3"
    build = tmp_path / "build"
    want = ".".join(version.split(".")[:2])
    sh(["cmake", "-S", CONSUMER, "-B", str(build), f"-DRPS3_WANT={want}",
        f"-DCMAKE_PREFIX_PATH={pre}"], env=clean_env())
    sh(["cmake", "--build", str(build)], env=clean_env())
    exe = build / "consumer"
    assert f"librps3.so.{version.split('.')[0]}" in needed(exe)
    out = sh([str(exe)], env=clean_env(LD_LIBRARY_PATH=str(pre / "lib")))
    assert out == in_tree_output
    # a major version the installation does not have is refused
    bad = subprocess.run(
        ["cmake", "-S", CONSUMER, "-B", str(tmp_path / "bad"),
         f"-DRPS3_WANT={int(version.split('.')[0]) + 1}.0",
         f"-DCMAKE_PREFIX_PATH={pre}"],
        capture_output=True, text=True, env=clean_env(), timeout=120)
    assert bad.returncode != 0
    assert "rps3" in bad.stderr


def test_uninstall_removes_everything(tmp_path):
    pre = tmp_path / "prefix"
    make("install", f"PREFIX={pre}")
    make("uninstall", f"PREFIX={pre}")
    left = [p for p in pre.rglob("*") if not p.is_dir()]
    assert left == []
