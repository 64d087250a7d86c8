#!/usr/bin/env python3
"""glTF conformance against a peer: each case rendered by glint and by Blender Cycles (Debian's
`blender`, headless, with its glTF importer) under the same uniform white sky (radiance 1),
the same camera and image size, then compared with HDR-FLIP (`glint diff --flip`). Writes a
Markdown table and JSON to --out and a contact sheet (glint left, Cycles right, one row per
case) as JPEG.

    python3 benchmarks/conformance.py --glint build-rel/glint --out benchmarks/results/conformance

Cases: every Khronos sample under $GLINT_ASSETS/gltf (see get_assets.sh), the project's own
test glTFs (tests/data/gltf) and the two example scenes. The camera is glint's bounds (from
`glint info`) seen from the front (+Z), a little right and above, with a 40-degree vertical
field of view; both renderers get it explicitly (glint through a sidecar, Blender as a camera
object), and both stop at path depth 8 (glint --max-depth 8, Cycles max_bounces 7: it counts
indirect bounces). Both pose animated files at scene time 0 (Blender: frame 0). Lights in a
file are kept by both (Blender converts KHR_lights_punctual units on import: rows with lights say so).

Beside FLIP, each renderer's tails: the brightest pixel and the 99.99th percentile of the
pixels' largest channel (a mean or a FLIP average hides a seam of fireflies; under a sky of
radiance 1 a non-emitting asset has no pixel much above 1).

Needs `blender` (the script installs it with apt-get when missing and it may),
`oiiotool`, and Debian's python3-openimageio and python3-numpy (run it with /usr/bin/python3). Debian's Blender 3.4 needs two workarounds, applied in the Blender script: its
glTF importer calls numpy.bool (gone in Debian 12's numpy), and it has no OpenImageDenoise.
"""
import argparse
import glob
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

BLENDER_SCRIPT = r'''
import sys, time, math
import numpy
if not hasattr(numpy, "bool"):
    numpy.bool = bool  # Blender 3.4's glTF importer still calls numpy.bool
import bpy
from mathutils import Vector
a = sys.argv[sys.argv.index("--") + 1:]
src, out = a[0], a[1]
width, height, spp = int(a[2]), int(a[3]), int(a[4])
pos = [float(v) for v in a[5:8]]
look = [float(v) for v in a[8:11]]
fov = float(a[11])
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=src)
# glint renders scene time 0; the importer puts glTF time t at frame t * fps (from frame 0),
# and Blender starts at frame 1.
bpy.context.scene.frame_set(0)
scene = bpy.context.scene
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = spp
scene.cycles.use_denoising = False  # Debian's build has no OpenImageDenoise
scene.cycles.max_bounces = 7  # indirect bounces: glint's path depth 8
# Each kind's own cap too: Cycles' defaults (4 diffuse, 4 glossy) would stop paths before
# glint does.
scene.cycles.diffuse_bounces = scene.cycles.glossy_bounces = 7
scene.cycles.transmission_bounces = scene.cycles.volume_bounces = 7
scene.cycles.transparent_max_bounces = 8
scene.render.resolution_x, scene.render.resolution_y = width, height
scene.render.resolution_percentage = 100
world = bpy.data.worlds.new("sky")
scene.world = world
world.use_nodes = True
bg = world.node_tree.nodes["Background"]
bg.inputs[0].default_value = (1, 1, 1, 1)
bg.inputs[1].default_value = 1
def blender(v):  # glTF (Y up) to Blender (Z up), as the importer converts
    return Vector((v[0], -v[2], v[1]))
cam = bpy.data.cameras.new("conformance")
cam.sensor_fit = "VERTICAL"
cam.angle_y = math.radians(fov)
cam.clip_start, cam.clip_end = 0.001, 1e6
obj = bpy.data.objects.new("conformance", cam)
scene.collection.objects.link(obj)
scene.camera = obj
obj.location = blender(pos)
obj.rotation_euler = (blender(look) - blender(pos)).to_track_quat("-Z", "Y").to_euler()
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
'''


def cases(assets):
    found = []
    for path in sorted(glob.glob(os.path.join(assets, "gltf", "*", "glTF", "*.gltf"))):
        found.append((os.path.basename(os.path.dirname(os.path.dirname(path))), path))
    for path in sorted(glob.glob(os.path.join(ROOT, "tests", "data", "gltf", "*.gltf"))):
        found.append(("tests/" + os.path.splitext(os.path.basename(path))[0], path))
    for name in ("first_image/first_image.gltf", "material_extensions/material_extensions.gltf"):
        found.append(("scenes/" + name.split("/")[0], os.path.join(ROOT, "scenes", name)))
    return found


def bounds(glint, path):
    info = subprocess.run([glint, "info", path], capture_output=True, text=True, check=True).stdout
    m = re.search(r"bounds:\s*\(([^)]*)\) to \(([^)]*)\)", info)
    lo = [float(v) for v in m.group(1).split(",")]
    hi = [float(v) for v in m.group(2).split(",")]
    lights = re.search(r"lights:\s*(\d+)", info)
    return lo, hi, int(lights.group(1)) if lights else 0


def camera(lo, hi, fov, aspect):
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    radius = max(1e-3, 0.5 * math.dist(lo, hi))
    d = [0.35, 0.3, 1.0]
    n = math.sqrt(sum(v * v for v in d))
    half = math.radians(fov) / 2
    half = min(half, math.atan(math.tan(half) * aspect))  # the narrower of the two fields
    dist = 1.05 * radius / math.sin(half)
    return [c + dist * v / n for c, v in zip(centre, d)], centre


def blender_env():
    """The environment for Blender: system directories first. Blender's embedded Python finds
    its prefix (and with it numpy) from the first python3 on PATH; a pyenv or virtualenv
    interpreter running this script would otherwise hide Debian's."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYENV", "VIRTUAL_ENV"))}
    env["PATH"] = "/usr/bin:/bin:" + env.get("PATH", "")
    return env


def run(cmd, **kw):
    start = time.perf_counter()
    r = subprocess.run(cmd, **kw)
    if r.returncode != 0:
        raise RuntimeError(f"{os.path.basename(cmd[0])} exited with {r.returncode}")
    if kw.get("capture_output") and "Saved:" not in r.stdout.decode(errors="replace"):
        tail = r.stdout.decode(errors="replace").strip().splitlines()[-3:]
        raise RuntimeError(f"{os.path.basename(cmd[0])} wrote no image: " + " / ".join(tail))
    return time.perf_counter() - start


def tails(exr):
    """The brightest pixel and the 99.99th percentile of the pixels' largest channel."""
    import numpy as np
    import OpenImageIO as oiio
    px = oiio.ImageBuf(exr).get_pixels(oiio.FLOAT)[:, :, :3].max(axis=2)
    return float(px.max()), float(np.percentile(px, 99.99))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--glint", default=os.path.join(ROOT, "build-rel", "glint"))
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--assets", default=os.environ.get("GLINT_ASSETS",
                                                       os.path.join(ROOT, "..", "shared", "assets")))
    ap.add_argument("--out", default=os.path.join(ROOT, "benchmarks", "results", "conformance"))
    ap.add_argument("--width", type=int, default=200)
    ap.add_argument("--height", type=int, default=150)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--fov", type=float, default=40)
    ap.add_argument("--only", help="run only cases whose name contains this")
    args = ap.parse_args()
    if not shutil.which(args.blender):
        print("conformance: installing Debian's blender (apt-get)", file=sys.stderr)
        sudo = [] if os.geteuid() == 0 else ["sudo"]
        subprocess.run(sudo + ["apt-get", "install", "-y", "-qq", "--no-install-recommends",
                               "blender"], check=True)
    os.makedirs(args.out, exist_ok=True)
    work = tempfile.mkdtemp(prefix="glint_conformance_")
    sky = os.path.join(work, "sky.exr")
    subprocess.run(["oiiotool", "--pattern", "constant:color=1,1,1", "64x32", "3", "-d", "float",
                    "-o", sky], check=True)
    script = os.path.join(work, "cycles.py")
    with open(script, "w") as f:
        f.write(BLENDER_SCRIPT)
    rows, tiles = [], []
    for name, path in cases(args.assets):
        if args.only and args.only not in name:
            continue
        slug = re.sub(r"[^A-Za-z0-9]+", "_", name)
        row = {"case": name, "file": os.path.relpath(path, ROOT)}
        try:
            lo, hi, lights = bounds(args.glint, path)
            pos, look = camera(lo, hi, args.fov, args.width / args.height)
            row["lights"] = lights
            side = os.path.join(work, slug + ".glint.json")
            with open(side, "w") as f:
                json.dump({"cameras": [{"name": "conformance", "position": pos, "look_at": look,
                                        "up": [0, 1, 0], "yfov_degrees": args.fov,
                                        "znear": 0.001, "zfar": 1e6}],
                           "render": {"camera": "conformance"}}, f)
            g = os.path.join(work, slug + "_glint.exr")
            c = os.path.join(work, slug + "_cycles.exr")
            row["glint_s"] = run([args.glint, "render", path, "--sidecar", side, "--env", sky,
                                  "--integrator", "path", "--max-depth", "8", "--width",
                                  str(args.width), "--height", str(args.height), "--spp",
                                  str(args.spp), "--quiet", "-o", g])
            row["cycles_s"] = run([args.blender, "-b", "-P", script, "--", path, c,
                                   str(args.width), str(args.height), str(args.spp),
                                   *map(str, pos), *map(str, look), str(args.fov)],
                                  capture_output=True, env=blender_env())
            diff = subprocess.run([args.glint, "diff", g, c, "--flip", "--json"],
                                  capture_output=True, text=True)
            if not diff.stdout.strip():
                raise RuntimeError("glint diff: " + diff.stderr.strip())
            flip = json.loads(diff.stdout)["flip"]
            row["flip_mean"] = flip["mean"]
            row["flip_q3"] = flip["weighted_quartiles"][1]
            row["flip_p95"] = flip["percentile_95"]
            row["glint_max"], row["glint_p9999"] = tails(g)
            row["cycles_max"], row["cycles_p9999"] = tails(c)
            for exr, tag in ((g, "glint"), (c, "cycles")):
                png = os.path.join(work, f"{slug}_{tag}.png")
                subprocess.run([args.glint, "tonemap", exr, "-o", png], check=True,
                               stdout=subprocess.DEVNULL)
                tiles.append(png)
        except Exception as e:  # a case that fails is reported, not hidden
            row["error"] = str(e).splitlines()[0][:200]
        rows.append(row)
        print(json.dumps(row), flush=True)
    with open(os.path.join(args.out, "conformance.json"), "w") as f:
        json.dump(rows, f, indent=1)
    with open(os.path.join(args.out, "conformance.md"), "w") as f:
        f.write(f"| case | lights | FLIP mean | FLIP 95th percentile | FLIP weighted Q3 "
                f"| brightest pixel glint / Cycles | 99.99th percentile glint / Cycles "
                f"| glint s | Cycles s |\n|---|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            if "error" in r:
                f.write(f"| {r['case']} | | error: {r['error']} | | | | | | |\n")
                continue
            f.write(f"| {r['case']} | {r['lights']} | {r['flip_mean']:.3f} | {r['flip_p95']:.3f} "
                    f"| {r['flip_q3']:.3f} | {r['glint_max']:.3g} / {r['cycles_max']:.3g} "
                    f"| {r['glint_p9999']:.3g} / {r['cycles_p9999']:.3g} "
                    f"| {r['glint_s']:.1f} | {r['cycles_s']:.1f} |\n")
    if tiles:
        sheet = os.path.join(args.out, "contact_sheet.jpg")
        subprocess.run(["oiiotool", *tiles, "--mosaic", f"2x{len(tiles) // 2}", "-o", sheet],
                       check=True)
    if not os.environ.get("GLINT_CONFORMANCE_KEEP"):
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
