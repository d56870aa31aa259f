"""GNU conventions of the programs' command lines: a usage error is one
line saying what is wrong and a "Try 'PROG --help'" line; --version is
name and version, copyright, licence and no-warranty lines (read against
LICENSE and the header); a number's range in --help is the one its error
names (both read from one option table); the run's summary counts work
units; the man pages list every option of --help; and a changed compiler
rebuilds the objects."""

import os
import re
import shutil
import subprocess

import pytest

from conftest import CONFIGS, ROOT, RUNNER

BUILD = os.path.dirname(RUNNER)
PROGS = ["rps3-run", "rps3-study", "rps3-simstudy"]
PAPER = os.path.join(CONFIGS, "paper.yaml")


def prog(name):
    path = os.path.join(BUILD, name)
    if not os.access(path, os.X_OK):
        pytest.fail(f"{path} is missing: run `make runner`")
    return path


def cli(name, *args, cwd=None):
    return subprocess.run([prog(name), *map(str, args)], capture_output=True,
                          text=True, timeout=120, cwd=cwd)


def header_version():
    text = open(os.path.join(ROOT, "include", "rps3.h")).read()
    return re.search(r'#define RPS3_VERSION_STRING "([^"]+)"', text).group(1)


def clean_env(**extra):
    env = {k: v for k, v in os.environ.items()
           if k not in ("MAKEFLAGS", "MFLAGS", "MAKELEVEL", "MAKEOVERRIDES")}
    env.update(extra)
    return env


# ------------------------------------------------------------ usage errors

USAGE_ERRORS = [
    ("rps3-run", [PAPER], "rps3-run", "missing -o OUT.h5"),
    ("rps3-run", ["-o", "x.h5"], "rps3-run", "missing the scene file"),
    ("rps3-run", [], "rps3-run", "missing the scene file"),
    ("rps3-run", [PAPER, PAPER, "-o", "x.h5"], "rps3-run",
     "one scene at a time"),
    ("rps3-run", [PAPER, "-o", "x.h5", "--bogus"], "rps3-run",
     "unknown option '--bogus'"),
    ("rps3-run", [PAPER, "-o", "x.h5", "-j"], "rps3-run", "-j needs a value"),
    ("rps3-run", [PAPER, "-o", "x.h5", "--gzip=10"], "rps3-run",
     "--gzip needs a whole number 0-9, got '10'"),
    ("rps3-run", [PAPER, "-o", "x.h5", "--shard", "3/2"], "rps3-run",
     "--shard needs K/N with 0 <= K < N, got '3/2'"),
    ("rps3-run", [PAPER, "-o", "x.h5", "--fields", "nonsense"], "rps3-run",
     "nonsense"),
    ("rps3-run", [PAPER, "-o", "x.h5", "--copy"], "rps3-run",
     "--copy is for rps3-run-mpi under mpirun and for merge"),
    ("rps3-run", [PAPER, "-o", "x.h5", "--resume"], "rps3-run",
     "--resume is for --shard K/N runs"),
    ("rps3-run", [os.path.join(CONFIGS, "closed_loop.yaml"), "-o", "x.h5",
                  "--fields", "force"], "rps3-run",
     "--fields selects variables of the inverse-dynamics file"),
    ("rps3-run", ["merge"], "rps3-run merge", "missing OUT.h5"),
    ("rps3-run", ["merge", "x.h5"], "rps3-run merge",
     "missing the part files"),
    ("rps3-run", ["merge", "x.h5", "--bogus"], "rps3-run merge",
     "unknown option '--bogus'"),
    ("rps3-run", ["--clean"], "rps3-run --clean", "missing OUT.h5"),
    ("rps3-run", ["--clean", "a.h5", "b.h5"], "rps3-run --clean",
     "one OUT.h5 at a time"),
    ("rps3-study", [], "rps3-study", "missing the study"),
    ("rps3-study", ["frobnicate", "-o", "x.h5"], "rps3-study",
     "unknown study 'frobnicate'"),
    ("rps3-study", ["accuracy"], "rps3-study", "missing -o OUT.h5"),
    ("rps3-study", ["accuracy", "-o", "x.h5", "--samples=9"], "rps3-study",
     "--samples needs a whole number 10-1000000, got '9'"),
    ("rps3-simstudy", [], "rps3-simstudy", "missing -o OUT.h5"),
    ("rps3-simstudy", ["-o", "x.h5", "extra"], "rps3-simstudy",
     "no operand expected, got 'extra'"),
]


@pytest.mark.parametrize("name,args,who,what", USAGE_ERRORS)
def test_usage_error_is_one_line_and_a_pointer(runner, tmp_path, name, args,
                                               who, what):
    p = cli(name, *args, cwd=tmp_path)
    assert p.returncode == 2, p.stderr
    lines = p.stderr.splitlines()
    # what is wrong, in one line, then where the rest is: never the whole
    # help, which hides the one line that matters
    assert len(lines) == 2, p.stderr
    assert lines[0].startswith(f"{who}: ") and what in lines[0], lines[0]
    helper = who.split()[0]
    assert lines[1] == f"Try '{helper} --help' for more information."
    assert p.stdout == ""
    assert os.listdir(tmp_path) == []
    # and the command it points to works
    assert cli(helper, "--help").returncode == 0


# ---------------------------------------------------------------- version

def licence_facts():
    """(year, holder, licence name) read from LICENSE."""
    text = open(os.path.join(ROOT, "LICENSE")).read()
    m = re.search(r"Copyright \(c\) (\d{4}), (.+)", text)
    assert m, "LICENSE has no copyright line"
    assert text.startswith("BSD 3-Clause License")
    return m.group(1), m.group(2).strip(), "BSD-3-Clause"


@pytest.mark.parametrize("name", PROGS)
def test_version_is_the_gnu_form(runner, name):
    p = cli(name, "--version")
    assert p.returncode == 0 and p.stderr == ""
    lines = p.stdout.splitlines()
    year, holder, licence = licence_facts()
    assert lines[0] == f"{name} (rps3) {header_version()}"
    assert lines[1] == f"Copyright (C) {year} {holder}."
    assert lines[2].startswith(f"License {licence} <https://")
    # the binary links GSL: its licence is named too
    assert any("GSL" in ln and "GPL" in ln for ln in lines)
    assert "This is free software: you are free to change and " \
        "redistribute it." in lines
    assert lines[-1] == "There is NO WARRANTY, to the extent permitted by " \
        "law."


# ------------------------------------------------- ranges from one table

def numeric_rows(help_text):
    """[(option, LO, HI)] from the --help rows "  -x, --name ARG  ..."
    followed by "ARG is a whole number LO-HI"."""
    rows, last = [], None
    for line in help_text.splitlines():
        m = re.match(r"  (?:-\w, )?(--[\w-]+) (\S+)", line)
        if m:
            last = m.groups()
            continue
        m = re.match(r" {24}(\S+) is a whole number (\d+)-(\d+)$", line)
        if m and last and m.group(1) == last[1]:
            rows.append((last[0], int(m.group(2)), int(m.group(3))))
    return rows


@pytest.mark.parametrize("name", PROGS)
def test_help_ranges_are_the_ranges_enforced(runner, tmp_path, name):
    helptext = cli(name, "--help").stdout
    rows = numeric_rows(helptext)
    if name != "rps3-simstudy":
        assert rows, helptext
    for opt, lo, hi in rows:
        # the ends are accepted (the value is parsed, then --help ends it)
        for v in (lo, hi):
            p = cli(name, f"{opt}={v}", "--help", cwd=tmp_path)
            assert p.returncode == 0, (opt, v, p.stderr)
        # one past either end is refused, naming the same range
        for v in ([lo - 1] if lo > 0 else []) + [hi + 1]:
            p = cli(name, f"{opt}={v}", "--help", cwd=tmp_path)
            assert p.returncode == 2, (opt, v)
            assert f"needs a whole number {lo}-{hi}, got '{v}'" in p.stderr
    # no other range is written into an option's text
    for line in helptext.splitlines():
        if re.match(r"  -", line):
            assert not re.search(r"\b\d+-\d+\b", line), line


def test_gzip_help_and_error_agree(runner, tmp_path):
    rows = dict((o, (lo, hi)) for o, lo, hi in
                numeric_rows(cli("rps3-run", "--help").stdout))
    assert rows["--gzip"] == (0, 9)
    assert rows["--jobs"] == (1, 1024)


# ------------------------------------------------------ summary wording

def test_summary_counts_work_units_not_jobs(runner, tmp_path):
    grid = os.path.join(CONFIGS, "grid.yaml")
    check = cli("rps3-run", grid, "--check")
    assert check.returncode == 0, check.stderr
    m = re.search(r"^(\d+) work units? of ", check.stdout, re.M)
    assert m, check.stdout
    units = int(m.group(1))
    assert units > 1  # so that "-j 1" and the count differ
    p = cli("rps3-run", grid, "-o", tmp_path / "g.h5", "-j", "1")
    assert p.returncode == 0, p.stderr
    last = p.stderr.rstrip().splitlines()[-1]
    assert last.endswith(f", {units} work units"), last
    assert "job" not in last


# -------------------------------------------------------------- man pages

@pytest.fixture(scope="module")
def man_pages(runner):
    subprocess.run(["make", "-C", ROOT, "--no-print-directory", "man"],
                   capture_output=True, text=True, check=True, timeout=300,
                   env=clean_env())
    return os.path.join(BUILD, "man")


def help_options(text):
    return re.findall(r"^  (?:-\w, )?(--[\w-]+)", text, re.M)


@pytest.mark.parametrize("name", PROGS + ["rps3-run-mpi"])
def test_man_page_lists_every_option_of_the_help(man_pages, name):
    page = open(os.path.join(man_pages, f"{name}.1")).read()
    helptext = cli("rps3-run" if name == "rps3-run-mpi" else name,
                   "--help").stdout
    assert page.startswith(".\\\" generated by packaging/man1.awk")
    assert f'.TH {name.upper()} 1 "" "rps3 {header_version()}"' in page
    assert re.search(rf"^\.SH NAME\n{re.escape(name.replace('-', chr(92) + '-'))} \\- \w",
                     page, re.M)
    for sect in ("SYNOPSIS", "DESCRIPTION", "OPTIONS", '"EXIT STATUS"',
                 "COPYRIGHT"):
        assert f"\n.SH {sect}\n" in page, sect
    opts = help_options(helptext)
    assert "--help" in opts and "--version" in opts
    for opt in opts:
        roff = opt.replace("-", "\\-")
        assert f"\\fB{roff}\\fR" in page, opt
    # every range of the help is in the page
    for opt, lo, hi in numeric_rows(helptext):
        assert f"is a whole number {lo}\\-{hi}" in page, opt
    if shutil.which("groff"):
        g = subprocess.run(["groff", "-man", "-ww", "-z",
                            os.path.join(man_pages, f"{name}.1")],
                           capture_output=True, text=True, timeout=60)
        assert g.returncode == 0 and g.stderr == "", g.stderr


def test_man_page_follows_the_help(runner, man_pages, tmp_path):
    """The page is made from --help: an option row of another help appears
    in the page made from it (the generator reads, it does not know)."""
    helptext = cli("rps3-simstudy", "--help").stdout
    extra = helptext.replace(
        "  --quick ", f"{'  --frobnicate N':<24}turn the frob\n"
        f"{'':24}N is a whole number 2-7\n  --quick ")
    h = tmp_path / "help.txt"
    v = tmp_path / "version.txt"
    h.write_text(extra)
    v.write_text(cli("rps3-simstudy", "--version").stdout)
    page = subprocess.run(
        ["awk", "-v", "prog=rps3-simstudy", "-f",
         os.path.join(ROOT, "packaging", "man1.awk"), str(h), str(v)],
        capture_output=True, text=True, check=True).stdout
    assert "\\fB\\-\\-frobnicate\\fR \\fIN\\fR\nturn the frob\n.br\n" \
        "N is a whole number 2\\-7" in page


# ------------------------------------------------- compiler and flags

def test_changed_compiler_rebuilds(runner, tmp_path):
    """`make CC=clang` after a cc build rebuilds the objects; the same
    compiler again rebuilds nothing."""
    if shutil.which("clang") is None:
        pytest.fail("clang is missing: `make check` installs it")
    b = tmp_path / "b"
    obj = f"{b}/obj/error.o"

    def make(*args):
        p = subprocess.run(["make", "-C", ROOT, "--no-print-directory",
                            f"B={b}", *args, obj], capture_output=True,
                           text=True, timeout=300, env=clean_env())
        assert p.returncode == 0, p.stdout + p.stderr
        return p.stdout

    def compiled(out):
        return [ln for ln in out.splitlines() if " -c src/error.c " in ln]

    first = compiled(make("CC=cc"))
    assert first and first[0].startswith("cc ")
    assert compiled(make("CC=cc")) == []
    again = compiled(make("CC=clang"))
    assert again and again[0].startswith("clang ")
    assert compiled(make("CC=clang")) == []
    # a changed flag is a change too
    assert compiled(make("CC=clang", "OPT=-O1"))
    assert compiled(make("CC=clang", "OPT=-O1")) == []
