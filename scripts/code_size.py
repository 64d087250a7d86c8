#!/usr/bin/env python3
"""The house's size: lines per room and the longest functions in product code.

Usage: scripts/code_size.py [--top N] [--rev REV]

Lines are counted per room (every line of every .h/.cpp, comments and blank lines included, as
`wc -l` does). Functions are found by universal-ctags (function definitions with their end
line), so a function's length is its definition's first line to its closing brace. Product code
is every room except tests/, benchmarks/ and tools/. With --rev, the numbers are those of that
commit (read through `git show`, the working tree untouched), so a change can be measured
before and after:

    scripts/code_size.py --rev 5a51887 > before.txt; scripts/code_size.py > after.txt
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

PRODUCT_ROOMS = ["geometry", "materials", "renderer", "image", "scenes", "apps", "python"]
ALL_ROOMS = PRODUCT_ROOMS + ["tests", "benchmarks", "tools"]


def source_files(root, rev):
    args = ["git", "-C", root, "ls-tree", "-r", "--name-only", rev] if rev else \
        ["git", "-C", root, "ls-files"]
    names = subprocess.run(args, check=True, capture_output=True, text=True).stdout.split()
    return [n for n in names if n.endswith((".h", ".cpp")) and n.split("/")[0] in ALL_ROOMS]


def read(root, rev, name):
    if rev:
        return subprocess.run(["git", "-C", root, "show", f"{rev}:{name}"], check=True,
                              capture_output=True, text=True).stdout
    with open(os.path.join(root, name), encoding="utf-8") as f:
        return f.read()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--top", type=int, default=10)
    parser.add_argument("--rev", default=None)
    args = parser.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

    files = source_files(root, args.rev)
    lines = {room: 0 for room in ALL_ROOMS}
    functions = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in files:
            text = read(root, args.rev, name)
            lines[name.split("/")[0]] += text.count("\n")
            if name.split("/")[0] not in PRODUCT_ROOMS:
                continue
            path = os.path.join(tmp, name)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "w", encoding="utf-8") as f:
                f.write(text)
        out = subprocess.run(
            ["ctags", "-R", "--languages=C++", "--langmap=C++:+.h", "--kinds-C++=f",
             "--fields=+ne", "--output-format=json", "-o", "-", "."],
            cwd=tmp, check=True, capture_output=True, text=True).stdout
    for line in out.splitlines():
        tag = json.loads(line)
        if "end" not in tag:
            continue
        scope = tag.get("scope", "").replace("glint::", "")
        scope = "" if scope.startswith("__anon") else scope
        name = f"{scope.split('::')[-1]}::{tag['name']}" if scope and "__anon" not in scope \
            else tag["name"]
        functions.append((tag["end"] - tag["line"] + 1, name, f"{tag['path']}:{tag['line']}"))

    label = args.rev or "working tree"
    print(f"# code size at {label}")
    print("\n| room | lines |\n|---|---|")
    for room in ALL_ROOMS:
        print(f"| {room}/ | {lines[room]:,} |")
    product = sum(lines[r] for r in PRODUCT_ROOMS)
    print(f"| product ({', '.join(PRODUCT_ROOMS)}) | {product:,} |")
    print(f"| all | {sum(lines.values()):,} |")
    print(f"\n| longest functions (product code) | lines | where |\n|---|---|---|")
    for length, name, where in sorted(functions, key=lambda f: (-f[0], f[2]))[:args.top]:
        print(f"| `{name}` | {length} | {where.lstrip('./')} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
