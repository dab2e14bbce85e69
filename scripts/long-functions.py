#!/usr/bin/env python3
"""Count the long functions of the workspace's non-test Rust code.

    scripts/long-functions.py [--over N] [--list] [PATH ...]

A function's length is its lines from the line of `fn` to the line of the brace that closes its
body (signature, doc-less body and closing brace; its doc comment and attributes are not
counted). Bodies are found by brace matching on the source with comments, strings, raw strings
and character literals taken out, so a brace in a message or a comment does not count.

Non-test code: every `.rs` file under `crates/*/src` and `python/src` (default PATH), without
`#[cfg(test)]` items (test modules and test-only functions) and without the `tests/`,
`benches/` and `examples/` folders. Functions nested in a function are counted on their own
and also inside the one that holds them.

Prints how many functions are over 80 and over 120 lines (the workspace's targets: at most 25
and 5, docs/architecture.md) and, with --list, each one over --over (default 80) lines, longest
first, as `lines path:line name`.
"""

import argparse
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_PATHS = ["crates", "python/src"]
SKIPPED_FOLDERS = {"tests", "benches", "examples", "target"}


def blank_out(text):
    """`text` with comments, string, raw-string and char literals replaced by spaces (newlines
    kept), so that braces can be matched and lines still count."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        nxt = text[i + 1] if i + 1 < n else ""
        if c == "/" and nxt == "/":
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif c == "/" and nxt == "*":
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
        elif c == "r" and re.match(r'r#*"', text[i:]) and not (i and (text[i - 1].isalnum() or text[i - 1] == "_")):
            hashes = re.match(r'r(#*)"', text[i:]).group(1)
            end = text.find('"' + hashes, i + 2 + len(hashes))
            j = n if end < 0 else end + 1 + len(hashes)
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            j += 1
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == "'":
            m = re.match(r"'(\\.[^']*|[^\\'])'", text[i:])
            if m:
                out.append(" " * len(m.group(0)))
                i += len(m.group(0))
            else:  # a lifetime or a label
                out.append(c)
                i += 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def matching_brace(code, open_at):
    """Index of the brace that closes the one at `open_at`."""
    depth = 0
    for j in range(open_at, len(code)):
        if code[j] == "{":
            depth += 1
        elif code[j] == "}":
            depth -= 1
            if depth == 0:
                return j
    return len(code) - 1


CFG_TEST = re.compile(r"#\[cfg\(test\)\]")
FN = re.compile(r"\bfn\s+([A-Za-z_][A-Za-z0-9_]*)")


def test_spans(code):
    """Character spans of `#[cfg(test)]` items: from the attribute to the end of the item."""
    spans = []
    for m in CFG_TEST.finditer(code):
        j = m.end()
        while j < len(code) and code[j] not in "{;":
            j += 1
        end = matching_brace(code, j) if j < len(code) and code[j] == "{" else j
        spans.append((m.start(), end))
    return spans


def functions(path):
    """(name, first line, lines) of every non-test function with a body in `path`."""
    text = path.read_text(encoding="utf-8")
    code = blank_out(text)
    skip = test_spans(code)
    found = []
    for m in FN.finditer(code):
        if any(a <= m.start() <= b for a, b in skip):
            continue
        j = m.end()
        depth = 0  # parentheses and angle-free scan to the body or the `;` of a declaration
        while j < len(code):
            ch = code[j]
            if ch in "([":
                depth += 1
            elif ch in ")]":
                depth -= 1
            elif depth == 0 and ch in "{;":
                break
            j += 1
        if j >= len(code) or code[j] == ";":
            continue
        end = matching_brace(code, j)
        first = code.count("\n", 0, m.start()) + 1
        last = code.count("\n", 0, end) + 1
        found.append((m.group(1), first, last - first + 1))
    return found


def source_files(paths):
    for p in paths:
        p = (ROOT / p) if not Path(p).is_absolute() else Path(p)
        files = [p] if p.is_file() else sorted(p.rglob("*.rs"))
        for f in files:
            rel = f.relative_to(ROOT)
            if SKIPPED_FOLDERS & set(rel.parts[:-1]):
                continue
            # crates/<name>/src/… only (build scripts and crate-level tests are not library code)
            if rel.parts[0] == "crates" and (len(rel.parts) < 3 or rel.parts[2] != "src"):
                continue
            yield f, rel


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("paths", nargs="*", default=DEFAULT_PATHS)
    parser.add_argument("--over", type=int, default=80)
    parser.add_argument("--list", action="store_true")
    args = parser.parse_args()
    rows = []
    for f, rel in source_files(args.paths):
        for name, line, lines in functions(f):
            rows.append((lines, f"{rel}:{line}", name))
    rows.sort(key=lambda r: (-r[0], r[1]))
    over_80 = sum(1 for r in rows if r[0] > 80)
    over_120 = sum(1 for r in rows if r[0] > 120)
    print(f"{len(rows)} functions; {over_80} over 80 lines, {over_120} over 120 lines")
    if args.list:
        for lines, where, name in rows:
            if lines > args.over:
                print(f"{lines:5d} {where} {name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
