#!/usr/bin/env python3
"""Pairs of files in one crate whose code refers to each other (`use crate::x`, `super::x` or a
`crate::x::Y` path in code; comments, `#[cfg(test)] mod tests` and a module's own parent
`mod.rs`/`lib.rs` left out). The workspace keeps none: a shared item moves into the lower file
or a leaf module of its own.

    python3 scripts/import-circles.py        # prints each pair, then `pairs N`; exit 1 if N > 0
"""
import itertools
import os
import re
import sys


def module_file(root, path):
    for cand in (os.path.join(root, *path) + ".rs", os.path.join(root, *path, "mod.rs")):
        if os.path.exists(cand):
            return cand
    return None


def module_path(root, f):
    rel = os.path.relpath(f, root)[:-3].split(os.sep)
    return rel[:-1] if rel[-1] in ("mod", "lib", "main") else rel


def references(root, f):
    text = open(f, encoding="utf-8").read()
    text = re.sub(r"//[^\n]*", "", text)
    text = re.sub(r"#\[cfg\(test\)\]\s*mod tests\s*\{.*", "", text, flags=re.S)
    here = module_path(root, f)
    deps = set()
    for m in re.finditer(r"\b(crate|super)((?:::\w+)+)", text):
        segs = m.group(2).split("::")[1:]
        base = [] if m.group(1) == "crate" else here[:-1]
        path = base + segs
        for k in range(len(path), 0, -1):
            target = module_file(root, path[:k])
            if target:
                if target != f:
                    deps.add(target)
                break
    return deps


def main():
    pairs = 0
    for crate in sorted(os.listdir("crates")):
        root = f"crates/{crate}/src"
        if not os.path.isdir(root):
            continue
        files = [os.path.join(d, n) for d, _, ns in os.walk(root) for n in ns if n.endswith(".rs")]
        edges = {f: references(root, f) for f in files}
        for a, b in itertools.combinations(files, 2):
            if not (b in edges[a] and a in edges[b]):
                continue
            parentish = any(x.endswith(("mod.rs", "lib.rs")) for x in (a, b))
            if parentish and (os.path.dirname(a) == os.path.dirname(b) or any(x.endswith("lib.rs") for x in (a, b))):
                continue
            print(crate, os.path.relpath(a, root), "<->", os.path.relpath(b, root))
            pairs += 1
    print("pairs", pairs)
    return 1 if pairs else 0


if __name__ == "__main__":
    sys.exit(main())
