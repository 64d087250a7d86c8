#!/usr/bin/env python3
"""A fire baked by Blender's own fluid simulation, rendered by Cycles from the domain and by
glint from the cache's .vdb files (issue 52: "a user's .vdb renders with one sidecar entry").

The VDB tests and the Cycles comparison (cycles_vdb.py) use files glint's tool writes with
libopenvdb. This script checks the files people bring: it bakes a Mantaflow fire in Debian's
blender 3.4 (headless; an OpenVDB cache with Blender's defaults: Blosc compression, 16-bit
floats), renders the domain in Cycles as a Blender user would see it, and renders the cache's
file for the same frame in glint with the sidecar entry scenes/README.md gives for Blender
caches. What it tells:

- placement: Blender writes a cache's grids from the origin (voxel i at i x voxel size, with
  no domain transform) and renders them stretched over the domain's box (n = round(side /
  voxel) voxels per axis, voxel = longest side / resolution), so the sidecar translates by
  half a voxel, scales by side / (n x voxel), translates by the domain's lowest corner and
  turns Blender's Z up into glint's Y up;
- temperature: Cycles gives a fluid domain's "temperature" attribute from its FLAME grid
  (ignition + flame x (max temperature - ignition) where flame > 0.01, else 0, voxel by
  voxel; Blender's rna_fluid.cc), while the cache's own "temperature" grid is the
  simulation's heat. The sidecar names the flame grid with temperature_scale, _offset and
  _cutoff (the cutoff is 0 K at or below it, mapped per voxel before interpolation as Blender
  does);
- colour (--smoke-color R G B: coloured smoke instead of the fire, under a bright sky): the
  cache stores it as three float grids, color_r, color_g and color_b, each colour x density,
  which Blender renders as they stand, interpolated weighted by the density, the colour
  tinting the albedo (Cycles' Principled Volume with its Color Attribute "color" and a black
  Absorption Color); the sidecar says color_grid [color_r, color_g, color_b],
  color_density_weighted and color_mode "albedo";
- the image: both renderers' means over the fire's pixels, per 8 x 8 tile, and the brightest
  pixels; a PNG of glint, Cycles and their difference.

    /usr/bin/python3 benchmarks/blender_fluid.py --glint build-tests/glint --work /tmp/bfluid \\
        --out benchmarks/results/blender_fluid.json --png benchmarks/results/blender_fluid.png

Needs `blender` (Debian 12, 3.4.1; not part of scripts/setup.sh), /usr/bin/python3 with numpy
and OpenImageIO, and `oiiotool`.
"""
import argparse
import datetime
import json
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "accuracy"))
import conformance  # noqa: E402  (blender_env)
import cycles_vdb  # noqa: E402  (principled_volume, bias_row, volume_mask)
import helmet_equal_error as heq  # noqa: E402  (timed, read_rgb, tails)
from accel_report import cpu_model  # noqa: E402

# The scene in Blender's axes (Z up). The domain's sides are not whole multiples of its voxel
# (3 / 48): Blender stretches the grid's 34 x 30 x 48 voxels over it.
DOMAIN = {"location": [0.3, -0.2, 1.5], "size": [2.1, 1.9, 3.0], "resolution": 48,
          "frames": 40}
FLOW = {"location": [0.3, -0.2, 0.35], "radius": 0.3}
CAMERA = {"position": [0.3, 1.6, 6.0], "look_at": [0.3, 1.3, 0.2], "yfov_degrees": 40}  # glint's
SKY = [0.02, 0.025, 0.04]
SMOKE_SKY = [0.8, 0.8, 0.8]  # --smoke-color: no fire to light the smoke, so a bright sky
# The medium, as glint's sidecar says it; Cycles' Principled Volume gets the same values
# through cycles_vdb.principled_volume.
MEDIUM = {"sigma_a": 2.0, "sigma_s": 6.0, "g": 0.2}

BAKE_SCRIPT = r'''
import json, math, sys
import bpy
from mathutils import Vector
a = sys.argv[sys.argv.index("--") + 1:]
work = a[0]
S = json.loads(r"""@SCENE@""")
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
D = S["domain"]
bpy.ops.mesh.primitive_cube_add(size=1, location=D["location"])
dom = bpy.context.object
dom.name = "Domain"
dom.scale = D["size"]
bpy.ops.object.transform_apply(location=False, rotation=False, scale=True)
dom.rotation_euler = (0.0, 0.0, math.radians(S["rotate_z"]))
bpy.ops.object.modifier_add(type="FLUID")
fm = dom.modifiers["Fluid"]
fm.fluid_type = "DOMAIN"
ds = fm.domain_settings
ds.domain_type = "GAS"
ds.resolution_max = D["resolution"]
ds.cache_directory = work + "/cache"
ds.cache_type = "ALL"
ds.cache_data_format = "OPENVDB"
ds.cache_frame_start, ds.cache_frame_end = 1, D["frames"]
ds.use_adaptive_domain = S["adaptive"]
F = S["flow"]
bpy.ops.mesh.primitive_uv_sphere_add(radius=F["radius"], location=F["location"])
flow = bpy.context.object
flow.name = "Flow"
bpy.ops.object.modifier_add(type="FLUID")
flow.modifiers["Fluid"].fluid_type = "FLOW"
fs = flow.modifiers["Fluid"].flow_settings
fs.flow_type = "SMOKE" if S["smoke_color"] else "BOTH"
if S["smoke_color"]:
    fs.smoke_color = S["smoke_color"]
fs.flow_behavior = "INFLOW"
flow.hide_render = True
scene.frame_start, scene.frame_end = 1, D["frames"]
bpy.context.view_layer.objects.active = dom
# Blender 3.4's first evaluation of a new fluid domain raises now and then (mantaflow's
# script finds a grid missing), and operators start with that evaluation: take it here.
for attempt in range(3):
    try:
        bpy.context.view_layer.update()
        break
    except SystemError:
        pass
result = list(bpy.ops.fluid.bake_all())
# The box as set up (an adaptive domain's mesh is the last frame's adaptive box after a bake):
# its sides, and where its centre is and how it is turned.
info = {"bake": result, "blender": bpy.app.version_string,
        "domain_size": D["size"], "domain_location": D["location"],
        "domain_rotate_z": S["rotate_z"],
        "adaptive_domain": ds.use_adaptive_domain, "smoke_color": S["smoke_color"],
        "flame_ignition": ds.flame_ignition, "flame_max_temp": ds.flame_max_temp,
        "resolution_max": ds.resolution_max,
        "cache_compression": ds.openvdb_cache_compress_type,
        "cache_precision": ds.openvdb_data_depth}
bpy.ops.wm.save_as_mainfile(filepath=work + "/fire.blend")
with open(work + "/domain.json", "w") as f:
    json.dump(info, f, indent=1)
'''

RENDER_SCRIPT = r'''
import json, math, sys
import bpy
from mathutils import Matrix, Vector
a = sys.argv[sys.argv.index("--") + 1:]
out, spp, seed, threads, timing = a[0], int(a[1]), int(a[2]), int(a[3]), a[4]
step_rate = 1.0
SCENE = json.loads(r"""@SCENE@""")
Y_UP = Matrix(((1, 0, 0, 0), (0, 0, -1, 0), (0, 1, 0, 0), (0, 0, 0, 1)))
def point(v):
    return (Y_UP @ Vector((v[0], v[1], v[2], 1.0))).xyz
scene = bpy.context.scene
scene.frame_set(SCENE["frame"])
''' + cycles_vdb.CYCLES_COMMON + r'''
m = SCENE["volume"]
dom = bpy.data.objects["Domain"]
mat = bpy.data.materials.new("fire")
mat.use_nodes = True
mat.cycles.volume_interpolation = "LINEAR"
nodes, links = mat.node_tree.nodes, mat.node_tree.links
nodes.remove(nodes["Principled BSDF"])
pv = nodes.new("ShaderNodeVolumePrincipled")
pv.inputs["Color"].default_value = (*m["color"], 1.0)
pv.inputs["Density"].default_value = m["density"]
pv.inputs["Density Attribute"].default_value = "density"
pv.inputs["Absorption Color"].default_value = (*m["absorption_color"], 1.0)
pv.inputs["Anisotropy"].default_value = m["g"]
pv.inputs["Blackbody Intensity"].default_value = SCENE["blackbody_intensity"]
pv.inputs["Color Attribute"].default_value = SCENE["color_attribute"]
pv.inputs["Blackbody Tint"].default_value = (1.0, 1.0, 1.0, 1.0)
pv.inputs["Temperature"].default_value = 1000.0  # Blender's default: the attribute is in 1000 K
pv.inputs["Temperature Attribute"].default_value = "temperature"
pv.inputs["Emission Strength"].default_value = 0.0
links.new(pv.outputs[0], nodes["Material Output"].inputs["Volume"])
dom.data.materials.clear()
dom.data.materials.append(mat)
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
timing_extra = {"blender": bpy.app.version_string, "frame": scene.frame_current}
''' + heq.TIMED_RENDER


def blender(args, script, extra, log, blend=None):
    cmd = [args.blender, "-b"] + ([blend] if blend else ["--factory-startup"]) + \
          ["-noaudio", "-t", str(args.threads), "--python", script, "--"] + extra
    return heq.timed(cmd, log, env=conformance.blender_env())


def write(path, text):
    with open(path, "w") as f:
        f.write(text)
    return path


def bake(args):
    """Bakes the fire, and checks that every frame's file is there (up to three tries)."""
    flow = dict(FLOW, location=[FLOW["location"][0] + args.flow_offset[0],
                                FLOW["location"][1] + args.flow_offset[1], FLOW["location"][2]])
    scene = {"domain": DOMAIN, "flow": flow, "adaptive": args.adaptive_domain,
             "rotate_z": args.rotate_z, "smoke_color": args.smoke_color}
    script = write(os.path.join(args.work, "bake.py"),
                   BAKE_SCRIPT.replace("@SCENE@", json.dumps(scene)))
    info_path = os.path.join(args.work, "domain.json")
    for attempt in range(3):
        subprocess.run(["rm", "-rf", os.path.join(args.work, "cache"), info_path])
        blender(args, script, [args.work], os.path.join(args.work, f"bake{attempt}.log"))
        if os.path.exists(info_path):
            with open(info_path) as f:
                info = json.load(f)
            last = os.path.join(args.work, "cache", "data", f"fluid_data_{DOMAIN['frames']:04d}.vdb")
            if info["bake"][0] == "FINISHED" and os.path.exists(last):
                info["attempts"] = attempt + 1
                return info
    sys.exit(f"blender_fluid: the bake failed three times (see {args.work}/bake*.log)")


def sidecar_medium(info, frame):
    """The sidecar entry for frame `frame` of the cache: what scenes/README.md tells a user."""
    size = np.array(info["domain_size"])
    voxel = size.max() / info["resolution_max"]
    cells = np.round(size / voxel)  # per axis; the file's grid is cells x voxel long
    ign, top = info["flame_ignition"], info["flame_max_temp"]
    medium = dict(MEDIUM, name="fire")
    # The grid onto the domain's own box (centred at its origin), then the domain's rotation
    # and location, then Blender's Z up to glint's Y up.
    medium["transform"] = [{"translate": [voxel / 2] * 3},
                           {"scale": (size / (cells * voxel)).tolist()},
                           {"translate": (-size / 2).tolist()},
                           {"rotate": {"axis": [0, 0, 1], "degrees": info["domain_rotate_z"]}},
                           {"translate": info["domain_location"]},
                           {"rotate": {"axis": [1, 0, 0], "degrees": -90}}]
    medium["density"] = {
        "type": "vdb", "file": "cache/data/fluid_data_####.vdb", "frame_offset": frame,
        "grid": "density"}
    if info.get("smoke_color"):
        # Coloured smoke: the cache keeps the colour in three float grids (colour x density, as
        # the simulation advects it), which Blender renders as they stand, interpolated
        # weighted by the density, tinting the albedo (its Absorption Color is black here).
        medium["density"] |= {"color_grid": ["color_r", "color_g", "color_b"],
                              "color_density_weighted": True, "color_mode": "albedo"}
    else:
        medium["density"] |= {
            "temperature_grid": "flame", "blackbody_intensity": 1,
            "temperature_scale": 1000 * (top - ign), "temperature_offset": 1000 * ign,
            "temperature_cutoff": 1000 * (ign + 0.01 * (top - ign))}
    return medium


def sky(info):
    return SMOKE_SKY if info.get("smoke_color") else SKY


def glint_json(args, info, with_medium=True):
    s = {"render": {"width": args.width, "height": args.height, "spp": 16,
                    "filter": {"type": "box", "radius": 0.5},
                    "integrator": {"type": "path", "max_depth": cycles_vdb.GLINT_DEPTH}},
         "cameras": [CAMERA], "environment": {"color": sky(info)}}
    if with_medium:
        s["media"] = [sidecar_medium(info, args.frame)]
    return write(os.path.join(args.work, "fire.json" if with_medium else "empty.json"),
                 json.dumps(s, indent=1))


def render_glint(args, scene, spp, seed, exr):
    stats = exr[:-4] + ".stats.json"
    wall, cpu = heq.timed([args.glint, "render", scene, "--spp", str(spp), "--seed", str(seed),
                           "--threads", str(args.threads), "--quiet", "--stats", stats,
                           "-o", exr], exr[:-4] + ".log")
    with open(stats) as f:
        st = json.load(f)
    return {"renderer": "glint", "spp": spp, "wall_seconds": wall, "cpu_seconds": cpu,
            "render_seconds": st["render_seconds"]}


def render_cycles(args, script, blend, spp, seed, exr):
    timing = exr[:-4] + ".timing.json"
    wall, cpu = blender(args, script, [exr, str(spp), str(seed), str(args.threads), timing],
                        exr[:-4] + ".log", blend)
    with open(timing) as f:
        t = json.load(f)
    return {"renderer": "cycles", "spp": spp, "wall_seconds": wall, "cpu_seconds": cpu,
            "render_call_seconds": t["render_call_seconds"], "frame": t["frame"],
            "blender": t["blender"]}


def efficiency(args, scene, empty, script):
    """Speed at equal variance: per round each renderer renders twice at --efficiency spp with
    new seeds (alternated); half the mean squared difference of its two images over the fire's
    pixels (luminance), times spp, is the variance of one sample v; with t the seconds per
    sample (glint's render seconds, Cycles' render call), glint's speed is
    (v_cycles t_cycles) / (v_glint t_glint). Both means agree (the comparison above), so equal
    variance is equal error up to that bias."""
    w, spp = args.work, args.efficiency
    render_glint(args, empty, 16, 3, f"{w}/empty.exr")
    e = heq.read_rgb(f"{w}/empty.exr")
    lum = cycles_vdb.LUMINANCE
    rounds = []
    for rnd in range(args.rounds):
        row = {"load_before": os.getloadavg()[0]}
        images, seconds = {"glint": [], "cycles": []}, {"glint": [], "cycles": []}
        for k in range(2):
            seed = 100 * (rnd + 1) + k
            order = ("glint", "cycles") if (rnd + k) % 2 == 0 else ("cycles", "glint")
            for who in order:
                exr = f"{w}/eff_{who}_{rnd}_{k}.exr"
                if who == "glint":
                    r = render_glint(args, scene, spp, seed, exr)
                    seconds[who].append(r["render_seconds"])
                else:
                    r = render_cycles(args, script, f"{w}/fire.blend", spp, seed, exr)
                    seconds[who].append(r["render_call_seconds"])
                images[who].append(heq.read_rgb(exr))
        mask = cycles_vdb.volume_mask(images["glint"][0], e)
        for who in images:
            a, b = (img @ lum for img in images[who])
            row[f"{who}_variance"] = float(np.mean((a - b)[mask] ** 2) / 2 * spp)
            row[f"{who}_seconds"] = seconds[who]
        t = {who: np.mean(seconds[who]) / spp for who in images}
        row["speed"] = (row["cycles_variance"] * t["cycles"]) / (row["glint_variance"] * t["glint"])
        row["pixels"] = int(mask.sum())
        rounds.append(row)
        print(json.dumps(row), flush=True)
    speeds = [r["speed"] for r in rounds]
    return {"date": datetime.date.today().isoformat(), "machine": cpu_model(),
            "threads": args.threads, "width": args.width, "height": args.height, "spp": spp,
            "frame": args.frame, "smoke_color": args.smoke_color, "rounds": rounds,
            "speed_median": float(np.median(speeds)), "speed_min": float(min(speeds)),
            "speed_max": float(max(speeds))}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--glint", required=True)
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--work", required=True)
    ap.add_argument("--frame", type=int, default=30)
    ap.add_argument("--width", type=int, default=160)
    ap.add_argument("--height", type=int, default=200)
    ap.add_argument("--spp", type=int, default=1024, help="both renderers")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--skip-bake", action="store_true", help="reuse --work's cache")
    ap.add_argument("--adaptive-domain", action="store_true",
                    help="bake with Blender's Adaptive Domain (the sidecar is the same)")
    ap.add_argument("--rotate-z", type=float, default=0.0,
                    help="the domain turned by this many degrees about Blender's Z (up)")
    ap.add_argument("--flow-offset", type=float, nargs=2, default=[0.0, 0.0],
                    help="the flow moved by (x, y) off the domain's centre (Blender's axes)")
    ap.add_argument("--smoke-color", type=float, nargs=3,
                    help="bake coloured smoke (no fire) of this colour, lit by a bright sky")
    ap.add_argument("--efficiency", type=int, metavar="SPP",
                    help="instead of the comparison: each renderer twice at SPP (other seeds), "
                         "the variance of one sample over the fire's pixels from the two "
                         "images' difference, and the speed at equal variance")
    ap.add_argument("--rounds", type=int, default=3, help="with --efficiency")
    ap.add_argument("--out")
    ap.add_argument("--png")
    args = ap.parse_args()
    args.work = os.path.abspath(args.work)
    os.makedirs(args.work, exist_ok=True)

    if args.skip_bake:
        with open(os.path.join(args.work, "domain.json")) as f:
            info = json.load(f)
    else:
        info = bake(args)
    print(json.dumps(info), flush=True)
    scene, empty = glint_json(args, info), glint_json(args, info, with_medium=False)
    info_out = subprocess.run([args.glint, "info", scene], capture_output=True, text=True)
    if info_out.returncode != 0:
        sys.exit(f"blender_fluid: glint info failed: {info_out.stderr}")
    medium = MEDIUM | {"density": {"scale": 1.0}}
    volume = cycles_vdb.principled_volume(medium)
    cyc = {"frame": args.frame, "width": args.width, "height": args.height,
           "bounces": cycles_vdb.CYCLES_BOUNCES, "camera": CAMERA, "sky": sky(info),
           "volume": volume, "color_attribute": "color" if info.get("smoke_color") else "",
           "blackbody_intensity": 0.0 if info.get("smoke_color") else 1.0}
    script = write(os.path.join(args.work, "render.py"),
                   RENDER_SCRIPT.replace("@SCENE@", json.dumps(cyc)))
    w = args.work
    if args.efficiency:
        result = efficiency(args, scene, empty, script)
        text = json.dumps(result, indent=1)
        print(text)
        if args.out:
            write(args.out, text + "\n")
        return
    runs = [render_glint(args, scene, args.spp, 1, f"{w}/glint.exr"),
            render_glint(args, scene, args.spp, 2, f"{w}/glint2.exr"),
            render_glint(args, empty, 16, 3, f"{w}/empty.exr"),
            render_cycles(args, script, f"{w}/fire.blend", args.spp, 1, f"{w}/cycles.exr")]
    for r in runs:
        print(json.dumps(r), flush=True)
    if runs[3]["frame"] != args.frame:
        sys.exit(f"blender_fluid: Cycles rendered frame {runs[3]['frame']}, not {args.frame}")
    g, g2, e, c = (heq.read_rgb(f"{w}/{n}.exr") for n in ("glint", "glint2", "empty", "cycles"))
    mask = cycles_vdb.volume_mask(g, e)
    if mask.sum() < 100:
        sys.exit(f"blender_fluid: the fire covers {mask.sum()} pixels; nothing to compare")
    lum = cycles_vdb.LUMINANCE
    # How far the two silhouettes agree: pixels each renderer changes against the sky.
    cmask = cycles_vdb.volume_mask(c, e)
    result = {
        "date": datetime.date.today().isoformat(), "machine": cpu_model(),
        "cores": os.cpu_count(), "threads": args.threads, "width": args.width,
        "height": args.height, "spp": args.spp, "frame": args.frame, "bake": info,
        "sidecar_medium": sidecar_medium(info, args.frame), "runs": runs,
        "glint_info": info_out.stdout,
        "cycles_vs_glint": cycles_vdb.bias_row(c, g, mask),
        "glint_seed_vs_glint": cycles_vdb.bias_row(g2, g, mask),
        "silhouette": {"glint_pixels": int(mask.sum()), "cycles_pixels": int(cmask.sum()),
                       "both": int((mask & cmask).sum())},
        "brightest_luminance": {"glint": float((g @ lum).max()),
                                "cycles": float((c @ lum).max())},
        "tails": {"glint": heq.tails(g), "cycles": heq.tails(c)},
    }
    if args.png:
        cycles_vdb.side_by_side(args.png, f"{w}/diff.exr", f"{w}/glint.exr", f"{w}/cycles.exr")
        result["png"] = os.path.relpath(os.path.abspath(args.png), ROOT)
    text = json.dumps(result, indent=1)
    print(text)
    if args.out:
        write(args.out, text + "\n")


if __name__ == "__main__":
    main()
