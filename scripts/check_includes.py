#!/usr/bin/env python3
"""The house's include order: rooms include only rooms below them, and no header cycles.

The product's rooms, lowest first (docs/layout.md):

    geometry -> materials -> renderer -> image -> scenes -> apps | python

A file in a room may include its own room and the rooms before it, never one after it, and
no product file includes from tests/, benchmarks/ or tools/. apps/ (the command line) and
python/ (the Python module) both sit on top of scenes/, side by side: neither includes the
other. Within and across rooms, no
header may reach itself through its includes (a cycle makes the order a matter of
`#pragma once` luck). Only quoted includes of project paths ("room/file.h") count; system
headers are not the house's.

    python3 scripts/check_includes.py        # from anywhere; exit 1 listing each violation

.ci/run runs it first (scripts/test.sh), before anything is built.
"""
import os
import re
import sys

ROOMS = ["geometry", "materials", "renderer", "image", "scenes", "apps", "python"]
# Rooms of the same rank sit side by side (the top two).
RANK = {"geometry": 0, "materials": 1, "renderer": 2, "image": 3, "scenes": 4, "apps": 5,
        "python": 5}
NOT_PRODUCT = ["tests", "benchmarks", "tools"]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
SOURCES = (".h", ".cpp", ".inc")


def product_files(root):
    for room in ROOMS:
        for folder, _, names in os.walk(os.path.join(root, room)):
            for name in sorted(names):
                if name.endswith(SOURCES):
                    yield room, os.path.relpath(os.path.join(folder, name), root)


def includes(root, path):
    """(line number, included path) of each quoted include of a project path in `path`."""
    out = []
    with open(os.path.join(root, path), errors="replace") as f:
        for number, line in enumerate(f, 1):
            m = INCLUDE.match(line)
            if m:
                out.append((number, m.group(1)))
    return out


def order_violations(root):
    rank = RANK
    found = []
    for room, path in product_files(root):
        for number, target in includes(root, path):
            top = target.split("/")[0]
            if top in rank and (rank[top] > rank[room] or (rank[top] == rank[room] and top != room)):
                found.append(f"{path}:{number}: includes {target}: {top}/ is not below {room}/ "
                             f"(geometry -> materials -> renderer -> image -> scenes -> "
                             f"apps | python)")
            elif top in NOT_PRODUCT:
                found.append(f"{path}:{number}: includes {target}: product code includes "
                             f"nothing from {top}/")
    return found


def header_cycles(root):
    """Cycles among the project's headers, each reported once (as its smallest rotation)."""
    graph = {}
    for _, path in product_files(root):
        if path.endswith(".h"):
            graph[path] = [t for _, t in includes(root, path)
                           if os.path.isfile(os.path.join(root, t)) and t.endswith(".h")]
    cycles, state, stack = set(), {}, []

    def visit(node):
        state[node] = "open"
        stack.append(node)
        for nxt in graph.get(node, []):
            if state.get(nxt) == "open":
                cycle = stack[stack.index(nxt):]
                i = cycle.index(min(cycle))
                cycles.add(tuple(cycle[i:] + cycle[:i]))
            elif nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = "done"

    for node in sorted(graph):
        if node not in state:
            visit(node)
    return [" -> ".join(c + (c[0],)) for c in sorted(cycles)]


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    problems = order_violations(root) + [f"header cycle: {c}" for c in header_cycles(root)]
    for p in problems:
        print(p)
    if problems:
        print(f"check_includes: {len(problems)} include(s) run against the house's order "
              "(docs/layout.md)", file=sys.stderr)
        return 1
    print(f"check_includes: the rooms include only rooms below them, no header cycles "
          f"({sum(1 for _ in product_files(root))} files)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
