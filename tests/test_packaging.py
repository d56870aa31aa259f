"""The Python package as users install it (python/README.md, "Installing"):

- the sdist of `python -m build` carries the library's C sources and header,
  byte for byte the tree's;
- a wheel built from that sdist alone (pip's isolated build, in a fresh
  virtual environment outside the tree) installs there, and the package's
  tests (tests/test_python.py: the runner's files bit for bit, the golden
  answers, ...) pass against that installed copy, not the tree's;
- the same sdist built against an installed librps3 (RPS3_PREFIX, after
  `make install`) links that library and gives the same numbers;
- a missing build dependency (gsl-config, a C compiler, cffi, the library
  under RPS3_PREFIX) stops the build with one line naming what to install,
  not a traceback.

The fresh environment takes its packages from pip's cache or the index,
pinned by analysis/requirements.txt and tests/requirements.txt (a minute
or two, most of it compiling the library's sources into the wheel).
"""

import os
import re
import subprocess
import sys
import tarfile
import zipfile

import pytest
from conftest import ROOT

PY = os.path.join(ROOT, "python")
PINS = [os.path.join(ROOT, "analysis", "requirements.txt"),
        os.path.join(ROOT, "tests", "requirements.txt")]


def clean_env(**extra):
    """The environment without the calling make's jobserver and without
    anything that would put the tree's package on the path."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("MAKEFLAGS", "MFLAGS", "MAKELEVEL", "MAKEOVERRIDES",
                        "PYTHONPATH", "RPS3_PREFIX", "VIRTUAL_ENV")}
    env.update(extra)
    return env


def sh(cmd, timeout=900, **kw):
    kw.setdefault("env", clean_env())
    proc = subprocess.run([str(c) for c in cmd], capture_output=True, text=True,
                          timeout=timeout, **kw)
    assert proc.returncode == 0, f"{cmd}\n{proc.stdout[-4000:]}\n{proc.stderr[-4000:]}"
    return proc.stdout


def header_version():
    text = open(os.path.join(ROOT, "include", "rps3.h")).read()
    return re.search(r'#define RPS3_VERSION_STRING "([^"]+)"', text).group(1)


def dynamic(path):
    """(NEEDED libraries, RPATH/RUNPATH directories) of an ELF file."""
    out = sh(["readelf", "-d", path])
    needed = re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", out)
    paths = re.findall(r"\((?:RPATH|RUNPATH)\)\s+Library r\w*path: \[([^\]]+)\]", out)
    return needed, ":".join(paths).split(":") if paths else []


@pytest.fixture(scope="module")
def sdist(tmp_path_factory):
    """`python -m build --sdist` of python/ (the venv's setuptools and cffi,
    which are the pinned ones of pyproject.toml)."""
    out = tmp_path_factory.mktemp("dist")
    sh([sys.executable, "-m", "build", "--sdist", "--no-isolation",
        "--outdir", out, PY])
    (tar,) = out.glob("rps3-*.tar.gz")
    return tar


@pytest.fixture(scope="module")
def fresh(tmp_path_factory, sdist):
    """A fresh virtual environment outside the tree with the wheel built
    from the sdist alone installed, and the packages the package's tests
    use: (its python, its directory, the wheel)."""
    top = tmp_path_factory.mktemp("fresh")
    venv = top / "venv"
    sh([sys.executable, "-m", "venv", venv])
    vpy = venv / "bin" / "python"
    pip = [vpy, "-m", "pip", "--disable-pip-version-check"]
    # pip's isolated build from the sdist alone: setuptools and cffi of
    # pyproject.toml from the index, the library's sources from csrc/
    sh([*pip, "wheel", "--no-deps", "-w", top / "wheels", sdist], cwd=top)
    (wheel,) = (top / "wheels").glob("rps3-*.whl")
    # what the figures need (analysis/requirements.txt) and pytest, at
    # their pins; the package's own dependencies come with the wheel
    constraints = [a for p in PINS for a in ("-c", p)]
    sh([*pip, "install", wheel, "-r", PINS[0], "pytest", *constraints], cwd=top)
    return vpy, venv, wheel


def test_sdist_carries_the_library_sources(sdist):
    """csrc/src and csrc/include of the sdist are the tree's src/*.[ch] and
    include/rps3.h, byte for byte; the package's modules are there; nothing
    compiled is."""
    with tarfile.open(sdist) as tar:
        top = tar.getnames()[0].split("/")[0]
        files = {m.name[len(top) + 1:]: m for m in tar.getmembers() if m.isfile()}
        want = {f"csrc/src/{n}": os.path.join(ROOT, "src", n)
                for n in os.listdir(os.path.join(ROOT, "src")) if n.endswith((".c", ".h"))}
        want["csrc/include/rps3.h"] = os.path.join(ROOT, "include", "rps3.h")
        for name, path in want.items():
            assert name in files, name
            assert tar.extractfile(files[name]).read() == open(path, "rb").read(), name
        assert {n for n in files if n.startswith("csrc/")} == set(want) | {"csrc/LICENSE"}
    for name in os.listdir(os.path.join(PY, "rps3")):
        if name.endswith(".py"):
            assert f"rps3/{name}" in files, name
    assert not [n for n in files if n.endswith((".o", ".a", ".so"))]


def test_wheel_from_the_sdist_passes_the_tests_installed(fresh):
    """The wheel holds the extension with the library compiled in (no
    librps3 needed, no path into the tree); the fresh environment imports
    the installed copy; tests/test_python.py passes against it."""
    vpy, venv, wheel = fresh
    with zipfile.ZipFile(wheel) as z:
        names = z.namelist()
    assert [n for n in names if re.match(r"rps3/_rps3\..*\.so$", n)], names
    assert not [n for n in names if n.startswith("csrc/")]
    code = ("import rps3, rps3._rps3 as e; "
            "print(rps3.__file__); print(e.__file__); print(rps3.__version__)")
    pkg, ext, version = sh([vpy, "-c", code], cwd=venv).split()
    assert pkg.startswith(str(venv)) and ext.startswith(str(venv))
    assert version == header_version()
    needed, paths = dynamic(ext)
    assert not [n for n in needed if "rps3" in n], needed
    assert not [p for p in paths if p.startswith(ROOT)], paths
    # the tests of the package, from a directory outside the tree: only
    # tests/ (the tests and conftest.py) comes from the tree
    out = sh([vpy, "-m", "pytest", "-q", "-p", "no:cacheprovider",
              os.path.join(ROOT, "tests", "test_python.py")],
             cwd=venv, env=clean_env(MPLBACKEND="Agg"))
    assert re.search(r"\d+ passed", out) and "failed" not in out, out[-2000:]


def test_installed_library_route(fresh, sdist, tmp_path):
    """RPS3_PREFIX: the sdist built against a librps3 installed with `make
    install PREFIX=...` links that library (by its SONAME, found through
    the RUNPATH) and computes what the sdist's own build computes."""
    vpy, venv, _ = fresh
    prefix = tmp_path / "prefix"
    sh(["make", "-C", ROOT, "--no-print-directory", "install", f"PREFIX={prefix}"])
    target = tmp_path / "site"
    sh([vpy, "-m", "pip", "--disable-pip-version-check", "install", "--no-deps",
        "--target", target, sdist], cwd=tmp_path,
       env=clean_env(RPS3_PREFIX=str(prefix)))
    (ext,) = (target / "rps3").glob("_rps3.*.so")
    needed, paths = dynamic(ext)
    assert f"librps3.so.{header_version().split('.')[0]}" in needed
    assert str(prefix / "lib") in paths
    code = ("import rps3, numpy as np; m = rps3.Model(m_over_M=0.5); "
            "t = rps3.trajectory.helix(samples=101, model=m); "
            "f = m.inverse(t.pose, t.dpose, t.ddpose).force; "
            "print(rps3._rps3.__file__); print(f.tobytes().hex())")
    linked = sh([vpy, "-c", code], cwd=tmp_path,
                env=clean_env(PYTHONPATH=str(target))).split()
    own = sh([vpy, "-c", code], cwd=tmp_path).split()
    assert linked[0].startswith(str(target)) and own[0].startswith(str(venv))
    assert linked[1] == own[1]


# --------------------------------------------------- missing dependencies

def build_fails(tmp_path, env, *pip_args):
    """pip wheel of python/ without build isolation (the venv's setuptools
    and cffi) under `env`: it must fail; its output."""
    proc = subprocess.run(
        [sys.executable, "-m", "pip", "--disable-pip-version-check", "wheel",
         "--no-build-isolation", "--no-deps", "-w", str(tmp_path / "w"), *pip_args, PY],
        capture_output=True, text=True, timeout=300, env=env, cwd=tmp_path)
    assert proc.returncode != 0
    out = proc.stdout + proc.stderr
    # one line from the build, no traceback of it
    assert "Traceback" not in out and "FileNotFoundError" not in out, out
    return out


def path_with(tmp_path, *tools):
    """A directory holding only the named tools (links), for PATH."""
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir(exist_ok=True)
    for tool in tools:
        found = subprocess.run(["sh", "-c", f"command -v {tool}"],
                               capture_output=True, text=True).stdout.strip()
        assert found, tool
        (bin_dir / tool).symlink_to(found)
    return str(bin_dir)


def compiler():
    import sysconfig
    return (os.environ.get("CC") or sysconfig.get_config_var("CC") or "cc").split()[0]


def test_no_gsl_config_names_what_to_install(tmp_path):
    out = build_fails(tmp_path, clean_env(PATH=path_with(tmp_path, compiler())))
    assert "rps3: cannot build the extension: gsl-config is not on PATH" in out
    assert "apt-get install libgsl-dev" in out and "GSL's development files" in out


def test_no_compiler_names_what_to_install(tmp_path):
    out = build_fails(tmp_path, clean_env(PATH=path_with(tmp_path, "gsl-config")))
    assert f"rps3: cannot build the extension: no C compiler: {compiler()!r}" in out
    assert "apt-get install gcc" in out


def test_no_cffi_names_what_to_install(tmp_path):
    """Without build isolation and without cffi, setuptools would drop
    cffi_modules with a warning and build a package without extension."""
    hidden = tmp_path / "hide" / "cffi"
    hidden.mkdir(parents=True)
    (hidden / "__init__.py").write_text("raise ImportError('no cffi here')\n")
    out = build_fails(tmp_path, clean_env(PYTHONPATH=str(hidden.parent)))
    assert "rps3: cannot build the extension: cffi is missing" in out


def test_rps3_prefix_without_the_library(tmp_path):
    out = build_fails(tmp_path, clean_env(RPS3_PREFIX=str(tmp_path / "none")))
    assert f"RPS3_PREFIX={tmp_path / 'none'}: {tmp_path / 'none'}/include/rps3.h " \
           "is missing" in out


def test_gsl_headers_not_found_names_what_to_install(tmp_path):
    """gsl-config there, but the compiler does not find GSL's headers (a
    compiler of another system root)."""
    cc = f"{compiler()} --sysroot={tmp_path / 'elsewhere'}"
    out = build_fails(tmp_path, clean_env(CC=cc))
    assert "rps3: cannot build the extension: GSL's headers are not found" in out
    assert "apt-get install libgsl-dev" in out


def test_no_python_headers_names_what_to_install(tmp_path):
    """Python.h missing where sysconfig says Python's headers are."""
    code = ("import runpy, sysconfig; p = sysconfig.get_paths(); "
            f"sysconfig.get_paths = lambda *a, **k: {{**p, 'include': {str(tmp_path)!r}}}; "
            f"runpy.run_path({os.path.join(PY, 'rps3', '_build.py')!r})")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True,
                          text=True, timeout=120, env=clean_env())
    assert proc.returncode == 1
    assert proc.stderr.strip() == (
        f"rps3: cannot build the extension: Python's headers are missing "
        f"({tmp_path}/Python.h): install them (Debian, Ubuntu: apt-get install "
        "python3-dev; Fedora: dnf install python3-devel)")
