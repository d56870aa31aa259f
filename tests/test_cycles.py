"""scripts/check_cycles.py (`make cycles`): it fails, naming the cycle or
the edge, on a file cycle (by includes or by the symbols the objects use)
and on a folder that uses one above it, and it passes on the runner."""

import os
import shutil
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPT = os.path.join(ROOT, "scripts", "check_cycles.py")
CC = os.environ.get("CC", "cc")


def tree(base, files):
    """Write {relative path: text} under base/runner."""
    root = base / "runner"
    for rel, text in files.items():
        p = root / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)
    return root


def build(root, objdir):
    """Compile every .c of root into objdir/<folder>/<name>.o."""
    if shutil.which(CC) is None:
        pytest.skip("no C compiler")
    for dirpath, _, names in os.walk(root):
        for n in names:
            if n.endswith(".c"):
                src = os.path.join(dirpath, n)
                rel = os.path.relpath(src, root)[:-2] + ".o"
                out = os.path.join(objdir, rel)
                os.makedirs(os.path.dirname(out), exist_ok=True)
                subprocess.run([CC, "-c", "-I", str(root), src, "-o", out],
                               check=True)


def run(root, *objdirs):
    args = [sys.executable, SCRIPT, "--root", str(root)]
    for d in objdirs:
        args += ["--objects", str(d)]
    return subprocess.run(args, capture_output=True, text=True, timeout=120)


# a clean tree: scene/ uses core/, bin/ uses both
CLEAN = {
    "core/log.h": "#ifndef LOG_H\n#define LOG_H\nint log_msg(int x);\n#endif\n",
    "core/log.c": '#include "log.h"\nint log_msg(int x) { return x + 1; }\n',
    "scene/parse.h": "#ifndef PARSE_H\n#define PARSE_H\nint parse_it(int x);\n"
                     "#endif\n",
    "scene/parse.c": '#include "parse.h"\n#include "core/log.h"\n'
                     "int parse_it(int x) { return log_msg(x) * 2; }\n",
    "bin/main.c": '#include "scene/parse.h"\n#include "core/log.h"\n'
                  "int main(void) { return parse_it(log_msg(0)) - 4; }\n",
}


def test_clean_tree_passes(tmp_path):
    root = tree(tmp_path, CLEAN)
    build(root, tmp_path / "obj")
    p = run(root, tmp_path / "obj")
    assert p.returncode == 0, p.stderr
    assert "no cycle, no upward edge" in p.stdout
    # the objects were read: the edge of the calls counts
    assert "3 objects read" in p.stdout


def test_cycle_by_symbols_fails(tmp_path):
    # no include between them: only nm sees that each calls the other
    files = dict(CLEAN)
    files["scene/x.c"] = ("int y_f(int);\nint x_f(int a);\n"
                          "int x_f(int a) { return a ? y_f(a - 1) : 0; }\n")
    files["scene/y.c"] = ("int x_f(int);\nint y_f(int a);\n"
                          "int y_f(int a) { return a ? x_f(a - 1) : 1; }\n")
    root = tree(tmp_path, files)
    assert run(root).returncode == 0  # the sources alone show no cycle
    build(root, tmp_path / "obj")
    p = run(root, tmp_path / "obj")
    assert p.returncode == 1
    assert "cycle: scene/x -> scene/y -> scene/x" in p.stderr
    assert "scene/x.c uses y_f of scene/y.c" in p.stderr
    assert "scene/y.c uses x_f of scene/x.c" in p.stderr


def test_cycle_by_includes_fails(tmp_path):
    files = dict(CLEAN)
    files["scene/a.h"] = '#ifndef A_H\n#define A_H\n#include "b.h"\n#endif\n'
    files["scene/b.h"] = '#ifndef B_H\n#define B_H\n#include "a.h"\n#endif\n'
    p = run(tree(tmp_path, files))
    assert p.returncode == 1
    assert "cycle: scene/a -> scene/b -> scene/a" in p.stderr
    assert 'scene/a.h:3 includes "b.h"' in p.stderr


def test_three_file_cycle_is_named(tmp_path):
    files = dict(CLEAN)
    for a, b in (("p", "q"), ("q", "r"), ("r", "p")):
        files[f"scene/{a}.c"] = (f"int {b}_f(int);\nint {a}_f(int v);\n"
                                   f"int {a}_f(int v) {{ return v ? {b}_f(v - 1)"
                                   " : 0; }\n")
    root = tree(tmp_path, files)
    build(root, tmp_path / "obj")
    p = run(root, tmp_path / "obj")
    assert p.returncode == 1
    assert "cycle: scene/p -> scene/q -> scene/r -> scene/p" in p.stderr


def test_upward_edge_by_include_fails(tmp_path):
    files = dict(CLEAN)
    files["core/log.c"] = ('#include "log.h"\n#include "scene/parse.h"\n'
                           "int log_msg(int x) { return x + 1; }\n")
    p = run(tree(tmp_path, files))
    assert p.returncode == 1
    assert "upward edge: core/log -> scene/parse" in p.stderr
    assert "cycle" in p.stderr  # log and parse now need each other too


def test_upward_edge_by_symbol_fails(tmp_path):
    # core calls into bin without including anything: no cycle, but a
    # folder that uses one above it
    files = dict(CLEAN)
    files["bin/tool.c"] = "int tool_f(int);\nint tool_f(int v) { return v; }\n"
    files["core/util.c"] = ("int tool_f(int);\nint util_f(int);\n"
                            "int util_f(int v) { return tool_f(v); }\n")
    root = tree(tmp_path, files)
    build(root, tmp_path / "obj")
    p = run(root, tmp_path / "obj")
    assert p.returncode == 1
    assert "upward edge: core/util -> bin/tool" in p.stderr
    assert "uses tool_f" in p.stderr
    assert "cycle:" not in p.stderr


def test_sibling_folders_fail(tmp_path):
    # mpi/ sits beside core/: neither may use the other
    files = dict(CLEAN)
    files["mpi/world.c"] = '#include "core/log.h"\nint world_f(void);\n' \
                           "int world_f(void) { return log_msg(1); }\n"
    p = run(tree(tmp_path, files))
    assert p.returncode == 1
    assert "edge between sibling folders: mpi/world -> core/log" in p.stderr


def test_mpi_outside_its_folder_fails(tmp_path):
    files = dict(CLEAN)
    files["bin/main.c"] = ('#include "scene/parse.h"\n#include "core/log.h"\n'
                           "#ifdef RPS3_MPI\n#include <mpi.h>\n#endif\n"
                           "int main(void) { return parse_it(0); }\n")
    files["mpi/world.c"] = ("#include <mpi.h>\nint world_f(void);\n"
                            "int world_f(void) { return 0; }\n")
    p = run(tree(tmp_path, files))
    assert p.returncode == 1
    assert "bin/main.c:3: MPI outside mpi/: #ifdef RPS3_MPI" in p.stderr
    assert "bin/main.c:4: MPI outside mpi/: #include <mpi.h>" in p.stderr
    assert "mpi/world.c" not in p.stderr


def test_file_outside_the_layers_fails(tmp_path):
    files = dict(CLEAN)
    files["misc/x.c"] = "int x_f(void);\nint x_f(void) { return 0; }\n"
    files["loose.c"] = "int loose_f(void);\nint loose_f(void) { return 0; }\n"
    p = run(tree(tmp_path, files))
    assert p.returncode == 1
    assert "folder misc/ has no layer" in p.stderr
    assert "loose.c: not in one subsystem folder" in p.stderr


def test_private_header_belongs_to_its_module(tmp_path):
    # sweep_int.h (no sweep_int.c) is sweep's: sweep.c including it, and it
    # including sweep.h, is no cycle
    files = dict(CLEAN)
    files["scene/sweep.h"] = "#ifndef S_H\n#define S_H\nint sw(void);\n#endif\n"
    files["scene/sweep_int.h"] = ('#ifndef SI_H\n#define SI_H\n#include '
                                  '"sweep.h"\n#endif\n')
    files["scene/sweep.c"] = ('#include "sweep.h"\n#include "sweep_int.h"\n'
                              "int sw(void) { return 0; }\n")
    assert run(tree(tmp_path, files)).returncode == 0


def test_missing_objects_folder_is_a_usage_error(tmp_path):
    p = run(tree(tmp_path, CLEAN), tmp_path / "nowhere")
    assert p.returncode == 2
    assert "no such folder" in p.stderr


def test_the_runner_passes():
    objdirs = [os.path.join(ROOT, "build", d) for d in ("runner", "runner-mpi")]
    objdirs = [d for d in objdirs if os.path.isdir(d)]
    p = run(os.path.join(ROOT, "runner"), *objdirs)
    assert p.returncode == 0, p.stderr
    assert "no cycle, no upward edge" in p.stdout
