"""tests/mutation.py's own bookkeeping, without running a mutation.

`make mutation` takes long and is not part of `make check`; these checks
are quick and are: every mutation's original text still occurs exactly once
in its file (an edit of src/ that moves it makes the entry stale, and the
script would stop there), docs/mutations.md names a killer for every
mutation, and the order of one mutation's tests puts the tests that killed
it last time first, C programs before pytest, then every other test.
"""

import importlib.util
import os

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _mutation():
    path = os.path.join(ROOT, "tests", "mutation.py")
    spec = importlib.util.spec_from_file_location("mutation", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_every_original_text_occurs_once():
    mut = _mutation()
    assert mut.check_originals(ROOT, mut.MUTATIONS) == []
    names = [m[0] for m in mut.MUTATIONS]
    assert len(names) == len(set(names))
    # and the check can fail: a text that is not there, one that is twice
    bad = mut.check_originals(ROOT, [
        ("absent", "src/model.c", "no such text in the model", "", ""),
        ("twice", "src/model.c", "m->", "", "")])
    assert [b.split(":")[0] for b in bad] == ["absent", "twice"]


def test_page_names_a_killer_for_every_mutation():
    mut = _mutation()
    kills = mut.previous_kills(os.path.join(ROOT, "docs", "mutations.md"))
    missing = [m[0] for m in mut.MUTATIONS if not kills.get(m[0])]
    assert missing == [], f"docs/mutations.md names no killer of {missing}"


def test_order_previous_killers_first():
    mut = _mutation()
    ctests = ["test_a", "test_b", "test_c"]
    times = {"test_a": 3.0, "test_b": 1.0, "test_c": 2.0,
             "test_oracles": 9.0, "test_anchor": 0.5}
    files = ["tests/test_oracles.py", "tests/test_anchor.py"]
    nodes = {"tests/test_oracles.py::test_x"}
    plan = mut.order(ctests, files, ["test_oracles::test_x", "test_c",
                                     "test_oracles::gone"], times, nodes)
    assert plan == [("c", "test_c"),
                    ("py", ["tests/test_oracles.py::test_x"]),
                    ("c", "test_b"), ("c", "test_a"),
                    ("py", ["tests/test_anchor.py",
                            "tests/test_oracles.py"])]
    # without a previous killer: the C programs fastest first, then pytest
    assert mut.order(ctests, files, [], times, nodes)[0] == ("c", "test_b")


def test_previous_kills_reads_the_table(tmp_path):
    mut = _mutation()
    page = tmp_path / "m.md"
    page.write_text(
        "| mutation | where | killed by | survived? |\n|---|---|---|---|\n"
        "| centre-x: x of the centre | `src/ik.c:36` | `test_ik`, "
        "`test_oracles::test_y` | no |\n"
        "| omega: a rate | `src/velocity.c:3` | `test_sim (timeout)` | no |\n"
        "| alive: survives | `src/x.c:1` | nothing | **YES** |\n")
    assert mut.previous_kills(str(page)) == {
        "centre-x": ["test_ik", "test_oracles::test_y"],
        "omega": ["test_sim"], "alive": []}
    assert mut.previous_kills(str(tmp_path / "none.md")) == {}
