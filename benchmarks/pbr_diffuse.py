#!/usr/bin/env python3
"""The core PBR model against a peer (issue 24): how bright is glTF's grey rough dielectric?

One scene, written by this script: the Stanford bunny (`$GLINT_ASSETS/stanford/bun_zipper.glb`)
on a floor, lit by a sun (KHR_lights_punctual), seen by the file's camera, no environment. Two
material variants of the same file:
  pbr      base colour 0.8, metallic 0, roughness 1 (glTF's metallic-roughness model)
  lambert  a Lambertian of albedo 0.8: in glint the same material with KHR_materials_specular
           strength 0 (an exact Lambertian, tests/materials/furnace_test.cpp), in Cycles a
           Diffuse BSDF of colour 0.8 put in place of the imported material.
Each renderer renders both; the table gives the mean of each image and the ratio pbr / lambert
per renderer. The ratio is what the material model does; the lambert columns show that the two
renderers agree where their models are the same.

Then the white furnace, where the answer is known: a sphere of base colour 1 (roughness 1,
metallic 0 and 1) inside a uniform white sky of radiance 1. A material that neither gains nor
loses energy is invisible there: every pixel is 1. The table gives the mean of the sphere's
middle (a centred square inside its silhouette) and the brightest and darkest pixel.

    python3 benchmarks/pbr_diffuse.py --glint build-rel/glint --out benchmarks/results/pbr_diffuse

Needs `blender` (Debian's 3.4; see benchmarks/conformance.py for its workarounds) and
`oiiotool`. Lights are imported with convert_lighting_mode="RAW" (the sun's 3 lux as 3 W/m^2, the
irradiance glint gives it). Path depth 8 in both (Cycles max_bounces 7), box pixel filter, no denoising.
"""
import argparse
import json
import math
import os
import re
import struct
import subprocess
import sys
import tempfile
import time

from conformance import blender_env

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

BLENDER_SCRIPT = r'''
import sys
import numpy
if not hasattr(numpy, "bool"):
    numpy.bool = bool
import bpy
a = sys.argv[sys.argv.index("--") + 1:]
src, out, variant = a[0], a[1], a[2]
width, height, spp = int(a[3]), int(a[4]), int(a[5])
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=src, convert_lighting_mode="RAW")
scene = bpy.context.scene
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = spp
scene.cycles.use_denoising = False
scene.cycles.use_adaptive_sampling = False
scene.cycles.max_bounces = 7
scene.cycles.diffuse_bounces = scene.cycles.glossy_bounces = 7
scene.cycles.sample_clamp_direct = scene.cycles.sample_clamp_indirect = 0
scene.cycles.blur_glossy = 0
scene.cycles.pixel_filter_type = "BOX"
scene.cycles.filter_width = 1.0
scene.render.resolution_x, scene.render.resolution_y = width, height
scene.render.resolution_percentage = 100
world = bpy.data.worlds.new("black")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0
scene.world = world
for o in scene.objects:
    if o.type == "CAMERA":
        scene.camera = o
    if o.type == "LIGHT" and o.data.type == "SUN":
        o.data.angle = 0
if variant.startswith("furnace"):
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (1, 1, 1, 1)
    bg.inputs["Strength"].default_value = 1
if variant == "lambert":
    for m in bpy.data.materials:
        m.use_nodes = True
        nt = m.node_tree
        nt.nodes.clear()
        d = nt.nodes.new("ShaderNodeBsdfDiffuse")
        d.inputs["Color"].default_value = (0.8, 0.8, 0.8, 1)
        d.inputs["Roughness"].default_value = 0
        o = nt.nodes.new("ShaderNodeOutputMaterial")
        nt.links.new(d.outputs["BSDF"], o.inputs["Surface"])
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
'''


def read_glb(path):
    data = open(path, "rb").read()
    magic, _, _ = struct.unpack_from("<III", data, 0)
    if magic != 0x46546C67:
        sys.exit(f"{path}: not a GLB")
    offset, doc, binary = 12, None, b""
    while offset < len(data):
        length, kind = struct.unpack_from("<II", data, offset)
        chunk = data[offset + 8:offset + 8 + length]
        if kind == 0x4E4F534A:
            doc = json.loads(chunk)
        elif kind == 0x004E4942:
            binary = chunk
        offset += 8 + length
    return doc, binary


def look_rotation(forward, up=(0, 1, 0)):
    """The unit quaternion (x, y, z, w) that turns -Z to `forward` with +Y towards `up`."""
    f = [c / math.sqrt(sum(v * v for v in forward)) for c in forward]
    z = [-c for c in f]
    x = [up[1] * z[2] - up[2] * z[1], up[2] * z[0] - up[0] * z[2], up[0] * z[1] - up[1] * z[0]]
    n = math.sqrt(sum(v * v for v in x))
    x = [v / n for v in x]
    y = [z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]]
    m = [[x[0], y[0], z[0]], [x[1], y[1], z[1]], [x[2], y[2], z[2]]]
    t = m[0][0] + m[1][1] + m[2][2]
    if t > 0:
        s = math.sqrt(t + 1) * 2
        return [(m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, s / 4]
    i = max(range(3), key=lambda k: m[k][k])
    j, k = (i + 1) % 3, (i + 2) % 3
    s = math.sqrt(1 + m[i][i] - m[j][j] - m[k][k]) * 2
    q = [0, 0, 0, 0]
    q[i] = s / 4
    q[j] = (m[j][i] + m[i][j]) / s
    q[k] = (m[k][i] + m[i][k]) / s
    q[3] = (m[k][j] - m[j][k]) / s
    return q


def write_scene(bunny_glb, folder, variant):
    """scene_VARIANT.gltf + scene.bin in `folder`: the bunny's first primitive, scaled by 10,
    on a 6 x 6 floor, a sun and a camera."""
    doc, binary = read_glb(bunny_glb)
    prim = doc["meshes"][0]["primitives"][0]
    pos = doc["accessors"][prim["attributes"]["POSITION"]]
    lo, hi = pos["min"], pos["max"]
    scale = 10
    floor_y = lo[1] * scale
    blob = bytearray(binary)
    while len(blob) % 4:
        blob.append(0)
    floor_offset = len(blob)
    s = 3
    floor = [-s, floor_y, -s, s, floor_y, -s, s, floor_y, s, -s, floor_y, s]
    blob += struct.pack("<12f", *floor)
    blob += struct.pack("<6H", 0, 2, 1, 0, 3, 2)
    with open(os.path.join(folder, "scene.bin"), "wb") as f:
        f.write(blob)
    views = [dict(v) for v in doc["bufferViews"]]
    for v in views:
        v["buffer"] = 0
    accessors = [dict(a) for a in doc["accessors"]]
    views.append({"buffer": 0, "byteOffset": floor_offset, "byteLength": 48})
    views.append({"buffer": 0, "byteOffset": floor_offset + 48, "byteLength": 12})
    accessors.append({"bufferView": len(views) - 2, "componentType": 5126, "count": 4,
                      "type": "VEC3", "min": [-s, floor_y, -s], "max": [s, floor_y, s]})
    accessors.append({"bufferView": len(views) - 1, "componentType": 5123, "count": 6,
                      "type": "SCALAR"})
    material = {"name": "grey", "pbrMetallicRoughness": {
        "baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0, "roughnessFactor": 1}}
    used = ["KHR_lights_punctual"]
    if variant == "lambert":
        material["extensions"] = {"KHR_materials_specular": {"specularFactor": 0}}
        used.append("KHR_materials_specular")
    bunny_prim = {"attributes": {"POSITION": prim["attributes"]["POSITION"]},
                  "indices": prim["indices"], "material": 0}
    center = [(lo[i] + hi[i]) / 2 * scale for i in range(3)]
    eye = [center[0] + 1.2, center[1] + 1.0, center[2] + 3.2]
    gltf = {
        "asset": {"version": "2.0", "generator": "benchmarks/pbr_diffuse.py"},
        "extensionsUsed": used,
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "directional", "intensity": 3, "color": [1, 1, 1], "name": "sun"}]}},
        "buffers": [{"uri": "scene.bin", "byteLength": len(blob)}],
        "bufferViews": views, "accessors": accessors, "materials": [material],
        "meshes": [{"name": "bunny", "primitives": [bunny_prim]},
                   {"name": "floor", "primitives": [{"attributes": {"POSITION": len(accessors) - 2},
                                                     "indices": len(accessors) - 1,
                                                     "material": 0}]}],
        "cameras": [{"type": "perspective", "perspective": {
            "yfov": 0.55, "aspectRatio": 4 / 3, "znear": 0.01}}],
        "nodes": [
            {"name": "bunny", "mesh": 0, "scale": [scale] * 3},
            {"name": "floor", "mesh": 1},
            {"name": "sun", "rotation": look_rotation([-0.5, -1.0, -0.7]),
             "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"name": "camera", "camera": 0, "translation": eye,
             "rotation": look_rotation([center[i] - eye[i] for i in range(3)])},
        ],
        "scenes": [{"nodes": [0, 1, 2, 3]}], "scene": 0,
    }
    path = os.path.join(folder, f"scene_{variant}.gltf")
    with open(path, "w") as f:
        json.dump(gltf, f, indent=1)
    return path


def write_furnace(folder, metallic):
    """furnace_METAL.gltf: a smooth-shaded unit sphere (96 x 48 quads) of base colour 1,
    roughness 1, seen from +Z; no lights."""
    nu, nv = 96, 48
    pos, idx = [], []
    for j in range(nv + 1):
        th = math.pi * j / nv
        for i in range(nu + 1):
            ph = 2 * math.pi * i / nu
            pos += [math.sin(th) * math.cos(ph), math.cos(th), -math.sin(th) * math.sin(ph)]
    for j in range(nv):
        for i in range(nu):
            a, b = j * (nu + 1) + i, (j + 1) * (nu + 1) + i
            idx += [a, b, a + 1, a + 1, b, b + 1]
    name = f"furnace_{'metal' if metallic else 'dielectric'}"
    blob = struct.pack(f"<{len(pos)}f", *pos) + struct.pack(f"<{len(idx)}I", *idx)
    with open(os.path.join(folder, name + ".bin"), "wb") as f:
        f.write(blob)
    n = len(pos) // 3
    gltf = {
        "asset": {"version": "2.0", "generator": "benchmarks/pbr_diffuse.py"},
        "buffers": [{"uri": name + ".bin", "byteLength": len(blob)}],
        "bufferViews": [{"buffer": 0, "byteLength": 12 * n},
                        {"buffer": 0, "byteOffset": 12 * n, "byteLength": 4 * len(idx)}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3",
             "min": [-1, -1, -1], "max": [1, 1, 1]},
            {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3"},
            {"bufferView": 1, "componentType": 5125, "count": len(idx), "type": "SCALAR"}],
        "materials": [{"name": "white", "pbrMetallicRoughness": {
            "baseColorFactor": [1, 1, 1, 1], "metallicFactor": metallic, "roughnessFactor": 1}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2,
                                    "material": 0}]}],
        "cameras": [{"type": "perspective", "perspective": {
            "yfov": 0.6, "aspectRatio": 4 / 3, "znear": 0.01}}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, 4]}],
        "scenes": [{"nodes": [0, 1]}], "scene": 0,
    }
    path = os.path.join(folder, name + ".gltf")
    with open(path, "w") as f:
        json.dump(gltf, f, indent=1)
    return path


def image_stats(path, crop=None):
    """(mean, min, max) over the colour channels, of the whole image or a crop 'WxH+X+Y'."""
    cmd = ["oiiotool", path] + (["--cut", crop] if crop else []) + ["--printstats"]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    values = {}
    for key in ("Avg", "Min", "Max"):
        m = re.search(rf"Stats {key}:\s+([-\d.e+]+)\s+([-\d.e+]+)\s+([-\d.e+]+)", out)
        if not m:
            sys.exit(f"no statistics for {path}:\n{out}")
        values[key] = [float(v) for v in m.groups()]
    return (sum(values["Avg"]) / 3, min(values["Min"]), max(values["Max"]))


def image_mean(path):
    return image_stats(path)[0]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--glint", default=os.path.join(ROOT, "build-rel", "glint"))
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--out", default=os.path.join(ROOT, "benchmarks", "results", "pbr_diffuse"))
    ap.add_argument("--assets", default=os.environ.get(
        "GLINT_ASSETS", os.path.join(ROOT, "..", "shared", "assets")))
    ap.add_argument("--width", type=int, default=400)
    ap.add_argument("--height", type=int, default=300)
    ap.add_argument("--spp", type=int, default=512)
    ap.add_argument("--work", help="folder for the scenes and EXRs (default: a new temporary one)")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    work = args.work or tempfile.mkdtemp(prefix="glint_pbr_diffuse_")
    os.makedirs(work, exist_ok=True)
    bunny = os.path.join(args.assets, "stanford", "bun_zipper.glb")
    if not os.path.exists(bunny):
        sys.exit(f"{bunny}: missing (benchmarks/get_assets.sh fetches it)")
    script = os.path.join(work, "cycles_render.py")
    with open(script, "w") as f:
        f.write(BLENDER_SCRIPT)
    env = blender_env()  # Debian's python and numpy for Blender (conformance.py says why)
    results = {}
    for variant in ("pbr", "lambert"):
        scene = write_scene(bunny, work, variant)
        glint_out = os.path.join(work, f"glint_{variant}.exr")
        cycles_out = os.path.join(work, f"cycles_{variant}.exr")
        start = time.time()
        subprocess.run([args.glint, "render", scene, "-o", glint_out, "--quiet", "--integrator",
                        "path", "--max-depth", "8", "--spp", str(args.spp), "--width",
                        str(args.width), "--height", str(args.height)], check=True)
        glint_s = time.time() - start
        start = time.time()
        subprocess.run([args.blender, "-b", "--factory-startup", "-noaudio", "-P", script, "--",
                        scene, cycles_out, variant, str(args.width), str(args.height),
                        str(args.spp)], check=True, capture_output=True, env=env)
        cycles_s = time.time() - start
        results[variant] = {"glint": image_mean(glint_out), "cycles": image_mean(cycles_out),
                            "glint_seconds": round(glint_s, 1),
                            "cycles_seconds": round(cycles_s, 1)}
    for r in ("glint", "cycles"):
        results[f"{r}_ratio"] = results["pbr"][r] / results["lambert"][r]
    results["lambert_cycles_over_glint"] = results["lambert"]["cycles"] / results["lambert"]["glint"]
    white = os.path.join(work, "white_sky.exr")
    subprocess.run(["oiiotool", "--pattern", "constant:color=1,1,1", "64x32", "3", "-d", "float",
                    "-o", white], check=True)
    side = args.height * 2 // 5
    crop = f"{side}x{side}+{(args.width - side) // 2}+{(args.height - side) // 2}"
    for metallic in (0, 1):
        scene = write_furnace(work, metallic)
        variant = os.path.splitext(os.path.basename(scene))[0]
        glint_out = os.path.join(work, f"glint_{variant}.exr")
        cycles_out = os.path.join(work, f"cycles_{variant}.exr")
        subprocess.run([args.glint, "render", scene, "-o", glint_out, "--quiet", "--integrator",
                        "path", "--max-depth", "8", "--spp", str(args.spp), "--width",
                        str(args.width), "--height", str(args.height), "--env", white],
                       check=True)
        subprocess.run([args.blender, "-b", "--factory-startup", "-noaudio", "-P", script, "--",
                        scene, cycles_out, variant, str(args.width), str(args.height),
                        str(args.spp)], check=True, capture_output=True, env=env)
        for r, path in (("glint", glint_out), ("cycles", cycles_out)):
            mean, _, _ = image_stats(path, crop)
            _, lo, hi = image_stats(path)
            results.setdefault(variant, {})[r] = {"middle_mean": mean, "min": lo, "max": hi}
    # Contact sheets, glint left and Cycles right: the bunny (pbr top, lambert bottom) and the
    # furnace (dielectric top, metal bottom) at exposure 0.6, so that the sky is mid-grey and a
    # sphere that gains energy shows brighter than it, one that loses it darker.
    def sheet(rows, name, scale):
        tiles = []
        for v in rows:
            for r in ("glint", "cycles"):
                png = os.path.join(work, f"{r}_{v}.png")
                subprocess.run(["oiiotool", os.path.join(work, f"{r}_{v}.exr"), "--ch", "R,G,B",
                                "--mulc", str(scale), "--tocolorspace", "sRGB", "-o", png],
                               check=True)
                tiles.append(png)
        subprocess.run(["oiiotool"] + tiles + ["--mosaic", "2x2", "-o",
                                               os.path.join(args.out, name)], check=True)
    sheet(("pbr", "lambert"), "bunny_sheet.jpg", 1.0)
    sheet(("furnace_dielectric", "furnace_metal"), "furnace_sheet.jpg", 0.6)
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump(results, f, indent=1)
    print(f"| variant | glint mean | Cycles mean |")
    print(f"|---|---|---|")
    for v in ("pbr", "lambert"):
        print(f"| {v} | {results[v]['glint']:.5f} | {results[v]['cycles']:.5f} |")
    print(f"| pbr / lambert | {results['glint_ratio']:.4f} | {results['cycles_ratio']:.4f} |")
    print(f"Cycles / glint on the Lambertian: {results['lambert_cycles_over_glint']:.5f}")
    print()
    print("| white furnace (sky 1) | glint middle mean | glint min / max | Cycles middle mean | Cycles min / max |")
    print("|---|---|---|---|---|")
    for v in ("furnace_dielectric", "furnace_metal"):
        g, c = results[v]["glint"], results[v]["cycles"]
        print(f"| {v} | {g['middle_mean']:.4f} | {g['min']:.3f} / {g['max']:.3f} | "
              f"{c['middle_mean']:.4f} | {c['min']:.3f} / {c['max']:.3f} |")


if __name__ == "__main__":
    main()
