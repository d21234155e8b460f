#!/usr/bin/env python3
"""The module import graph of the library (src/): its circles and its imports that run up.

Usage: python3 tools/import_graph.py [--src src] [--lib-only] [--edges] [--all]

Exit status 1 when a circle or an upward import is found in the library, 0 otherwise.

What a node is: one module file (`foo.rs` or `foo/mod.rs`), found by following `mod x;` from
src/lib.rs. Inline modules (`mod tests { ... }`) belong to their file.

What an edge is: file A -> file B when A names an item of B through
  - a `use` declaration whose path starts with `crate::`, `super::`, `self::` or the name of
    one of A's child modules (braces and nested braces expanded), or
  - a path in code (not in comments or strings) that starts with `crate::` or `super::`.
`super::`/`self::` inside an inline module count from that inline module.

How a path is resolved to a file: the longest prefix of the path that names a module file
gives the file; if the next segment is a name that file brings in with a `use` (its own or
re-exported with `pub use`), the path is followed through that `use` to the file that defines
the item. So `crate::raster::Context`, re-exported by raster/mod.rs from raster/context.rs,
is an edge to raster/context.rs, not to raster/mod.rs.

The rule for re-exports: a `pub use` of an item from inside the file's own subtree (a mod.rs
re-exporting its children's items) only forwards and is no edge; so a mod.rs that re-exports
a child's items while the child imports a type defined in mod.rs is not a circle. A `pub use`
of anything outside the file's subtree is an import like any other. An import of an item that
mod.rs itself defines (not a re-export) is an edge to mod.rs; a mod.rs that then also `use`s
its child's items for its own code forms a circle, as it should.

Circles: strongly connected components of more than one file (Tarjan), sibling files and a
mod.rs with its children included.

Upward imports: the layer order of shared/ARCHITECTURE.md, highest first:
    cli -> bench, tour, web, video -> renderer -> raster, raytrace, stream
        -> prepare, render, output, compare -> projection, scene, io
An edge from a file in a top-level module of a lower layer to one of a higher layer is
upward. Within the sketch's fourth layer, compare (the metrics: it measures rendered images
and writes its heatmaps through output) sits above render and output, which must not import
it. Top-level modules that the sketch does not place are given a layer here (LAYERS):
frames sits with output (it names files and parses JSON; tour, video and web read it);
frame (the rendered image type), rng, value (option value parsing), stats (percentiles),
font (the charts' font) and synthetic (generated test scenes) sit at the bottom with scene; memory (memory budgets,
which size the stream's chunks) sits with stream; suite (the benchmark scene suite) sits
with bench. Edges between files of one layer are not upward (circles catch their loops).
Tests (`#[cfg(test)]` modules) count: a test that imports a higher layer is reported too;
edges that only tests make are marked (test).

Folder circles: the same graph with each top-level module as one node; two folders that
import each other (in any files) are a circle even when no file-level circle exists.

--lib-only leaves src/cli out; --edges prints every edge between top-level modules (--all:
also those inside one).
"""

import argparse
import os
import re
import sys
from collections import defaultdict

LAYERS = {
    "cli": 6,
    "bench": 5, "tour": 5, "web": 5, "video": 5, "suite": 5,
    "renderer": 4,
    "raster": 3, "raytrace": 3, "stream": 3, "memory": 3, "index": 3,
    "compare": 2.5,
    "prepare": 2, "render": 2, "output": 2, "frames": 2,
    "projection": 1, "scene": 1, "io": 1,
    "frame": 1, "rng": 1, "value": 1, "font": 1, "synthetic": 1, "stats": 1,
}


def strip(text):
    """Blanks comments, string and char literals (keeping newlines and length)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            depth, j = 1, i + 2
            while j < n and depth:
                if text.startswith("/*", j):
                    depth, j = depth + 1, j + 2
                elif text.startswith("*/", j):
                    depth, j = depth - 1, j + 2
                else:
                    j += 1
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == "r" and re.match(r'r#*"', text[i:i + 10]) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            hashes = re.match(r'r(#*)"', text[i:]).group(1)
            end = text.find('"' + hashes, i + 2 + len(hashes))
            end = n if end < 0 else end + 1 + len(hashes)
            out.append(re.sub(r"[^\n]", " ", text[i:end]))
            i = end
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            out.append(re.sub(r"[^\n]", " ", text[i:j + 1]))
            i = j + 1
        elif c == "'":
            m = re.match(r"'(\\.[^']*|[^\\'])'", text[i:])
            if m:
                out.append(" " * len(m.group(0)))
                i += len(m.group(0))
            else:  # a lifetime
                out.append(c)
                i += 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def expand_use(tree):
    """`a::{b, c::{d, e as f}, self}` -> [[a, b], [a, c, d], [a, c, e], [a]] (names, alias)."""
    tree = re.sub(r"\s+", "", tree)

    def parse(s, prefix):
        paths = []
        depth, start, parts = 0, 0, []
        for k, ch in enumerate(s):
            if ch == "{":
                depth += 1
            elif ch == "}":
                depth -= 1
            elif ch == "," and depth == 0:
                parts.append(s[start:k])
                start = k + 1
        parts.append(s[start:])
        for part in parts:
            if not part:
                continue
            brace = part.find("{")
            if brace >= 0:
                head = [x for x in part[:brace].split("::") if x]
                paths += parse(part[brace + 1:part.rfind("}")], prefix + head)
            else:
                alias = None
                if "as" in part and re.search(r"[a-zA-Z0-9_]as[A-Za-z_]", part):
                    # `x as y` lost its spaces: split on the last `as` between names.
                    m = re.match(r"(.*[A-Za-z0-9_*])as([A-Za-z_][A-Za-z0-9_]*)$", part)
                    if m and not m.group(1).endswith(":"):
                        part, alias = m.group(1), m.group(2)
                segs = [x for x in part.split("::") if x]
                if segs == ["self"]:
                    paths.append((prefix, alias))
                else:
                    paths.append((prefix + segs, alias))
        return paths

    return parse(tree, [])


class Module:
    def __init__(self, path, file, is_dir_mod):
        self.path = path  # ["raster", "context"]
        self.file = file
        self.is_dir_mod = is_dir_mod  # lib.rs, mod.rs, or foo.rs with a foo/ folder
        self.children = {}
        self.bindings = {}  # name -> absolute path (from `use`)
        self.globs = []  # absolute module paths glob-imported
        self.uses = []  # (abs path, is_pub, scope_path)
        self.code_paths = []  # abs paths named in code


def discover(src):
    mods = {}

    def load(path, file):
        is_dir = os.path.basename(file) in ("mod.rs", "lib.rs")
        if not is_dir and os.path.isdir(file[:-3]):
            is_dir = True
        m = Module(path, file, is_dir)
        mods[tuple(path)] = m
        text = strip(open(file, encoding="utf-8").read())
        m.text = text
        base = os.path.dirname(file) if os.path.basename(file) in ("mod.rs", "lib.rs") else file[:-3]
        for mm in re.finditer(r"^\s*(?:pub(?:\([^)]*\))?\s+)?mod\s+([a-z_][a-z0-9_]*)\s*;", text, re.M):
            name = mm.group(1)
            for cand in (os.path.join(base, name + ".rs"), os.path.join(base, name, "mod.rs")):
                if os.path.exists(cand):
                    m.children[name] = cand
                    load(path + [name], cand)
                    break
        return m

    load([], os.path.join(src, "lib.rs"))
    return mods


def scopes(text):
    """For each offset range, the inline module path (e.g. ['tests']) it lies in."""
    stack = []  # (name or None, depth at open)
    depth = 0
    marks = []  # (offset, tuple(inline path))
    pending = None
    for m in re.finditer(r"\bmod\s+([a-z_][a-z0-9_]*)\s*\{|[{}]", text):
        tok = m.group(0)
        if tok.startswith("mod"):
            depth += 1
            before = text[max(0, m.start() - 200):m.start()]
            before = re.split(r"[;{}]", before)[-1]
            name = m.group(1) + ("#test" if "cfg(test)" in before else "")
            stack.append((name, depth))
            marks.append((m.end(), tuple(s[0] for s in stack)))
        elif tok == "{":
            depth += 1
        else:
            if stack and stack[-1][1] == depth:
                stack.pop()
                marks.append((m.end(), tuple(s[0] for s in stack)))
            depth -= 1
    return marks


def scope_at(marks, offset):
    cur = ()
    for off, path in marks:
        if off > offset:
            break
        cur = path
    return list(cur)


def is_test(scope):
    return any(s.endswith("#test") for s in scope)


def absolute(mod, scope, segs):
    """An absolute path (list of names from the crate root) for a path written in `mod`
    inside inline module `scope`; None if it does not start at the crate or a module."""
    if not segs:
        return None
    here = mod.path + [s.split("#")[0] for s in scope]
    if segs[0] == "crate":
        return segs[1:]
    if segs[0] in ("super", "self"):
        cur = list(here)
        k = 0
        while k < len(segs) and segs[k] in ("super", "self"):
            if segs[k] == "super":
                if not cur:
                    return None
                cur = cur[:-1]
            k += 1
        return cur + segs[k:]
    if not scope and segs[0] in mod.children:
        return mod.path + segs
    return None


def parse_uses(mods):
    for mod in mods.values():
        text = mod.text
        marks = scopes(text)
        for m in re.finditer(r"(^|[;{}\]]\s*)((?:pub(?:\([^)]*\))?\s+)?)use\s+([^;]+);", text, re.M):
            scope = scope_at(marks, m.start(3))
            is_pub = bool(m.group(2).strip())
            for segs, alias in expand_use(m.group(3)):
                if segs and segs[0] == "::":
                    continue
                ab = absolute(mod, scope, segs)
                if ab is None:
                    continue
                if segs[-1] == "*":
                    if not scope:
                        mod.globs.append(ab[:-1])
                    mod.uses.append((ab[:-1], is_pub, scope))
                    continue
                if not scope:
                    mod.bindings[alias or ab[-1]] = ab
                mod.uses.append((ab, is_pub, scope))
        # Paths in code, outside `use` lines.
        code = re.sub(r"(?:pub(?:\([^)]*\))?\s+)?use\s+[^;]+;", lambda x: re.sub(r"[^\n]", " ", x.group(0)), text)
        for m in re.finditer(r"(?<![A-Za-z0-9_:])((?:crate|super)(?:\s*::\s*[A-Za-z_][A-Za-z0-9_]*)+)", code):
            segs = [s.strip() for s in m.group(1).split("::")]
            scope = scope_at(marks, m.start())
            ab = absolute(mod, scope, segs)
            if ab is not None:
                mod.code_paths.append((ab, scope))


def resolve(mods, path, seen=None):
    """The file an absolute path's item lives in (following `use` bindings)."""
    seen = seen or set()
    key = tuple(path)
    if key in seen:
        return None
    seen.add(key)
    k = len(path)
    while k >= 0 and tuple(path[:k]) not in mods:
        k -= 1
    if k < 0:
        return None
    mod = mods[tuple(path[:k])]
    rest = path[k:]
    if rest and rest[0] in mod.bindings:
        target = mod.bindings[rest[0]] + rest[1:]
        got = resolve(mods, target, seen)
        if got:
            return got
    if rest and rest[0] not in mod.bindings:
        # A glob re-export (`pub use child::*`) may hold it: look for its definition.
        for g in mod.globs:
            gm = mods.get(tuple(g))
            if gm and re.search(r"\b(fn|struct|enum|trait|type|const|static|mod)\s+" + re.escape(rest[0]) + r"\b", gm.text):
                got = resolve(mods, g + rest, seen)
                if got:
                    return got
    return mod.file


def build_edges(mods):
    edges = defaultdict(set)  # file -> {file}
    non_test = set()  # (file, file) made by code outside tests
    for mod in mods.values():
        named = [(ab, scope) for ab, is_pub, scope in mod.uses
                 # A re-export of the module's own items or children only forwards.
                 if not (is_pub and not scope and ab[:len(mod.path)] == mod.path)]
        for ab, scope in named + mod.code_paths:
            t = resolve(mods, ab)
            if t and t != mod.file:
                edges[mod.file].add(t)
                if not is_test(scope):
                    non_test.add((mod.file, t))
    return edges, non_test


def sccs(nodes, edges):
    index, low, on, stack, out = {}, {}, set(), [], []
    counter = [0]
    sys.setrecursionlimit(10000)

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(edges.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            out.append(sorted(comp))

    for v in sorted(nodes):
        if v not in index:
            visit(v)
    return [c for c in out if len(c) > 1]


def top(mods, file, src):
    rel = os.path.relpath(file, src)
    head = rel.split(os.sep)[0]
    return head[:-3] if head.endswith(".rs") else head


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--src", default=os.path.join(os.path.dirname(__file__), "..", "src"))
    ap.add_argument("--edges", action="store_true", help="print every edge")
    ap.add_argument("--all", action="store_true", help="with --edges, also edges inside one top-level module")
    ap.add_argument("--lib-only", action="store_true", help="leave out src/cli")
    args = ap.parse_args()
    src = os.path.normpath(args.src)
    mods = discover(src)
    parse_uses(mods)
    edges, non_test = build_edges(mods)
    tag = lambda a, b: "" if (a, b) in non_test else " (test)"
    rel = lambda f: os.path.relpath(f, src)
    files = {m.file for m in mods.values()}
    if args.lib_only:
        files = {f for f in files if top(mods, f, src) != "cli"}
        edges = {a: {b for b in bs if b in files} for a, bs in edges.items() if a in files}

    if args.edges:
        for a in sorted(edges):
            for b in sorted(edges[a]):
                if args.all or top(mods, a, src) != top(mods, b, src):
                    print(f"edge {rel(a)} -> {rel(b)}{tag(a, b)}")

    circles = sccs(files, edges)
    print(f"{len(files)} files, {sum(len(v) for v in edges.values())} edges")
    print(f"circles: {len(circles)}")
    for c in circles:
        print("  " + " <-> ".join(rel(f) for f in c))
        inner = [(a, b) for a in c for b in sorted(edges.get(a, ())) if b in c]
        for a, b in inner:
            print(f"      {rel(a)} -> {rel(b)}{tag(a, b)}")
    ups = []
    unplaced = set()
    for a in sorted(edges):
        ta = top(mods, a, src)
        for b in sorted(edges[a]):
            tb = top(mods, b, src)
            if ta in ("lib", "main") or tb in ("lib", "main"):
                continue
            if ta not in LAYERS:
                unplaced.add(ta)
                continue
            if tb not in LAYERS:
                unplaced.add(tb)
                continue
            if LAYERS[tb] > LAYERS[ta]:
                ups.append((a, b))
    print(f"imports up: {len(ups)}")
    for a, b in ups:
        print(f"  {rel(a)} -> {rel(b)}{tag(a, b)}")
    folders = defaultdict(set)
    for a in edges:
        for b in edges[a]:
            ta, tb = top(mods, a, src), top(mods, b, src)
            if ta != tb and "lib" not in (ta, tb):
                folders[ta].add(tb)
    folder_circles = sccs(set(folders) | {t for v in folders.values() for t in v}, folders)
    print(f"folder circles: {len(folder_circles)}")
    for c in folder_circles:
        print("  " + " <-> ".join(c))
        for a in c:
            for b in sorted(folders[a]):
                if b in c:
                    which = [f"{rel(x)} -> {rel(y)}{tag(x, y)}" for x in sorted(edges) for y in sorted(edges[x])
                             if top(mods, x, src) == a and top(mods, y, src) == b]
                    print(f"      {a} -> {b}: " + ", ".join(which))
    if unplaced:
        print("top-level modules without a layer: " + ", ".join(sorted(unplaced)))
    return 1 if circles or ups or folder_circles else 0


if __name__ == "__main__":
    sys.exit(main())
