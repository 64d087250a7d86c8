#!/usr/bin/env python3
"""A DamagedHelmet-like GLB for the loading benchmark, made from nothing but this script and
oiiotool: a UV sphere of about 14,500 triangles (DamagedHelmet has 14,556) with positions,
normals and texture coordinates, and a metal-rough material with five 2048x2048 JPEG textures
embedded in the GLB's binary chunk (base colour, metallic-roughness, normal, occlusion,
emission), as the Khronos sample has. The Khronos file itself is not in ../shared/assets.

    python3 benchmarks/make_helmet.py OUT.glb
"""
import json
import math
import os
import struct
import subprocess
import sys
import tempfile

SIZE = 2048
RINGS, SEGMENTS = 61, 120  # 2 * 60 * 120 = 14,400 triangles


def jpeg(path, pattern, channels=3):
    """A SIZE x SIZE JPEG of an oiiotool pattern (noise keeps the file realistically large)."""
    subprocess.run(["oiiotool", "--pattern", pattern, f"{SIZE}x{SIZE}", str(channels),
                    "--pattern", "noise:type=uniform:min=0:max=0.25", f"{SIZE}x{SIZE}",
                    str(channels), "--add", "--clamp:min=0:max=1", "-d", "uint8",
                    "--attrib", "Compression", "jpeg:90", "-o", path], check=True)
    with open(path, "rb") as f:
        return f.read()


def sphere():
    pos, nrm, uv, idx = [], [], [], []
    for r in range(RINGS):
        v = r / (RINGS - 1)
        theta = math.pi * v
        for s in range(SEGMENTS + 1):
            u = s / SEGMENTS
            phi = 2 * math.pi * u
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
            pos.append(n)
            nrm.append(n)
            uv.append((u, v))
    for r in range(RINGS - 1):
        for s in range(SEGMENTS):
            a = r * (SEGMENTS + 1) + s
            b = a + SEGMENTS + 1
            idx.extend([a, b, a + 1, a + 1, b, b + 1])
    return pos, nrm, uv, idx


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "helmet.glb"
    tmp = tempfile.mkdtemp(prefix="glint_helmet_")
    images = [
        jpeg(os.path.join(tmp, "base.jpg"), "checker:width=128:height=128:color1=0.8,0.6,0.3:color2=0.2,0.2,0.25"),
        jpeg(os.path.join(tmp, "mr.jpg"), "fill:topleft=0,0.3,1:topright=0,0.8,0:bottomleft=0,0.5,1:bottomright=0,0.2,0"),
        jpeg(os.path.join(tmp, "normal.jpg"), "constant:color=0.5,0.5,1"),
        jpeg(os.path.join(tmp, "occlusion.jpg"), "fill:top=1,1,1:bottom=0.6,0.6,0.6"),
        jpeg(os.path.join(tmp, "emissive.jpg"), "checker:width=512:height=512:color1=0,0,0:color2=0.1,0.3,0.4"),
    ]
    pos, nrm, uv, idx = sphere()
    blob = b""
    views, accessors = [], []

    def view(data):
        nonlocal blob
        blob += b"\0" * (-len(blob) % 4)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)})
        blob += data
        return len(views) - 1

    def accessor(fmt, values, ctype, atype, count, **extra):
        a = {"bufferView": view(struct.pack("<" + fmt * len(values), *values)),
             "componentType": ctype, "count": count, "type": atype}
        a.update(extra)
        accessors.append(a)
        return len(accessors) - 1

    flat = lambda rows: [c for row in rows for c in row]
    p = accessor("f", flat(pos), 5126, "VEC3", len(pos), min=[-1, -1, -1], max=[1, 1, 1])
    n = accessor("f", flat(nrm), 5126, "VEC3", len(nrm))
    t = accessor("f", flat(uv), 5126, "VEC2", len(uv))
    i = accessor("I", idx, 5125, "SCALAR", len(idx))
    image_views = [view(data) for data in images]
    doc = {
        "asset": {"version": "2.0", "generator": "glint benchmarks/make_helmet.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "helmet", "mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": p, "NORMAL": n, "TEXCOORD_0": t},
                                    "indices": i, "material": 0}]}],
        "materials": [{
            "name": "helmet",
            "pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                     "metallicRoughnessTexture": {"index": 1}},
            "normalTexture": {"index": 2},
            "occlusionTexture": {"index": 3},
            "emissiveTexture": {"index": 4},
            "emissiveFactor": [1, 1, 1]}],
        "textures": [{"source": k} for k in range(5)],
        "images": [{"bufferView": v, "mimeType": "image/jpeg"} for v in image_views],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob)}],
    }
    js = json.dumps(doc).encode()
    js += b" " * (-len(js) % 4)
    blob += b"\0" * (-len(blob) % 4)
    with open(out, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(js) + 8 + len(blob)))
        f.write(struct.pack("<II", len(js), 0x4E4F534A) + js)
        f.write(struct.pack("<II", len(blob), 0x004E4942) + blob)
    print(f"{out}: {len(idx) // 3} triangles, 5 JPEG textures of {SIZE}x{SIZE}, "
          f"{os.path.getsize(out) / 1e6:.1f} MB")


if __name__ == "__main__":
    main()
