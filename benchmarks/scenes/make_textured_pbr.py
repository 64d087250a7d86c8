#!/usr/bin/env python3
"""Writes the textured PBR benchmark scene: glTF's full set of material maps, as a scanned
asset like Khronos' DamagedHelmet carries them, on a few spheres and a floor.

    python3 benchmarks/scenes/make_textured_pbr.py OUT_DIR [--size 1024]

OUT_DIR/textured_pbr.gltf (+ .glint.json sidecar and four PNGs): five UV spheres and a floor
sharing one metallic-roughness material with a base colour (RGBA, sRGB), a metallicRoughness
(G roughness, B metallic), a normal and an emissive texture of SIZE x SIZE pixels, lit by a
quad area light and a uniform environment (so the path tracer's `auto` choice is natural).
The textures are generated (no files from elsewhere) and are large on purpose: lookup cost,
not image content, is what the benchmark measures. Not committed: the benchmark script writes
it into the build folder. Standard library only; reuses scripts/make_scenes.py's glTF writer.
"""
import argparse
import json
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
import make_scenes as ms  # noqa: E402


def png_rgba(width, height, pixel):
    """8-bit RGBA PNG; pixel(x, y) -> 4 bytes (make_scenes' encoder, faster compression)."""
    return ms.encode_png(width, height, pixel, alpha=True, level=6)


def write(path, data):
    with open(path, "wb") as f:
        f.write(data)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out_dir")
    ap.add_argument("--size", type=int, default=1024)
    args = ap.parse_args()
    n = args.size
    os.makedirs(args.out_dir, exist_ok=True)

    def wave(x, y, fx, fy):
        return 0.5 + 0.25 * math.sin(2 * math.pi * fx * x / n) + 0.25 * math.sin(2 * math.pi * fy * y / n)

    # Base colour: tiles of hues with a grain; alpha 1.
    def base(x, y):
        tile = ((x * 8) // n + (y * 8) // n) % 3
        g = ms.hash01(x // 4, y // 4, 3)
        c = [(200, 80, 60), (70, 150, 200), (220, 200, 120)][tile]
        return bytes([int(v * (0.8 + 0.2 * g)) for v in c] + [255])

    # metallicRoughness: G roughness 0.2..0.8, B metallic on alternate tiles.
    def mr(x, y):
        metal = 255 if ((x * 4) // n + (y * 4) // n) % 2 else 0
        return bytes([255, int(255 * (0.2 + 0.6 * wave(x, y, 11, 7))), metal, 255])

    # Normal: a gentle bumpy slope, tangent space.
    def normal(x, y):
        k = 0.3
        nx = -k * math.cos(2 * math.pi * 16 * x / n)
        ny = -k * math.cos(2 * math.pi * 16 * y / n)
        inv = 1 / math.sqrt(nx * nx + ny * ny + 1)
        return bytes([int(255 * (0.5 + 0.5 * nx * inv)), int(255 * (0.5 + 0.5 * ny * inv)),
                      int(255 * (0.5 + 0.5 * inv)), 255])

    # Emissive: thin glowing lines, black elsewhere.
    def emissive(x, y):
        on = (x % (n // 8)) < 2
        return bytes([255, 160, 40, 255] if on else [0, 0, 0, 255])

    names = {"base": base, "mr": mr, "normal": normal, "emissive": emissive}
    for name, fn in names.items():
        write(os.path.join(args.out_dir, "pbr_%s.png" % name), png_rgba(n, n, fn))

    g = ms.Gltf()
    sampler = g._add("samplers", {"magFilter": ms.LINEAR, "minFilter": ms.LINEAR_MIPMAP_LINEAR,
                                  "wrapS": ms.REPEAT, "wrapT": ms.REPEAT})
    tex = {}
    for name in names:
        image = g._add("images", {"name": name, "uri": "pbr_%s.png" % name})
        tex[name] = g._add("textures", {"name": name, "sampler": sampler, "source": image})
    mat = g._add("materials", {
        "name": "Scanned",
        "pbrMetallicRoughness": {"baseColorTexture": {"index": tex["base"]},
                                 "metallicRoughnessTexture": {"index": tex["mr"]},
                                 "metallicFactor": 1.0, "roughnessFactor": 1.0},
        "normalTexture": {"index": tex["normal"]},
        "emissiveTexture": {"index": tex["emissive"]},
        "emissiveFactor": [1.0, 1.0, 1.0]})
    sphere = g.mesh("Sphere", g.geometry(ms.orient(ms.uv_sphere(0.5, 64, 32)), uvs=True), mat)
    floor = g.mesh("Floor", g.geometry(ms.orient(ms.plane(8.0, 4.0)), uvs=True), mat)
    roots = [g.node("Floor", mesh=floor)]
    for i in range(5):
        a = 2 * math.pi * i / 5
        roots.append(g.node("Sphere%d" % i, mesh=sphere,
                            translation=(1.4 * math.cos(a), 0.5, 1.4 * math.sin(a))))
    doc = g.finish("Textured PBR", roots)
    with open(os.path.join(args.out_dir, "textured_pbr.gltf"), "w") as f:
        json.dump(doc, f)
    sidecar = {
        "render": {"width": 320, "height": 240, "spp": 4, "seed": 0, "camera": "Main",
                   "integrator": {"type": "path", "max_depth": 4}},
        "cameras": [{"name": "Main", "type": "perspective", "position": [0, 2.2, 4.2],
                     "look_at": [0, 0.4, 0], "yfov_degrees": 45}],
        "lights": [{"type": "quad", "corner": [-1, 3, -1], "edge_u": [0, 0, 2],
                    "edge_v": [2, 0, 0], "intensity": 6}],
        "environment": {"color": [0.4, 0.45, 0.5], "intensity": 1},
    }
    with open(os.path.join(args.out_dir, "textured_pbr.glint.json"), "w") as f:
        json.dump(sidecar, f, indent=1)
    print("wrote", os.path.join(args.out_dir, "textured_pbr.gltf"))


if __name__ == "__main__":
    main()
