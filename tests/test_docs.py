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
