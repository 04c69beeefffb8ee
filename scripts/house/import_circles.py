#!/usr/bin/env python3
"""Finds files of a Rust crate that import each other in a circle.

Usage: import_circles.py CRATE_SRC_DIR...   (exit 0: none; 1: circles, printed; 2: bad use)

A file imports another when one of its file-level `use` lines names an item of the other
(`crate::a::b::X`, `super::X`, `self::x::Y` or a child module `x::Y` from a `mod.rs`): the
target is the longest module path that is a file, followed through `pub use` re-exports to
the file that defines the name. Inline modules (an indented `use`, e.g. `mod tests`) are
not the file's own imports; a path written out in the code (`crate::a::X` in a type or a
call, outside `#[cfg(test)] mod ...`) is. The circles are the strongly connected components of that
graph with more than one file (Tarjan). It reads the source text with regular expressions,
not a Rust parser: good enough for this workspace's style (one `use` per statement, no
macros generating imports), which `tests/python/test_house.py` checks on every crate.
"""

import os
import re
import sys

ITEM = r"\b(struct|enum|fn|const|static|trait|type|mod|macro_rules!)\s+"


def read_crate(root):
    files = {}
    for d, _, names in os.walk(root):
        for f in names:
            if f.endswith(".rs"):
                p = os.path.relpath(os.path.join(d, f), root)
                with open(os.path.join(d, f), encoding="utf-8") as fh:
                    files[p.replace(os.sep, "/")] = re.sub(r"//[^\n]*", "", fh.read())
    return files


def module_path(p):
    parts = p[:-3].split("/")
    if parts[-1] in ("mod", "lib", "main"):
        parts = parts[:-1]
    return tuple(parts)


def expand(s):
    """`a::{b, c::{d, e}}` -> [`a::b`, `a::c::d`, `a::c::e`]."""
    s = s.strip()
    m = re.match(r"^(.*?)\{(.*)\}$", s, re.S)
    if not m:
        return [s]
    pre, inner = m.group(1), m.group(2)
    parts, depth, cur = [], 0, ""
    for ch in inner:
        depth += ch == "{"
        depth -= ch == "}"
        if ch == "," and depth == 0:
            parts.append(cur)
            cur = ""
        else:
            cur += ch
    if cur.strip():
        parts.append(cur)
    return [q for part in parts for q in expand(pre + part.strip())]


def circles(root):
    files = read_crate(root)
    by_module = {module_path(p): p for p in files}

    def resolve(segs):
        for k in range(len(segs), -1, -1):
            if tuple(segs[:k]) in by_module:
                return by_module[tuple(segs[:k])]
        return None

    def base_of(me, segs):
        if segs[0] == "crate":
            return [], segs[1:]
        if segs[0] == "super":
            base = list(me)
            while segs and segs[0] == "super":
                base, segs = base[:-1], segs[1:]
            return base, segs
        if segs[0] == "self":
            return list(me), segs[1:]
        if tuple(list(me) + [segs[0]]) in by_module:
            return list(me), segs
        return None, None

    def clean(path):
        path = re.sub(r"\s+as\s+\w+$", "", path.strip())
        return re.sub(r"\s+", "", path)

    reexports = {}
    for p, text in files.items():
        for m in re.finditer(r"\bpub(?:\([^)]*\))?\s+use\s+([^;]+);", text):
            for path in expand(m.group(1)):
                segs = clean(path).split("::")
                base, rest = base_of(module_path(p), segs)
                if base is None:
                    continue
                target = resolve(base + rest)
                if target and target != p:
                    reexports.setdefault(p, {})[segs[-1]] = target

    def defines(f, name):
        return re.search(ITEM + re.escape(name) + r"\b", files[f]) is not None

    def imports(p, me, path):
        """The files a `use` path (or a path written out in code) of file `p` imports."""
        base, rest = base_of(me, clean(path).split("::"))
        if base is None:
            return set()
        rest = [s for s in rest if s not in ("*", "self")]
        target = resolve(base + rest)
        found = set()
        for _ in range(10):
            if not (target and rest):
                break
            name = rest[-1]
            if name in reexports.get(target, {}) and not defines(target, name):
                # A reader following the path opens the re-exporting file first: the
                # path through it counts as an import of it too.
                found.add(target)
                target = reexports[target][name]
            else:
                break
        found.add(target)
        return {t for t in found if t and t != p}

    edges = {p: set() for p in files}
    for p, text in files.items():
        me = module_path(p)
        for m in re.finditer(r"(?m)^([ \t]*)(?:pub(?:\([^)]*\))?\s+)?use\s+([^;]+);", text):
            if m.group(1):
                continue
            for path in expand(m.group(2)):
                edges[p] |= imports(p, me, path)
        # A path written out in the code (`crate::wind::WindSpec` in a field's type) is an
        # import too, outside the file's test module.
        code = re.split(r"(?m)^#\[cfg\(test\)\]\s*\n\s*mod\s+\w+", text)[0]
        code = re.sub(r"\bpub\(in\s+[\w:]+\)", "pub", code)  # visibility, not a path
        for m in re.finditer(r"(?<![\w:])((?:crate|super)(?:::\w+)+)", code):
            edges[p] |= imports(p, me, m.group(1))

    index, low, stack, on, found, counter = {}, {}, [], set(), [], [0]
    sys.setrecursionlimit(10000)

    def connect(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(edges[v]):
            if w not in index:
                connect(w)
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
            if len(comp) > 1:
                found.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            connect(v)
    return found


def main(argv):
    if len(argv) < 2:
        print(__doc__.splitlines()[2], file=sys.stderr)
        return 2
    bad = 0
    for root in argv[1:]:
        if not os.path.isdir(root):
            print(f"{root}: not a directory", file=sys.stderr)
            return 2
        for comp in circles(root):
            bad += 1
            print(f"{root}: files importing each other: {', '.join(comp)}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
