#!/usr/bin/env python3
"""glint against Blender Cycles on the VDB cloud and fire (issue 52): bias and equal-error speed.

scenes/volumes/cloud.json (a sparse cumulus under a sun and a constant sky) and fire.json (a
fire with blackbody and flame emission over a stone floor) are rendered by glint and by Cycles
(Debian's blender 3.4, headless). For each scene this script writes a Blender Python script
that builds the same scene in Cycles from glint's JSON:

- the same .vdb, as a Blender Volume object; its matrix is glint's medium `transform` after
  the glTF-to-Blender axis change (x, y, z) -> (x, -z, y): glint is Y-up, Blender Z-up, and a
  VDB's own index-to-world transform is kept by both;
- a Principled Volume with Density D = max(sigma_a + sigma_s) x `scale`, Color sigma_s / D and
  Absorption Color chosen so that Cycles' absorption (1 - Color)(1 - sqrt(Absorption Color)) D
  is sigma_a (svm_node_principled_volume); Anisotropy g; Blackbody Intensity and Temperature
  (Cycles' Temperature multiplies the grid, glint's `temperature_scale`); the flame grid
  through an Attribute node times `flame_strength` into Emission Strength, `flame_color` as
  Emission Color. Both renderers emit per unit length, independent of the density;
- the same camera (vertical field of view), resolution, ground plane (a 20 km square, glint's
  is infinite) with a Diffuse BSDF (Lambert), sun (a delta light, angle 0; strength = glint's
  irradiance `intensity`, colour `color`) and constant world colour x intensity;
- path depth: glint `max_depth` 9 (nine scattering vertices with a light sample each) against
  Cycles' `max_bounces` = `volume_bounces` = 8 (Cycles' 0 is direct light only): the same paths,
  eight bounces after the first vertex;
- box pixel filters one pixel wide in both (glint `filter` box radius 0.5, Cycles BOX 1.0 px),
  no denoiser, adaptive sampling, clamping or light threshold in Cycles, linear float EXR.

Cycles ray-marches volumes in steps of voxel size x `volume_step_rate` (biased); glint's path
tracer is unbiased (delta and ratio tracking against a majorant grid). The script measures:

1. `references`: glint's high-spp reference per scene (--ref-spp) and a second glint image at
   --mean-spp with another seed (the noise floor of the comparison), and Cycles at --mean-spp
   for each of --step-rates. Each image's mean over the volume's pixels (those that differ by
   more than 2% from a glint render without the medium) per channel, relative to glint's
   reference, and per 8 x 8 tile of them: the bias.
2. `ladder`: --rounds rounds, alternating the renderers (glint first in even rounds, Cycles in
   odd), each rendering --spp-levels with a new seed; each image's RMSE against its OWN
   converged reference (glint: the reference above; Cycles: its --mean-spp image at step rate
   1), corrected for the reference's own noise (x n_ref / (n_ref + n)). Times: glint's
   `render_seconds` (--stats: rendering only, no loading or building), Cycles' sampling time
   from its progress lines ("Sample 0/N" to "Finished": no start-up, VDB loading or scene sync;
   the render call including sync is recorded too).
3. `parts`: the fire with its blackbody emission alone and its flame emission alone (the
   other set to 0), both renderers at --parts-spp: Cycles against glint per channel and in
   luminance, which tells the colour of the blackbody from the rest.
4. `report`: for each Cycles image, the glint render time that reaches the same RMSE (log-log
   interpolation along glint's ladder of the same round) and the ratio of times, median and
   spread over levels and rounds, by render seconds and by CPU seconds (glint's process;
   Cycles' render call); the load before each run; a PNG per scene in --png-dir: glint,
   Cycles and their difference.

    /usr/bin/python3 benchmarks/cycles_vdb.py all --glint build-tests/glint \\
        --tool build-tests/tools/glint_make_vdb_scenes --work /tmp/cyc \\
        --out benchmarks/results/cycles_vdb.json

Needs `blender` (Debian 12: `apt-get install blender`, 3.4.1; not part of scripts/setup.sh),
/usr/bin/python3 with numpy and OpenImageIO (`apt-get install python3-openimageio`) and
`oiiotool`. Both renderers run with --threads threads (blender -t).
"""
import argparse
import datetime
import json
import math
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "accuracy"))
import conformance  # noqa: E402  (blender_env)
import helmet_equal_error as heq  # noqa: E402  (timed, Cycles' progress times, read_rgb, ...)
from accel_report import cpu_model  # noqa: E402

SCENES = ("cloud", "fire")
GLINT_DEPTH = 9  # scattering vertices; Cycles' bounces are one fewer (its 0: direct light)
CYCLES_BOUNCES = GLINT_DEPTH - 1
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])  # Rec.709 weights, for linear RGB

# ---------------------------------------------------------------------------------------------
# The Blender side: SCENE (glint's values, glint's axes) is filled in per scene.
# ---------------------------------------------------------------------------------------------

# Cycles' settings for a comparison, its film, a constant sky and the camera: Blender-side
# code shared with blender_fluid.py. It expects `scene`, `SCENE` (width, height, bounces, sky,
# camera in glint's axes), spp, seed, step_rate, threads and point() (glint to Blender axes).
CYCLES_COMMON = r'''
scene.render.engine = "CYCLES"
scene.render.resolution_x, scene.render.resolution_y = SCENE["width"], SCENE["height"]
scene.render.resolution_percentage = 100
scene.render.threads_mode = "FIXED"
scene.render.threads = threads
c = scene.cycles
c.device = "CPU"
c.samples = spp
c.seed = seed
c.use_animated_seed = False
c.use_adaptive_sampling = False
c.use_denoising = False
c.max_bounces = c.volume_bounces = c.diffuse_bounces = SCENE["bounces"]
c.glossy_bounces = c.transmission_bounces = SCENE["bounces"]
c.transparent_max_bounces = SCENE["bounces"]
c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
c.light_sampling_threshold = 0.0  # 0.01 by default: drops dim light samples (biased)
c.blur_glossy = 0.0
c.pixel_filter_type = "BOX"
c.filter_width = 1.0
c.volume_step_rate = step_rate
c.volume_max_steps = 65536  # 1024 by default: a long ray would stop marching early
scene.view_settings.view_transform = "Standard"
scene.view_settings.look = "None"
scene.view_settings.exposure = 0.0
scene.view_settings.gamma = 1.0

world = bpy.data.worlds.new("sky")
scene.world = world
world.use_nodes = True
bg = world.node_tree.nodes["Background"]
bg.inputs["Color"].default_value = (*SCENE["sky"], 1.0)
bg.inputs["Strength"].default_value = 1.0

cam_data = bpy.data.cameras.new("View")
cam_data.sensor_fit = "VERTICAL"
cam_data.angle_y = math.radians(SCENE["camera"]["yfov_degrees"])
cam_data.clip_start, cam_data.clip_end = 1e-3, 1e6
cam = bpy.data.objects.new("View", cam_data)
scene.collection.objects.link(cam)
scene.camera = cam
pos, look = point(SCENE["camera"]["position"]), point(SCENE["camera"]["look_at"])
cam.location = pos
cam.rotation_euler = (look - pos).to_track_quat("-Z", "Y").to_euler()
'''

BLENDER_SCRIPT = r'''
import json, math, sys
import bpy
from mathutils import Matrix, Vector

SCENE = json.loads(r"""@SCENE@""")
a = sys.argv[sys.argv.index("--") + 1:]
out, timing = a[0], a[5]
spp, seed, step_rate, threads = int(a[1]), int(a[2]), float(a[3]), int(a[4])

# glint (glTF, Y up) to Blender (Z up), as Blender's glTF importer converts:
# (x, y, z) -> (x, -z, y).
Y_UP = Matrix(((1, 0, 0, 0), (0, 0, -1, 0), (0, 1, 0, 0), (0, 0, 0, 1)))
def point(v):
    return (Y_UP @ Vector((v[0], v[1], v[2], 1.0))).xyz
def direction(v):
    return (Y_UP.to_3x3() @ Vector(v)).normalized()

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
''' + CYCLES_COMMON + r'''

for i, s in enumerate(SCENE["suns"]):
    light = bpy.data.lights.new(f"sun{i}", "SUN")
    light.energy = s["irradiance"]  # a sun's strength is its irradiance, W/m^2
    light.color = s["color"]
    light.angle = 0.0  # glint's directional light is a delta light
    obj = bpy.data.objects.new(f"sun{i}", light)
    obj.rotation_euler = direction(s["direction"]).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(obj)

for i, p in enumerate(SCENE["planes"]):
    half = 1e4
    o = point(p["point"])
    mesh = bpy.data.meshes.new(f"plane{i}")
    mesh.from_pydata([o + Vector((x, y, 0)) for x, y in ((-half, -half), (half, -half),
                      (half, half), (-half, half))], [], [(0, 1, 2, 3)])
    mat = bpy.data.materials.new(f"plane{i}")
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.remove(nodes["Principled BSDF"])
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (*p["diffuse"], 1.0)
    diffuse.inputs["Roughness"].default_value = 0.0  # Lambert
    mat.node_tree.links.new(diffuse.outputs[0], nodes["Material Output"].inputs["Surface"])
    mesh.materials.append(mat)
    obj = bpy.data.objects.new(f"plane{i}", mesh)
    scene.collection.objects.link(obj)

for i, m in enumerate(SCENE["volumes"]):
    vol = bpy.data.volumes.new(f"volume{i}")
    vol.filepath = m["file"]
    vol.grids.load()
    vol.render.precision = "FULL"  # HALF by default
    vol.render.space = "OBJECT"
    vol.render.step_size = 0.0  # from the voxel size, times the step rates
    vol.render.clipping = 0.0  # no voxel counts as empty (0.001 by default)
    obj = bpy.data.objects.new(f"volume{i}", vol)
    obj.matrix_world = Y_UP @ Matrix(m["matrix"])
    scene.collection.objects.link(obj)
    mat = bpy.data.materials.new(f"volume{i}")
    mat.use_nodes = True
    mat.cycles.volume_interpolation = "LINEAR"  # glint samples grids trilinearly
    mat.cycles.homogeneous_volume = False
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.remove(nodes["Principled BSDF"])
    pv = nodes.new("ShaderNodeVolumePrincipled")
    pv.inputs["Color"].default_value = (*m["color"], 1.0)
    pv.inputs["Density"].default_value = m["density"]
    pv.inputs["Density Attribute"].default_value = m["grid"]
    pv.inputs["Absorption Color"].default_value = (*m["absorption_color"], 1.0)
    pv.inputs["Anisotropy"].default_value = m["g"]
    pv.inputs["Blackbody Intensity"].default_value = m["blackbody_intensity"]
    pv.inputs["Blackbody Tint"].default_value = (1.0, 1.0, 1.0, 1.0)
    pv.inputs["Temperature"].default_value = m["temperature_scale"]
    pv.inputs["Temperature Attribute"].default_value = m["temperature_grid"]
    pv.inputs["Emission Color"].default_value = (*m["flame_color"], 1.0)
    pv.inputs["Emission Strength"].default_value = 0.0
    if m["flame_grid"]:
        attr = nodes.new("ShaderNodeAttribute")
        attr.attribute_type = "GEOMETRY"
        attr.attribute_name = m["flame_grid"]
        mul = nodes.new("ShaderNodeMath")
        mul.operation = "MULTIPLY"
        mul.inputs[1].default_value = m["flame_strength"]
        links.new(attr.outputs["Fac"], mul.inputs[0])
        links.new(mul.outputs[0], pv.inputs["Emission Strength"])
    links.new(pv.outputs[0], nodes["Material Output"].inputs["Volume"])
    vol.materials.append(mat)

scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
scene.render.image_settings.exr_codec = "ZIP"
timing_extra = {"blender": bpy.app.version_string, "sampling_pattern": c.sampling_pattern}
''' + heq.TIMED_RENDER

# ---------------------------------------------------------------------------------------------
# glint's scene, and the same values for Cycles
# ---------------------------------------------------------------------------------------------


def transform_matrix(ops):
    """glint's `transform` (a 4x4 row-major matrix or a list of operations, first applied
    first) as a 4x4 numpy matrix; the operations these scenes use."""
    if not ops:
        return np.eye(4)
    if isinstance(ops[0], (int, float)) or isinstance(ops[0], list):
        return np.array(ops, dtype=float).reshape(4, 4)
    m = np.eye(4)
    for op in ops:
        step = np.eye(4)
        if "translate" in op:
            step[:3, 3] = op["translate"]
        elif "scale" in op:
            s = op["scale"]
            step[:3, :3] = np.diag([s] * 3 if isinstance(s, (int, float)) else s)
        elif "matrix" in op:
            step = np.array(op["matrix"], dtype=float).reshape(4, 4)
        else:
            sys.exit(f"cycles_vdb: transform operation {op} not translated")
        m = step @ m
    return m


def rgb(v):
    return np.array([v] * 3 if isinstance(v, (int, float)) else v, dtype=float)


def principled_volume(medium):
    """Principled Volume inputs giving glint's sigma_s and sigma_a (Cycles 3.4: scattering
    Color x D, absorption (1 - Color)(1 - sqrt(Absorption Color)) D, both times the grid)."""
    d = medium["density"]
    scale = d.get("scale", 1.0)
    sigma_s, sigma_a = rgb(medium.get("sigma_s", 0)), rgb(medium.get("sigma_a", 0))
    if np.any(rgb(medium.get("emission", 0)) > 0) or d.get("temperature_offset", 0) != 0:
        sys.exit("cycles_vdb: a medium's `emission` or `temperature_offset` is not translated")
    density = float((sigma_s + sigma_a).max())
    color = sigma_s / density
    room = density - sigma_s  # what (1 - Color) D leaves for absorption
    keep = np.where(room > 0, 1 - sigma_a / np.where(room > 0, room, 1), 0)
    has_temperature = bool(d.get("temperature_grid"))
    has_flame = bool(d.get("flame_grid"))
    return {"density": density * scale, "color": color.tolist(),
            "absorption_color": (keep ** 2).tolist(), "g": medium.get("g", 0.0),
            "grid": d.get("grid", "density"),
            "temperature_grid": d.get("temperature_grid", ""),
            "temperature_scale": d.get("temperature_scale", 1.0),
            "blackbody_intensity": d.get("blackbody_intensity", 1.0) if has_temperature else 0.0,
            "flame_grid": d.get("flame_grid", ""),
            "flame_strength": d.get("flame_strength", 1.0) if has_flame else 0.0,
            "flame_color": d.get("flame_color", [1, 1, 1])}


def glint_scene(args, name, with_medium=True, density_patch=None, tag=""):
    """scenes/volumes/NAME.json at --width x --height, box filter, depth GLINT_DEPTH, the VDB
    from --work, `density_patch` over each medium's density keys; returns (path, the scene)."""
    with open(os.path.join(ROOT, "scenes", "volumes", name + ".json")) as f:
        s = json.load(f)
    s["render"].update({"width": args.width, "height": args.height,
                        "filter": {"type": "box", "radius": 0.5}})
    s["render"]["integrator"] = {"type": "path", "max_depth": GLINT_DEPTH}
    for m in s.get("media", []):
        m["density"]["file"] = os.path.join(args.work, os.path.basename(m["density"]["file"]))
        m["density"].update(density_patch or {})
    if not with_medium:
        del s["media"]
    path = os.path.join(args.work, f"{name}{'' if with_medium else '_empty'}{tag}.json")
    with open(path, "w") as f:
        json.dump(s, f, indent=1)
    return path, s


def cycles_scene(s):
    """The values the Blender script needs, from glint's parsed scene."""
    cam = s["cameras"][0]
    if cam.get("up", [0, 1, 0]) != [0, 1, 0] or "transform" in cam:
        sys.exit("cycles_vdb: only position/look_at cameras with up +Y are translated")
    env = s.get("environment", {})
    if "color" not in env:
        sys.exit("cycles_vdb: only a constant environment colour is translated")
    out = {"width": s["render"]["width"], "height": s["render"]["height"],
           "bounces": CYCLES_BOUNCES, "camera": cam,
           "sky": (rgb(env["color"]) * env.get("intensity", 1.0)).tolist(),
           "suns": [], "planes": [], "volumes": []}
    for light in s.get("lights", []):
        if light["type"] != "directional":
            sys.exit(f"cycles_vdb: light type {light['type']} not translated")
        out["suns"].append({"direction": light["direction"],
                            "irradiance": light.get("intensity", 1),
                            "color": light.get("color", [1, 1, 1])})
    materials = {m["name"]: m for m in s.get("materials", [])}
    for o in s.get("objects", []):
        if o["type"] != "plane" or o.get("normal", [0, 1, 0]) != [0, 1, 0]:
            sys.exit("cycles_vdb: only ground planes (normal +Y) are translated")
        mat = materials[o["material"]]
        out["planes"].append({"point": o.get("point", [0, 0, 0]), "diffuse": mat["diffuse"]})
    for m in s.get("media", []):
        v = principled_volume(m)
        v["file"] = m["density"]["file"]
        v["matrix"] = transform_matrix(m.get("transform")).tolist()
        out["volumes"].append(v)
    return out


def write_blender_script(args, name, s, tag=""):
    path = os.path.join(args.work, f"cycles_{name}{tag}.py")
    with open(path, "w") as f:
        f.write(BLENDER_SCRIPT.replace("@SCENE@", json.dumps(cycles_scene(s))))
    return path


# ---------------------------------------------------------------------------------------------
# Renders
# ---------------------------------------------------------------------------------------------


def render_glint(args, json_path, spp, seed, exr):
    stats = exr[:-4] + ".stats.json"
    cmd = [args.glint, "render", json_path, "--spp", str(spp), "--seed", str(seed), "--threads",
           str(args.threads), "--quiet", "--stats", stats, "-o", exr]
    load = heq.load_average()
    wall, cpu = heq.timed(cmd, exr[:-4] + ".log")
    with open(stats) as f:
        st = json.load(f)
    st = st["frames"][0] if "frames" in st else st
    return {"renderer": "glint", "spp": spp, "seed": seed, "image": exr, "load_before": load,
            "wall_seconds": wall, "cpu_seconds": cpu, "render_seconds": st["render_seconds"]}


def render_cycles(args, script, spp, seed, step_rate, exr):
    timing = exr[:-4] + ".timing.json"
    log_path = exr[:-4] + ".log"
    cmd = [args.blender, "-b", "--factory-startup", "-noaudio", "-t", str(args.threads),
           "--python", script, "--", exr, str(spp), str(seed), str(step_rate),
           str(args.threads), timing]
    load = heq.load_average()
    wall, cpu = heq.timed(cmd, log_path, env=conformance.blender_env())
    with open(timing) as f:
        t = json.load(f)
    with open(log_path, errors="replace") as f:
        sampling, sync = heq.cycles_sampling_seconds(f.read())
    return {"renderer": "cycles", "spp": spp, "seed": seed, "step_rate": step_rate, "image": exr,
            "load_before": load, "wall_seconds": wall, "cpu_seconds": cpu,
            "render_seconds": sampling, "render_call_seconds": t["render_call_seconds"],
            "render_call_cpu_seconds": t["render_call_cpu_seconds"], "sync_seconds": sync,
            "blender": t["blender"], "sampling_pattern": t["sampling_pattern"]}


def append(args, record):
    heq.append(os.path.join(args.work, "records.jsonl"), record)
    print(json.dumps({k: v for k, v in record.items() if k != "image"}), flush=True)


def records(args):
    return heq.read_records(os.path.join(args.work, "records.jsonl"))


def prepare(args):
    os.makedirs(args.work, exist_ok=True)
    subprocess.run([args.tool, args.work], check=True, capture_output=True)
    out = {}
    for name in args.scenes:
        path, s = glint_scene(args, name)
        out[name] = {"glint": path, "cycles": write_blender_script(args, name, s),
                     "empty": glint_scene(args, name, with_medium=False)[0]}
    return out


def references(args, scenes):
    for name, p in scenes.items():
        w = f"{args.work}/{name}"
        append(args, dict(render_glint(args, p["glint"], args.ref_spp, 1, f"{w}_glint_ref.exr"),
                          scene=name, kind="reference"))
        append(args, dict(render_glint(args, p["glint"], args.mean_spp, 2, f"{w}_glint_mean.exr"),
                          scene=name, kind="mean"))
        append(args, dict(render_glint(args, p["empty"], 64, 3, f"{w}_glint_empty.exr"),
                          scene=name, kind="empty"))
        for rate in args.step_rates:
            # Cycles' step is the voxel size times the rate: below rate 1 the finer steps cost
            # more per sample, so spp x rate (about the same time).
            spp = max(16, int(args.mean_spp * min(rate, 1.0)))
            exr = f"{w}_cycles_mean_rate{rate:g}.exr"
            append(args, dict(render_cycles(args, p["cycles"], spp, 1, rate, exr),
                              scene=name, kind="mean"))


def ladder(args, scenes):
    for rnd in range(args.rounds):
        order = ("glint", "cycles") if rnd % 2 == 0 else ("cycles", "glint")
        for name, p in scenes.items():
            for renderer in order:
                for spp in args.spp_levels:
                    seed = 1000 + 100 * rnd + spp
                    exr = f"{args.work}/{name}_{renderer}_r{rnd}_{spp}.exr"
                    r = (render_glint(args, p["glint"], spp, seed, exr) if renderer == "glint" else
                         render_cycles(args, p["cycles"], spp, seed, 1.0, exr))
                    append(args, dict(r, scene=name, kind="ladder", round=rnd))


# The fire's two emissions apart: each renderer with the other one off.
FIRE_PARTS = {"blackbody": {"flame_strength": 0}, "flame": {"blackbody_intensity": 0}}


def fire_parts(args):
    for part, patch in FIRE_PARTS.items():
        tag = "_" + part
        path, s = glint_scene(args, "fire", density_patch=patch, tag=tag)
        script = write_blender_script(args, "fire", s, tag)
        exr = f"{args.work}/fire{tag}"
        append(args, dict(render_glint(args, path, args.parts_spp, 7, exr + "_glint.exr"),
                          scene="fire", kind="part", part=part))
        append(args, dict(render_cycles(args, script, args.parts_spp, 7, 1.0, exr + "_cycles.exr"),
                          scene="fire", kind="part", part=part))


# ---------------------------------------------------------------------------------------------
# Analysis
# ---------------------------------------------------------------------------------------------


def volume_mask(ref, empty):
    """The pixels the volume changes by more than 2% of the brighter image (luminance)."""
    a, b = ref @ LUMINANCE, empty @ LUMINANCE
    return np.abs(a - b) > 0.02 * np.maximum(np.maximum(a, b), 1e-3)


def bias_row(img, ref, mask, block=8):
    """The image's mean over the volume's pixels against the reference's, per channel; and
    per block x block tile (at least half of it the volume's) the relative difference of the
    luminance means: a local bias (brighter edges, a darker core) would show there where the
    whole mean could hide it. Noise alone gives the tiles of a second glint image."""
    m, r = img[mask].mean(axis=0), ref[mask].mean(axis=0)
    whole = img.mean(axis=0).mean(axis=0) / ref.mean(axis=0).mean(axis=0) - 1
    tiles = []
    for y in range(0, img.shape[0] - block + 1, block):
        for x in range(0, img.shape[1] - block + 1, block):
            k = mask[y:y + block, x:x + block]
            if k.sum() >= block * block // 2:
                a = img[y:y + block, x:x + block][k] @ LUMINANCE
                b = ref[y:y + block, x:x + block][k] @ LUMINANCE
                tiles.append(a.mean() / b.mean() - 1)
    tiles = np.abs(np.array(tiles))
    return {"volume_relative_mean_difference_rgb": (m / r - 1).tolist(),
            "image_relative_mean_difference_rgb": whole.tolist(),
            "volume_pixels": int(mask.sum()), "tiles": len(tiles),
            "tile_abs_relative_difference_median": float(np.median(tiles)),
            "tile_abs_relative_difference_p95": float(np.percentile(tiles, 95))}


def side_by_side(path, diff, left, right):
    """A side-by-side PNG at `path`, sRGB through oiiotool: glint (`left`), Cycles (`right`),
    and 0.5 + 4 x (Cycles - glint), kept as the EXR `diff` (uniform grey: equal; brighter or
    coloured: Cycles above glint)."""
    subprocess.run(["oiiotool", right, "--ch", "R,G,B", left, "--ch", "R,G,B", "--sub",
                    "--mulc", "4", "--addc", "0.5", "-o", diff], check=True)
    subprocess.run(["oiiotool", left, "--ch", "R,G,B", right, "--ch", "R,G,B", diff,
                    "--mosaic", "3x1", "--colorconvert", "linear", "sRGB", "-d", "uint8",
                    "-o", path], check=True)


def png(args, name, left, right):
    """side_by_side into --png-dir as cycles_vdb_NAME.png; its path from the repository."""
    path = os.path.join(args.png_dir, f"cycles_vdb_{name}.png")
    side_by_side(path, os.path.join(args.work, f"{name}_diff.exr"), left, right)
    return os.path.relpath(path, ROOT)


def time_for_error(rows, error, key):
    """glint's `key` seconds at `error` along its ladder [(seconds, rmse)] (log-log)."""
    curve = sorted((r[key], r["rmse_corrected"]) for r in rows)
    for (t0, e0), (t1, e1) in zip(curve, curve[1:]):
        if e0 >= error >= e1:
            f = (math.log(e0) - math.log(error)) / (math.log(e0) - math.log(e1))
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0)))
    t, e = curve[-1] if error < curve[-1][1] else curve[0]
    return t * (e / error) ** 2  # beyond the ladder: error ~ 1/sqrt(time)


# (label, glint's key, Cycles' key): render seconds (glint's rendering; Cycles' sampling, no
# sync), and CPU seconds (glint's whole process; Cycles' render call, sync included), which
# hold better than wall time on a loaded machine.
TIMES = (("render", "render_seconds", "render_seconds"),
         ("cpu", "cpu_seconds", "render_call_cpu_seconds"))


def equal_error(ladder_rows):
    """For each Cycles image, the glint time at its RMSE along glint's ladder of the same round,
    and the ratio (above 1: glint reaches that error sooner)."""
    out = []
    for rnd in sorted({r["round"] for r in ladder_rows}):
        g = [r for r in ladder_rows if r["round"] == rnd and r["renderer"] == "glint"]
        for c in (r for r in ladder_rows if r["round"] == rnd and r["renderer"] == "cycles"):
            row = {"round": rnd, "cycles_spp": c["spp"], "cycles_rmse": c["rmse_corrected"]}
            for label, gkey, ckey in TIMES:
                t = time_for_error(g, c["rmse_corrected"], gkey)
                row.update({f"cycles_{label}": c[ckey], f"glint_{label}": t,
                            f"speed_{label}": c[ckey] / t})
            out.append(row)
    return out


def analyse(args):
    recs = records(args)
    result = {"date": datetime.date.today().isoformat(), "machine": cpu_model(),
              "cores": os.cpu_count(), "threads": args.threads, "width": args.width,
              "height": args.height, "glint_depth": GLINT_DEPTH, "cycles_bounces": CYCLES_BOUNCES,
              "scenes": {}}
    for name in args.scenes:
        rs = [r for r in recs if r["scene"] == name]
        find = lambda **kw: [r for r in rs if all(r.get(k) == v for k, v in kw.items())]  # noqa
        ref_rec = find(renderer="glint", kind="reference")[-1]
        ref = heq.read_rgb(ref_rec["image"])
        mask = volume_mask(ref, heq.read_rgb(find(kind="empty")[-1]["image"]))
        out = {"reference": {k: v for k, v in ref_rec.items() if k != "image"}, "bias": []}
        for r in find(kind="mean"):
            row = {k: r.get(k) for k in ("renderer", "spp", "step_rate", "render_seconds",
                                         "load_before")}
            row.update(bias_row(heq.read_rgb(r["image"]), ref, mask))
            out["bias"].append(row)
        for part in FIRE_PARTS:
            pair = {r["renderer"]: heq.read_rgb(r["image"]) for r in find(kind="part", part=part)}
            if len(pair) == 2:
                row = bias_row(pair["cycles"], pair["glint"], mask)
                row["volume_relative_luminance_difference"] = float(
                    (pair["cycles"][mask] @ LUMINANCE).mean() /
                    (pair["glint"][mask] @ LUMINANCE).mean() - 1)
                out.setdefault("parts_cycles_vs_glint", {})[part] = row
        cyc_ref = find(renderer="cycles", kind="mean", step_rate=1.0)[-1]
        out["png"] = png(args, name, find(renderer="glint", kind="mean")[-1]["image"],
                         cyc_ref["image"])
        own = {"glint": (ref, ref_rec["spp"]), "cycles": (heq.read_rgb(cyc_ref["image"]),
                                                           cyc_ref["spp"])}
        ladder_rows = find(kind="ladder")
        for r in ladder_rows:
            img = heq.read_rgb(r["image"])
            r.update(heq.errors(img, own[r["renderer"]][0], r["spp"], own[r["renderer"]][1]))
        out["ladder"] = [{k: v for k, v in r.items() if k != "image"} for r in ladder_rows]
        out["equal_error"] = equal_error(ladder_rows)
        for label, _, _ in TIMES:
            speeds = [x[f"speed_{label}"] for x in out["equal_error"]]
            if speeds:
                out[f"speed_{label}"] = heq.median_spread(speeds)
        out["levels"] = {}
        for r in ladder_rows:
            out["levels"].setdefault(f"{r['renderer']} {r['spp']}", []).append(r)
        out["levels"] = {k: {key: heq.median_spread([r[key] for r in rs]) for key in
                             ("rmse_corrected", "render_seconds", "cpu_seconds",
                              "render_call_cpu_seconds")
                             if all(r.get(key) is not None for r in rs)}
                         for k, rs in out["levels"].items()}
        out["loads"] = [r["load_before"][0] for r in ladder_rows]
        result["scenes"][name] = out
    return result


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("phase", choices=("scripts", "references", "ladder", "parts", "report",
                                      "all"))
    ap.add_argument("--glint", required=True)
    ap.add_argument("--tool", required=True, help="glint_make_vdb_scenes")
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--work", required=True)
    ap.add_argument("--width", type=int, default=160)
    ap.add_argument("--height", type=int, default=90)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--ref-spp", type=int, default=4096)
    ap.add_argument("--mean-spp", type=int, default=1024)
    ap.add_argument("--step-rates", type=float, nargs="+", default=[1.0, 0.25, 4.0])
    ap.add_argument("--spp-levels", type=int, nargs="+", default=[4, 16, 64, 256])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--parts-spp", type=int, default=512)
    ap.add_argument("--png-dir", default=os.path.join(HERE, "results"))
    ap.add_argument("--out", default=os.path.join(HERE, "results", "cycles_vdb.json"))
    ap.add_argument("--scenes", nargs="+", choices=list(SCENES), default=list(SCENES))
    args = ap.parse_args()
    args.work = os.path.abspath(args.work)
    scenes = prepare(args)
    if args.phase in ("references", "all"):
        references(args, scenes)
    if args.phase in ("ladder", "all"):
        ladder(args, scenes)
    if args.phase in ("parts", "all") and "fire" in args.scenes:
        fire_parts(args)
    if args.phase in ("report", "all"):
        result = analyse(args)
        with open(args.out, "w") as f:
            json.dump(result, f, indent=1)
        for name, s in result["scenes"].items():
            for b in s["bias"]:
                print(name, b["renderer"], b.get("step_rate"), b["spp"],
                      " ".join(f"{v:+.4f}" for v in b["volume_relative_mean_difference_rgb"]))
            for part, b in s.get("parts_cycles_vs_glint", {}).items():
                print(name, part, "only, Cycles against glint",
                      " ".join(f"{v:+.4f}" for v in b["volume_relative_mean_difference_rgb"]),
                      f"luminance {b['volume_relative_luminance_difference']:+.4f}")
            for label, _, _ in TIMES:
                if f"speed_{label}" in s:
                    print(name, f"speed at equal error ({label})", s[f"speed_{label}"])


if __name__ == "__main__":
    main()
