#!/usr/bin/env python3
"""Prints the longest functions of the C++ sources under the given folders
(default: Rendering/), tests left out, longest first: lines from the
signature's first line to the closing brace.

usage: scripts/function-lengths.py [FOLDER...] [--top N] [--max LINES]

--max LINES: exit 1 when a function is longer (the architecture's limit,
about 100 lines for Rendering/).

Reads the project's clang-format layout (braces on their own lines): a
function body is a '{' alone on a line, at the indentation of the signature
above it, and ends at the next '}' at that indentation. Control statements,
classes, namespaces, initialiser lists of data and lambdas are not functions.
"""
import argparse
import pathlib
import re
import sys

NOT_FUNCTIONS = re.compile(
    r"^\s*(if|else|for|while|switch|do|try|catch|namespace|class|struct|enum|union|case|default"
    r"|return|extern)\b"
)


def functions(path):
    lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
    for i, line in enumerate(lines):
        if line.strip() != "{" or i == 0:
            continue
        indent = len(line) - len(line.lstrip())
        # The signature: the lines above, back to one at the same indentation.
        start = i - 1
        while start > 0 and (len(lines[start]) - len(lines[start].lstrip()) > indent
                             or not lines[start].strip()):
            start -= 1
        signature = " ".join(l.strip() for l in lines[start:i])
        if NOT_FUNCTIONS.match(lines[start]) or "(" not in signature:
            continue
        if signature.rstrip().endswith(("=", ",", "[&]", "[=]")) or "= [" in signature:
            continue
        end = i + 1
        while end < len(lines) and not (lines[end].startswith(" " * indent + "}")
                                        and len(lines[end]) - len(lines[end].lstrip()) == indent):
            end += 1
        name = re.sub(r"\s*\(.*", "", signature).split()[-1] if signature else "?"
        yield end - start + 1, name, start + 1


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("folders", nargs="*", default=["Rendering"])
    parser.add_argument("--top", type=int, default=10)
    parser.add_argument("--max", type=int, default=0)
    args = parser.parse_args()
    root = pathlib.Path(__file__).resolve().parent.parent
    found = []
    for folder in args.folders:
        for path in sorted((root / folder).rglob("*")):
            if path.suffix not in (".cxx", ".h") or "Testing" in path.parts:
                continue
            for length, name, line in functions(path):
                found.append((length, name, f"{path.relative_to(root)}:{line}"))
    found.sort(reverse=True)
    print(f"{'lines':>6}  function  (file:line)")
    for length, name, where in found[: args.top]:
        print(f"{length:>6}  {name}  ({where})")
    if args.max and found and found[0][0] > args.max:
        print(f"longest function {found[0][0]} lines > {args.max}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
