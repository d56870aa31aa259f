#!/usr/bin/env python3
"""check_cycles.py - the runner's files depend on each other without a
circle, and each subsystem folder only on the folders below it.

A module is a .c file and the .h of the same name in the same folder (a
header without a .c is a module of its own).  Module A depends on module B
when a file of A includes a file of B (`#include "..."`, the code's own
lines), or when A's object file uses a global symbol that B's object file
defines (`nm`, so calls through macros and data count too).  The graph
must have no cycle, and no edge may go from a folder to one above it in
LAYERS; folders of the same layer may not use each other either.  Every
file must sit in a folder of LAYERS, and only mpi/ may include <mpi.h> or
test RPS3_MPI.

    check_cycles.py [--root runner] [--objects DIR ...]

--objects: folders of built objects, DIR/<folder>/<name>.o for
runner/<folder>/<name>.c (objects whose source is gone are skipped).
Exit 0 when the graph is clean, 1 naming every cycle and every upward
edge, 2 on a usage error.  Standard library only, and `nm`.
"""

import argparse
import os
import re
import subprocess
import sys

# lowest first: a folder may use the folders of lower layers only.  mpi/
# sits beside core/: the one place that knows MPI, knowing nothing else of
# the runner (docs/runner.md, "Code layout").
LAYERS = [
    ("core", "mpi"),
    ("scene",),
    ("output",),
    ("exec",),
    ("shards",),
    ("study",),
    ("bin",),
]
RANK = {f: i for i, group in enumerate(LAYERS) for f in group}

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
# MPI is mpi/'s alone: elsewhere neither its header nor a build switch
MPI_ONLY = "mpi"
MPI_USE = re.compile(r'^\s*#\s*(?:include\s*<mpi\.h>|if.*\bRPS3_MPI\b)', re.M)


def module_of(path):
    """'scene/scene_parse.c' -> 'scene/scene_parse'."""
    return os.path.splitext(path)[0]


def owners(files):
    """File -> module.  A header without a .c of its own (sweep_int.h,
    study_ref_impl.h) is the private part of the module its name extends
    (sweep, study_ref) when there is one; else a module of its own."""
    stems = {module_of(r) for r in files}
    own = {}
    for r in files:
        m = module_of(r)
        if r.endswith(".h") and m + ".c" not in files:
            cand = m
            while "_" in cand.split("/")[-1]:
                cand = cand.rsplit("_", 1)[0]
                if cand in stems:
                    m = cand
                    break
        own[r] = m
    return own


def scan_sources(root, errors):
    """Relative paths of the .c and .h files under root."""
    files = []
    for dirpath, _, names in os.walk(root):
        for n in sorted(names):
            if not n.endswith((".c", ".h")):
                continue
            rel = os.path.relpath(os.path.join(dirpath, n), root)
            rel = rel.replace(os.sep, "/")
            parts = rel.split("/")
            if len(parts) != 2:
                errors.append(f"{rel}: not in one subsystem folder of {root}/")
                continue
            if parts[0] not in RANK:
                script = os.path.basename(__file__)
                errors.append(f"{rel}: folder {parts[0]}/ has no layer "
                              f"(LAYERS in {script})")
                continue
            files.append(rel)
    return sorted(files)


def include_edges(root, files, own, add, errors):
    known = set(files)
    for rel in files:
        folder = rel.split("/")[0]
        with open(os.path.join(root, rel), encoding="utf-8",
                  errors="replace") as f:
            text = f.read()
        if folder != MPI_ONLY:
            for m in MPI_USE.finditer(text):
                line = text.count("\n", 0, m.start()) + 1
                errors.append(f"{rel}:{line}: MPI outside {MPI_ONLY}/: "
                              f"{m.group(0).strip()}")
        for m in INCLUDE.finditer(text):
            name = m.group(1)
            line = text.count("\n", 0, m.start()) + 1
            # as the compiler looks: the including file's folder, then -I
            # runner; anything else (rps3.h, system) is not the runner's
            for cand in (folder + "/" + name, name):
                cand = os.path.normpath(cand).replace(os.sep, "/")
                if cand in known:
                    add(own[rel], own[cand],
                        f'{rel}:{line} includes "{name}"')
                    break


def nm_symbols(obj):
    out = subprocess.run(["nm", "-P", obj], capture_output=True, text=True,
                         check=True).stdout
    defined, undefined = set(), set()
    for line in out.splitlines():
        f = line.split()
        if len(f) < 2:
            continue
        sym, kind = f[0], f[1]
        if kind == "U":
            undefined.add(sym)
        elif kind.isupper() or kind in "vw":  # global (or weak) definition
            defined.add(sym)
    return defined, undefined


def symbol_edges(root, files, objdirs, add):
    sources = {module_of(r) for r in files if r.endswith(".c")}
    objs = []
    for d in objdirs:
        for dirpath, _, names in os.walk(d):
            for n in sorted(names):
                if n.endswith(".o"):
                    p = os.path.join(dirpath, n)
                    mod = module_of(os.path.relpath(p, d)
                                    .replace(os.sep, "/"))
                    if mod in sources:
                        objs.append((mod, p))
    definers = {}
    uses = []
    for mod, p in objs:
        defined, undefined = nm_symbols(p)
        for s in defined:
            definers.setdefault(s, set()).add(mod)
        uses.append((mod, undefined))
    for mod, undefined in uses:
        for s in sorted(undefined):
            for dst in sorted(definers.get(s, ())):
                add(mod, dst, f"{mod}.c uses {s} of {dst}.c")
    return len(objs)


def sccs(nodes, edges):
    """Tarjan's strongly connected components (iterative)."""
    index, low, on, stack, out = {}, {}, set(), [], []
    counter = [0]
    for start in sorted(nodes):
        if start in index:
            continue
        work = [(start, iter(sorted(edges.get(start, ()))))]
        index[start] = low[start] = counter[0]
        counter[0] += 1
        stack.append(start)
        on.add(start)
        while work:
            v, it = work[-1]
            advanced = False
            for w in it:
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(edges.get(w, ())))))
                    advanced = True
                    break
                if w in on:
                    low[v] = min(low[v], index[w])
            if advanced:
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    comp.append(w)
                    if w == v:
                        break
                out.append(sorted(comp))
    return out


def a_cycle(comp, edges):
    """One circle through the component's first module (BFS back to it)."""
    inside = set(comp)
    start = comp[0]
    prev = {}
    queue = [start]
    while queue:
        v = queue.pop(0)
        for w in sorted(edges.get(v, ())):
            if w not in inside:
                continue
            if w == start:
                path = [v]
                while path[-1] != start:
                    path.append(prev[path[-1]])
                return list(reversed(path)) + [start]
            if w not in prev:
                prev[w] = v
                queue.append(w)
    return comp + [start]


def check(root, objdirs):
    errors = []
    files = scan_sources(root, errors)
    edges, why = {}, {}

    def add(a, b, reason):
        if a == b:
            return
        edges.setdefault(a, set()).add(b)
        why.setdefault((a, b), reason)

    own = owners(files)
    include_edges(root, files, own, add, errors)
    nobj = symbol_edges(root, files, objdirs, add) if objdirs else 0
    nodes = set(own.values())

    for comp in sccs(nodes, edges):
        if len(comp) < 2:
            continue
        path = a_cycle(comp, edges)
        errors.append("cycle: {}".format(" -> ".join(path)))
        if len(comp) > len(path) - 1:
            errors.append("  (all of {} depend on each other)".format(", ".join(comp)))
        for a, b in zip(path, path[1:]):
            errors.append(f"  {why[(a, b)]}")
    for (a, b), reason in sorted(why.items()):
        fa, fb = a.split("/")[0], b.split("/")[0]
        if fa == fb:
            continue
        if RANK[fa] < RANK[fb]:
            errors.append(f"upward edge: {a} -> {b} ({fa}/ is below {fb}/): {reason}")
        elif RANK[fa] == RANK[fb]:
            errors.append(f"edge between sibling folders: {a} -> {b}: {reason}")
    summary = f"{len(nodes)} modules, {len(why)} edges ({nobj} objects read)"
    return errors, summary


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--root", default="runner")
    ap.add_argument("--objects", action="append", default=[],
                    help="a folder of built objects (repeatable)")
    a = ap.parse_args(argv)
    if not os.path.isdir(a.root):
        print(f"check_cycles: {a.root}: no such folder", file=sys.stderr)
        return 2
    for d in a.objects:
        if not os.path.isdir(d):
            print(f"check_cycles: {d}: no such folder (build first)",
                  file=sys.stderr)
            return 2
    errors, summary = check(a.root, a.objects)
    for e in errors:
        print(e, file=sys.stderr)
    if errors:
        print(f"check_cycles: {a.root}: {summary}", file=sys.stderr)
        return 1
    print(f"check_cycles: {a.root}: {summary}, no cycle, no upward edge")
    return 0


if __name__ == "__main__":
    sys.exit(main())
