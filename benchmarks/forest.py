#!/usr/bin/env python3
"""A forest of GPU-instanced trees (EXT_mesh_gpu_instancing): how long glint takes to load and
render N instances of one small mesh, and how much memory it holds.

    python3 benchmarks/forest.py [--glint build-rel/glint] [--count 100000] [--runs 3]

Writes the scene to $TMPDIR/glint_forest/forest.gltf (one tree of 2 x SEGMENTS triangles: a
cone crown on a trunk; instances on a jittered grid with random turns and sizes), then times
`glint info` (load only) and `glint render` (load, build, 640x360 at 4 spp, path tracer, the
default studio light) RUNS times each with /usr/bin/time, and prints wall time and peak
resident memory (min, median, max). Nothing is written into the repository.
"""
import argparse
import base64
import json
import math
import os
import random
import struct
import tempfile

from process_timing import spread, timed

SEGMENTS = 24


def tree():
    """Positions and indices of a tree 1 unit tall: a closed trunk cylinder and a crown cone."""
    pos, idx = [], []

    def ring(y, r):
        start = len(pos)
        for i in range(SEGMENTS):
            a = 2 * math.pi * i / SEGMENTS
            pos.append((r * math.cos(a), y, -r * math.sin(a)))
        return start

    def side(lower, upper):  # quads between two rings, wound outwards
        for i in range(SEGMENTS):
            j = (i + 1) % SEGMENTS
            idx.extend([lower + i, lower + j, upper + j, lower + i, upper + j, upper + i])

    trunk0, trunk1 = ring(0.0, 0.05), ring(0.3, 0.05)
    side(trunk0, trunk1)
    crown = ring(0.25, 0.3)
    tip = len(pos)
    pos.append((0.0, 1.0, 0.0))
    for i in range(SEGMENTS):
        idx.extend([crown + i, crown + (i + 1) % SEGMENTS, tip])
    centre = len(pos)
    pos.append((0.0, 0.25, 0.0))
    for i in range(SEGMENTS):  # the crown's underside
        idx.extend([crown + (i + 1) % SEGMENTS, crown + i, centre])
    return pos, idx


def forest(count, seed=1):
    rng = random.Random(seed)
    pos, idx = tree()
    side = math.ceil(math.sqrt(count))
    t, r, s = [], [], []
    for k in range(count):
        gx, gz = k % side, k // side
        t.append((gx - side / 2 + rng.uniform(-0.3, 0.3), 0.0, gz - side / 2 + rng.uniform(-0.3, 0.3)))
        a = rng.uniform(0, math.pi)
        r.append((0.0, math.sin(a), 0.0, math.cos(a)))
        h = rng.uniform(0.6, 1.4)
        s.append((h, h, h))
    chunks, views, accessors = [], [], []
    offset = 0

    def add(fmt, values, ctype, atype, n, **extra):
        nonlocal offset
        data = struct.pack("<" + fmt * len(values), *values)
        data += b"\0" * (-len(data) % 4)
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(data)})
        chunks.append(data)
        offset += len(data)
        a = {"bufferView": len(views) - 1, "componentType": ctype, "count": n, "type": atype}
        a.update(extra)
        accessors.append(a)
        return len(accessors) - 1

    flat = lambda rows: [c for row in rows for c in row]
    p = add("f", flat(pos), 5126, "VEC3", len(pos),
            min=[min(v[i] for v in pos) for i in range(3)], max=[max(v[i] for v in pos) for i in range(3)])
    i = add("I", idx, 5125, "SCALAR", len(idx))
    ta = add("f", flat(t), 5126, "VEC3", count)
    ra = add("f", flat(r), 5126, "VEC4", count)
    sa = add("f", flat(s), 5126, "VEC3", count)
    ground = [(-side / 2 - 1, 0, -side / 2 - 1), (side / 2 + 1, 0, -side / 2 - 1),
              (side / 2 + 1, 0, side / 2 + 1), (-side / 2 - 1, 0, side / 2 + 1)]
    g = add("f", flat(ground), 5126, "VEC3", 4, min=list(ground[0]), max=list(ground[2]))
    gi = add("I", [0, 2, 1, 0, 3, 2], 5125, "SCALAR", 6)
    data = b"".join(chunks)
    eye = [0, 6, side / 2 + 4]
    return {
        "asset": {"version": "2.0", "generator": "glint benchmarks/forest.py"},
        "extensionsUsed": ["EXT_mesh_gpu_instancing"],
        "extensionsRequired": ["EXT_mesh_gpu_instancing"],
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [
            {"name": "trees", "mesh": 0, "extensions": {"EXT_mesh_gpu_instancing": {
                "attributes": {"TRANSLATION": ta, "ROTATION": ra, "SCALE": sa}}}},
            {"name": "ground", "mesh": 1},
            # A camera at eye height over the edge of the forest, looking across it.
            {"name": "camera", "camera": 0, "translation": eye,
             "rotation": [-math.sin(math.radians(12)), 0, 0, math.cos(math.radians(12))]},
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.05}}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.15, 0.35, 0.12, 1],
                                                "metallicFactor": 0}},
                      {"pbrMetallicRoughness": {"baseColorFactor": [0.35, 0.3, 0.22, 1],
                                                "metallicFactor": 0}}],
        "meshes": [{"name": "tree", "primitives": [{"attributes": {"POSITION": p}, "indices": i,
                                                    "material": 0}]},
                   {"name": "ground", "primitives": [{"attributes": {"POSITION": g},
                                                      "indices": gi, "material": 1}]}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(data), "uri": "forest.bin"}],
    }, data, len(idx) // 3


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--glint", default="build-rel/glint")
    ap.add_argument("--count", type=int, default=100000)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--out", default=os.path.join(tempfile.gettempdir(), "glint_forest"))
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    doc, data, triangles = forest(args.count)
    gltf = os.path.join(args.out, "forest.gltf")
    with open(gltf, "w") as f:
        json.dump(doc, f)
    with open(os.path.join(args.out, "forest.bin"), "wb") as f:
        f.write(data)
    print(f"forest: {args.count} instances of a {triangles}-triangle tree "
          f"({args.count * triangles:,} triangles in the world), {args.runs} runs, "
          f"min / median / max")
    for name, cmd in [
        ("glint info", [args.glint, "info", gltf]),
        ("glint render 640x360, 4 spp", [args.glint, "render", gltf, "--width", "640", "--height",
                                         "360", "--spp", "4", "--quiet", "-o",
                                         os.path.join(args.out, "forest.png")]),
    ]:
        runs = [timed(cmd) for _ in range(args.runs)]
        print(f"- {name}: {spread([w for w, _ in runs], 's')}, "
              f"peak RSS {spread([m for _, m in runs], 'MB')}")


if __name__ == "__main__":
    main()
