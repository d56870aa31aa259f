"""The shared library exports exactly the functions that include/rps3.h
declares, every declaration carries RPS3_API, and the SONAME carries the
major version.  The header is read as text (comments and preprocessor lines
dropped) and librps3.so with `nm -D`; nothing is shared between the two.
"""

import os
import re
import subprocess

from conftest import ROOT

HEADER = os.path.join(ROOT, "include", "rps3.h")
SHARED = os.path.join(ROOT, "build", "librps3.so")


def header_statements():
    """Top-level statements of the header: comments, preprocessor lines
    (with their continuations) and the extern "C" braces removed."""
    text = open(HEADER).read()
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"^\s*#(?:[^\n]*\\\n)*[^\n]*", " ", text, flags=re.M)
    text = re.sub(r'extern\s+"C"\s*\{', " ", text)
    return [s.strip() for s in text.split(";") if s.strip()]


def declared_functions():
    """{name: statement} of every function the header declares."""
    decls = {}
    for stmt in header_statements():
        body = re.sub(r"\{[^{}]*\}", " ", stmt)  # struct/enum bodies
        m = re.search(r"\b(rps3_\w+)\s*\(", body)
        if m and not body.lstrip().startswith("typedef"):
            decls[m.group(1)] = " ".join(stmt.split())
    return decls


def exported_symbols():
    """Defined dynamic symbols of librps3.so: {name: nm type letter}."""
    out = subprocess.run(["nm", "-D", "--defined-only", SHARED],
                         capture_output=True, text=True, check=True).stdout
    syms = {}
    for line in out.splitlines():
        parts = line.split()
        if len(parts) == 3:
            syms[parts[2].split("@")[0]] = parts[1]
    return syms


def test_header_parse_finds_the_api():
    decls = declared_functions()
    # a parser that finds nothing would make the comparisons vacuous
    for name in ("rps3_version", "rps3_model_init", "rps3_inverse",
                 "rps3_traj_eval", "rps3_omega_paper"):
        assert name in decls, name
    assert len(decls) >= 25


def test_every_declaration_carries_rps3_api():
    missing = [n for n, s in declared_functions().items()
               if not s.startswith("RPS3_API ")]
    assert missing == []


def test_exports_are_the_declared_functions():
    exported = exported_symbols()
    declared = set(declared_functions())
    # only functions (text symbols), no data and nothing internal
    assert {n for n, t in exported.items() if t not in "TW"} == set()
    assert set(exported) - declared == set(), "exported, not declared"
    assert declared - set(exported) == set(), "declared, not exported"


def test_soname_carries_the_major_version():
    text = open(HEADER).read()
    major = re.search(r"#define RPS3_VERSION_MAJOR (\d+)", text).group(1)
    out = subprocess.run(["readelf", "-d", SHARED], capture_output=True,
                         text=True, check=True).stdout
    assert f"Library soname: [librps3.so.{major}]" in out


def test_one_validation_path_through_rps3_check():
    """Each object has one validation, and every function that validates
    its arguments reports through rps3_check (the field by identifier and
    the message), not through a caller's char buffer: no declaration takes
    an `err, errsz` pair, none is a second `_validate` entry point, and
    the validators and validating allocations end with `rps3_check *`."""
    decls = declared_functions()
    buffers = [n for n, s in decls.items()
               if re.search(r"\bchar\s*\*\s*\w*err\w*\s*,\s*size_t", s)]
    assert buffers == []
    assert [n for n in decls if n.endswith("_validate")] == []
    for name in ("rps3_model_init", "rps3_traj_check", "rps3_design_model",
                 "rps3_sim_alloc", "rps3_sim_check_rate", "rps3_ctrl_alloc"):
        assert re.search(r"rps3_check\s*\*\s*chk\s*\)$", decls[name]), \
            decls[name]
