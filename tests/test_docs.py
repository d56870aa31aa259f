"""The generated reference stays generated: the key table in docs/runner.md
is exactly `rps3-run --keys` (regenerate with `make docs`)."""

import os
import subprocess

from conftest import ROOT, RUNNER


def test_key_table_in_docs_is_generated(runner):
    keys = subprocess.run([RUNNER, "--keys"], capture_output=True, text=True,
                          check=True).stdout
    with open(os.path.join(ROOT, "docs", "runner.md")) as f:
        doc = f.read()
    assert keys in doc, "docs/runner.md key table is stale: run `make docs`"


def test_every_key_row_has_unit_range_and_doc(runner):
    keys = subprocess.run([RUNNER, "--keys"], capture_output=True, text=True,
                          check=True).stdout.splitlines()
    rows = [r.split(" | ") for r in keys[2:]]
    assert len(rows) >= 30
    for r in rows:
        assert len(r) == 7, r
        assert r[2] and r[3] and r[6].strip(" |"), r


def test_simulation_schema_in_docs_is_generated(runner):
    schema = subprocess.run([RUNNER, "--sim-schema"], capture_output=True,
                            text=True, check=True).stdout
    with open(os.path.join(ROOT, "docs", "runner.md")) as f:
        doc = f.read()
    assert schema in doc, "docs/runner.md simulation table is stale: run " \
        "`make docs`"


# ------------------------------------------------- every code block runs
#
# Every fenced block of README.md and docs/*.md is one of:
#   - a language that runs: ```sh (bash -e), ```python (this Python, with
#     the rps3 package), ```c (compiled and run, below);
#   - a file for the blocks after it: ```c file=app.c, ```cmake
#     file=CMakeLists.txt (written into the page's directory; a C file is
#     also compiled and run);
#   - ```text: output, tables, messages (not code);
#   - marked ```LANG fragment: part of something larger, or a command that
#     takes minutes, root or a cluster (counted, not run).
# A block without an info string, or of another language unmarked, fails:
# nothing is skipped silently.  The blocks of one page run in order in one
# temporary directory holding `build` and `configs` (links into the tree)
# and an empty `out`, with the built programs on PATH and an installed copy
# of rps3 (`make install PREFIX=...`) found by pkg-config, CMake and the
# loader.  C blocks are also compiled through pkg-config and CMake, each
# against the shared and the static library.

import re  # noqa: E402
import shutil  # noqa: E402
import sys  # noqa: E402

import pytest  # noqa: E402

RUNS = {"sh", "python", "c"}
FENCE = re.compile(r"^(\s*)```(.*)$")


def pages():
    docs = os.path.join(ROOT, "docs")
    return ["README.md"] + sorted(
        os.path.join("docs", f) for f in os.listdir(docs) if f.endswith(".md"))


def blocks(rel):
    """[(line, lang, attrs, text)] of the fenced blocks of a page."""
    lines = open(os.path.join(ROOT, rel)).read().split("\n")
    out, i = [], 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        indent, info = m.group(1), m.group(2).strip()
        j = i + 1
        while j < len(lines) and not re.match(r"^\s*```\s*$", lines[j]):
            j += 1
        assert j < len(lines), f"{rel}:{i + 1}: unclosed code block"
        words = info.split()
        lang = words[0] if words else ""
        attrs = dict(w.split("=", 1) if "=" in w else (w, True)
                     for w in words[1:])
        body = "\n".join(ln[len(indent):] if ln.startswith(indent) else ln
                         for ln in lines[i + 1:j]) + "\n"
        out.append((i + 1, lang, attrs, body))
        i = j + 1
    return out


def kind(lang, attrs):
    if lang == "text":
        return "text"
    if attrs.get("fragment"):
        return "fragment"
    if "file" in attrs:
        return "file"
    if lang in RUNS:
        return "run"
    return None


def test_every_block_is_classified():
    """Each block says what it is; the parser sees every fence (an
    independent count of the fence lines)."""
    counts = {"run": 0, "file": 0, "fragment": 0, "text": 0}
    for rel in pages():
        found = blocks(rel)
        fences = sum(1 for ln in open(os.path.join(ROOT, rel))
                     if ln.lstrip().startswith("```"))
        assert fences == 2 * len(found), rel
        for line, lang, attrs, _ in found:
            k = kind(lang, attrs)
            assert k, (f"{rel}:{line}: a ```{lang} block must run, be a "
                       "file=, or be marked ```text or ```LANG fragment")
            counts[k] += 1
    print(f"\ncode blocks: {counts}")
    # the README's C example, its build command and its Python runs
    readme = [kind(lang, a) for _, lang, a, _ in blocks("README.md")]
    assert readme.count("run") >= 3 and readme.count("file") == 1
    assert counts["run"] >= 10


@pytest.fixture(scope="module")
def installed(runner, tmp_path_factory):
    """rps3 installed with `make install PREFIX=...`."""
    pre = tmp_path_factory.mktemp("docs-prefix") / "usr"
    env = {k: v for k, v in os.environ.items()
           if k not in ("MAKEFLAGS", "MFLAGS", "MAKELEVEL", "MAKEOVERRIDES")}
    proc = subprocess.run(["make", "-C", ROOT, "--no-print-directory",
                           "install", f"PREFIX={pre}"], capture_output=True,
                          text=True, timeout=600, env=env)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return pre


def page_env(pre):
    env = {k: v for k, v in os.environ.items()
           if k not in ("MAKEFLAGS", "MFLAGS", "MAKELEVEL", "MAKEOVERRIDES")}
    env.update(
        PATH=os.pathsep.join([os.path.join(ROOT, "build"),
                              os.path.dirname(sys.executable),
                              env.get("PATH", "")]),
        PKG_CONFIG_PATH=str(pre / "lib" / "pkgconfig"),
        CMAKE_PREFIX_PATH=str(pre),
        LD_LIBRARY_PATH=str(pre / "lib"),
        MPLBACKEND="Agg")
    return env


def page_dir(tmp_path):
    for d in ("build", "configs"):
        (tmp_path / d).symlink_to(os.path.join(ROOT, d))
    (tmp_path / "out").mkdir()
    return tmp_path


@pytest.mark.parametrize("rel", pages())
def test_blocks_of_the_page_run(rel, installed, tmp_path):
    """The page's blocks, in order, in one directory."""
    here = page_dir(tmp_path)
    env = page_env(installed)
    for line, lang, attrs, body in blocks(rel):
        k = kind(lang, attrs)
        where = f"{rel}:{line}"
        if k == "file":
            (here / attrs["file"]).write_text(body)
            continue
        if k != "run" or lang == "c":
            continue
        cmd = (["bash", "-e", "-o", "pipefail", "-c", body] if lang == "sh"
               else [sys.executable, "-c", body])
        proc = subprocess.run(cmd, cwd=here, env=env, capture_output=True,
                              text=True, timeout=600)
        assert proc.returncode == 0, \
            f"{where}: ```{lang} failed\n{body}\n{proc.stdout}\n{proc.stderr}"


def c_blocks():
    return [(rel, line, body) for rel in pages()
            for line, lang, attrs, body in blocks(rel)
            if lang == "c" and kind(lang, attrs) in ("run", "file")]


CMAKE_BOTH = """\
cmake_minimum_required(VERSION 3.13)
project(block C)
find_package(rps3 REQUIRED)
add_executable(shared block.c)
target_link_libraries(shared PRIVATE rps3::rps3)
add_executable(static block.c)
target_link_libraries(static PRIVATE rps3::rps3_static)
"""


def needed(exe):
    out = subprocess.run(["readelf", "-d", str(exe)], capture_output=True,
                         text=True, check=True).stdout
    return re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", out)


@pytest.mark.parametrize("rel,line,body", c_blocks(),
                         ids=[f"{r}:{ln}" for r, ln, _ in c_blocks()])
def test_c_block_builds_through_pkg_config_and_cmake(rel, line, body,
                                                      installed, tmp_path):
    """Warning-free, against the installed copy, shared and static; it
    runs and exits 0 (a C program of the docs needs no GSL call: GSL's
    default handler stays on)."""
    if shutil.which("cmake") is None:
        pytest.fail("cmake is missing: `make check` installs it")
    env = page_env(installed)
    src = tmp_path / "block.c"
    src.write_text(body)
    warn = ["-Wall", "-Wextra", "-Werror"]

    def sh(cmd):
        p = subprocess.run(cmd, cwd=tmp_path, env=env, capture_output=True,
                           text=True, timeout=600)
        assert p.returncode == 0, f"{rel}:{line}: {cmd}\n{p.stdout}{p.stderr}"
        return p.stdout

    shared = sh(["pkg-config", "--cflags", "--libs", "rps3"]).split()
    static = sh(["pkg-config", "--static", "--cflags", "--libs",
                 "rps3"]).split()
    static = [w for f in static for w in
              (["-Wl,-Bstatic", "-lrps3", "-Wl,-Bdynamic"] if f == "-lrps3"
               else [f])]
    exes = {}
    for name, flags in (("pc-shared", shared), ("pc-static", static)):
        exes[name] = tmp_path / name
        sh(["cc", *warn, str(src), *flags, "-o", str(exes[name])])
    (tmp_path / "CMakeLists.txt").write_text(CMAKE_BOTH)
    sh(["cmake", "-S", ".", "-B", "cm", f"-DCMAKE_C_FLAGS={' '.join(warn)}"])
    sh(["cmake", "--build", "cm"])
    exes["cmake-shared"] = tmp_path / "cm" / "shared"
    exes["cmake-static"] = tmp_path / "cm" / "static"
    for name, exe in exes.items():
        so = [n for n in needed(exe) if n.startswith("librps3")]
        major = re.search(r"#define RPS3_VERSION_MAJOR (\d+)", open(
            os.path.join(ROOT, "include", "rps3.h")).read()).group(1)
        assert so == ([] if name.endswith("static")
                      else [f"librps3.so.{major}"]), \
            (name, needed(exe))
        sh([str(exe)])


# ------------------------------------------------ references to docs sections
# Scene files and docs point readers to docs pages and their sections, as
# markdown links (`simulation.md#what-it-costs`), as plain
# `docs/runner.md#scene-keys`, or as `docs/hdf5.md, "Compression"` (the
# quoted text the start of a heading).  Each must resolve to a page and a
# heading that exist; the docs speak of the software, not of the tracker.

import glob  # noqa: E402
import unicodedata  # noqa: E402

DOCS = os.path.join(ROOT, "docs")


def _doc_slug(heading):
    """GitHub's anchor for a heading: its rendered text lower-cased,
    punctuation and symbols dropped, spaces turned into hyphens."""
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # links: text
    text = text.replace("`", "").replace("*", "").strip().lower()
    kept = [c for c in text if c.isalnum() or c in "-_ "
            or unicodedata.category(c).startswith("M")]
    return "".join(kept).replace(" ", "-")


def _doc_headings(path):
    """(heading texts, anchors) of a markdown file, code blocks skipped;
    a repeated anchor gets -1, -2, ... as on GitHub."""
    texts, anchors, seen, fenced = [], set(), {}, False
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.lstrip().startswith("```"):
                fenced = not fenced
                continue
            m = None if fenced else re.match(r"#{1,6}\s+(.*?)\s*#*\s*$", line)
            if m:
                texts.append(m.group(1))
                slug = _doc_slug(m.group(1))
                n = seen.get(slug, 0)
                seen[slug] = n + 1
                anchors.add(slug if n == 0 else f"{slug}-{n}")
    return texts, anchors


def _doc_plain(text):
    """Heading text as a reader quotes it: no backticks, one space."""
    return " ".join(text.replace("`", "").split()).lower()


def _doc_sources():
    """(path, text with comment markers and line breaks joined) of every
    docs page and scene file."""
    for path in sorted(glob.glob(os.path.join(DOCS, "*.md"))
                       + glob.glob(os.path.join(ROOT, "configs", "*.yaml"))):
        with open(path, encoding="utf-8") as f:
            text = f.read()
        if path.endswith(".yaml"):
            text = re.sub(r"\n[ \t]*#[ \t]?", " ", text)
        yield path, text


def _doc_references(path, text):
    """(target page, anchor or None, quoted heading or None) of every
    reference to a docs page in `text`."""
    here = os.path.dirname(path)
    refs = []
    if path.endswith(".md"):
        for m in re.finditer(r"\]\(([^)\s]+)\)", text):
            target = m.group(1)
            if re.match(r"[a-z]+:", target):
                continue  # http:, mailto:
            page, _, anchor = target.partition("#")
            if page and not page.endswith(".md"):
                continue  # a source file or a directory
            page = os.path.normpath(os.path.join(here, page)) if page \
                else path
            refs.append((page, anchor or None, None))
    for m in re.finditer(r"(?<![\w/.])docs/([\w-]+\.md)#([\w-]+)", text):
        refs.append((os.path.join(DOCS, m.group(1)), m.group(2), None))
    flat = " ".join(text.split())
    for m in re.finditer(r"(?<![\w/.])docs/([\w-]+\.md),?\s+(?:section\s+)?"
                         r"[\"“]([^\"”]+)[\"”]", flat):
        refs.append((os.path.join(DOCS, m.group(1)), None, m.group(2)))
    return refs


def test_every_docs_reference_resolves():
    bad, count = [], 0
    for path, text in _doc_sources():
        where = os.path.relpath(path, ROOT)
        for page, anchor, quoted in _doc_references(path, text):
            count += 1
            if not os.path.isfile(page):
                bad.append(f"{where}: {os.path.relpath(page, ROOT)}: "
                           "no such page")
                continue
            texts, anchors = _doc_headings(page)
            if anchor is not None and anchor not in anchors:
                bad.append(f"{where}: {os.path.relpath(page, ROOT)}#{anchor}:"
                           " no such heading")
            if quoted is not None and not any(
                    _doc_plain(t).startswith(_doc_plain(quoted))
                    for t in texts):
                bad.append(f"{where}: {os.path.relpath(page, ROOT)}, "
                           f"\"{quoted}\": no such heading")
    assert count >= 20, "the reference patterns found almost nothing"
    assert not bad, "\n".join(bad)


def test_scene_files_point_to_docs_not_readme():
    for path, text in _doc_sources():
        if path.endswith(".yaml"):
            assert not re.search(r"README\s*,?\s*[\"“]", text), \
                f"{path}: points to a README section; use docs/X.md#section"


def test_docs_name_no_tracker_issues_or_sessions():
    history = re.compile(r"\bissues?\s+#?\d+|(?<![\w&/#])#\d+\b"
                         r"|\bthe issue'?s\b|\bsessions?\b", re.IGNORECASE)
    bad = []
    for path, text in _doc_sources():
        for m in history.finditer(text):
            bad.append(f"{os.path.relpath(path, ROOT)}: "
                       f"...{text[max(0, m.start() - 30):m.end() + 30]}...")
    assert not bad, "\n".join(bad)
