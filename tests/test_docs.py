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


# ------------------------------------------------ references to docs sections
# Scene files and docs point readers to docs pages and their sections, as
# markdown links (`simulation.md#what-it-costs`), as plain
# `docs/runner.md#scene-keys`, or as `docs/hdf5.md, "Compression"` (the
# quoted text the start of a heading).  Each must resolve to a page and a
# heading that exist; the docs speak of the software, not of the tracker.

import glob
import re
import unicodedata

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
