#!/usr/bin/env python3
"""Functions longer than a screen (60 lines, signature to closing brace) in Lava's sources:
src/, include/, python/, fuzz/, examples/ (C++) and shaders/ (GLSL). Tests are not counted.

A function body is a brace block whose opening follows a closing parenthesis (with
qualifiers, a trailing return type or a constructor's initialiser list between), at the
scope of a namespace, a class or the file; lambdas and blocks inside it count as its lines.
Strings, characters and comments are skipped.

Usage: long_functions.py ROOT [--limit N] [--allow FILE]
  --allow FILE: the known ones, "path:name lines" each; the run fails (exit 1) when a function
  not listed is over the limit or a listed one grew, and says which listed ones are gone or
  shorter (so the list only shrinks)."""
import argparse
import os
import re
import sys

ROOTS = ("src", "include", "python", "fuzz", "examples", "shaders")
SUFFIXES = (".cpp", ".h", ".hpp", ".comp", ".glsl", ".vert", ".frag")


def strip(text):
    """The text with comments, strings and character literals blanked (lines kept)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("".join(ch if ch == "\n" else " " for ch in text[i:j]))
            i = j
        elif text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            if not m:
                out.append(c)
                i += 1
                continue
            end = text.find(")" + m.group(1) + '"', i)
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append("".join(ch if ch == "\n" else " " for ch in text[i:j]))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append("".join(ch if ch == "\n" else " " for ch in text[i:j + 1]))
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


# What may stand between a function's ")" and its "{": qualifiers, a trailing return type,
# or a constructor's initialiser list.
BETWEEN = re.compile(r"^\)\s*(const|override|final|noexcept(\([^)]*\))?|mutable|->\s*[\w:<>,\s*&]+|\s)*"
                     r"(:\s*[\s\S]*)?$")
NAME = re.compile(r"([~\w:]+|operator\s*[^\s(]+)\s*\($")


def functions(path):
    """(name, first line, line count) of each function body in the file."""
    text = strip(open(path, encoding="utf-8", errors="replace").read())
    found, stack = [], []  # stack: (is_function_or_inside, start line, name)
    line = 1
    for i, c in enumerate(text):
        if c == "\n":
            line += 1
        elif c == "{":
            inside = any(f for f, _, _ in stack)
            if inside:
                stack.append((True, line, None))
                continue
            base = max(0, i - 2000)
            before = text[base:i]
            close = before.rfind(")")
            name, start = None, line
            if close >= 0 and BETWEEN.match(before[close:]) and not re.search(r"[;{}]", before[close:]):
                depth, j = 0, close
                while j >= 0:  # the matching "("
                    depth += {")": 1, "(": -1}.get(before[j], 0)
                    if depth == 0:
                        break
                    j -= 1
                m = NAME.search(before[:j + 1]) if j >= 0 else None
                for _ in range(64):  # a constructor's initialiser: back to its own ")"
                    if not m or not re.search(r"(,|[^:]:)\s*$", before[:m.start(1)]):
                        break
                    close = before.rfind(")", 0, m.start(1))
                    depth, j = 0, close
                    while j >= 0:
                        depth += {")": 1, "(": -1}.get(before[j], 0)
                        if depth == 0:
                            break
                        j -= 1
                    m = NAME.search(before[:j + 1]) if close >= 0 and j >= 0 else None
                if m and m.group(1).split("::")[-1] not in ("if", "for", "while", "switch", "catch"):
                    name = m.group(1)
                    start = text.count("\n", 0, base + m.start(1)) + 1  # the signature's line
            stack.append((name is not None, start, name))
        elif c == "}" and stack:
            is_function, start, name = stack.pop()
            if name is not None:
                found.append((name, start, line - start + 1))
    return found


def main():
    parser = argparse.ArgumentParser(usage=__doc__)
    parser.add_argument("root")
    parser.add_argument("--limit", type=int, default=60)
    parser.add_argument("--allow")
    args = parser.parse_args()
    long = {}
    for top in ROOTS:
        for folder, _, names in os.walk(os.path.join(args.root, top)):
            for file in sorted(names):
                if not file.endswith(SUFFIXES):
                    continue
                path = os.path.join(folder, file)
                rel = os.path.relpath(path, args.root)
                for name, start, count in functions(path):
                    if count > args.limit:
                        long[f"{rel}:{name}"] = max(count, long.get(f"{rel}:{name}", 0))
    allowed = {}
    if args.allow:
        for row in open(args.allow, encoding="utf-8"):
            row = row.split("#", 1)[0].strip()
            if row:
                key, count = row.rsplit(" ", 1)
                allowed[key] = int(count)
    failed = False
    for key, count in sorted(long.items(), key=lambda kv: -kv[1]):
        if key not in allowed:
            print(f"FAIL: {key} is {count} lines (over {args.limit}, not in the list)")
            failed = True
        elif count > allowed[key]:
            print(f"FAIL: {key} grew to {count} lines (listed at {allowed[key]})")
            failed = True
        else:
            print(f"{key} {count}")
    for key, count in sorted(allowed.items()):
        if long.get(key, 0) < count:
            print(f"note: {key} is now {long.get(key, 0) or 'within the limit'} "
                  f"(listed at {count}): shrink the list")
    print(f"long_functions: {len(long)} over {args.limit} lines, {len(allowed)} listed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
