#!/usr/bin/env python3
"""glint's speed against Blender Cycles at equal error, case by case, beside their FLIP.

For each case both renderers render the same camera, image and sky (conformance.py's harness:
a uniform white sky of radiance 1, path depth 8, box pixel filters one pixel wide, no denoising,
adaptive sampling, clamping or glossy filter in Cycles) twice at the same spp with different
seeds, interleaved (glint, Cycles, glint, Cycles). Half the mean squared difference of a
renderer's two images is its variance at that spp; times spp it is the variance of one sample.
A renderer's cost at an error e is then variance-per-sample / e² samples, each costing its
render time per sample, so

    speed (glint against Cycles, equal error) = (v_Cycles * t_Cycles) / (v_glint * t_glint)

with v the per-sample variance and t the render seconds per sample (glint's `render_seconds`;
Cycles' render call, which includes its scene sync, and its sampling alone from its progress
lines), or the render CPU seconds per sample (glint's process CPU less a one-pixel render's;
Cycles' CPU during its render call), which holds better on a loaded machine. Above 1 glint reaches a given error sooner. It measures noise only (each renderer against
itself); FLIP between the two renderers' first images shows they render the same thing.
This assumes both renderers' variance falls as 1/spp around the chosen spp; helmet_equal_error.py
measures whole ladders instead, for one case.

    /usr/bin/python3 benchmarks/equal_error_speed.py --glint build-rel/glint --work /tmp/eq \\
        --out benchmarks/results/equal_error_speed

Cases: DamagedHelmet with helmet_equal_error.py's camera (400x400), and a textured conformance
subset (BoxTextured, NormalTangentTest, CesiumMan, TextureSettingsTest) with conformance.py's
camera (400x300). Both renderers run on --threads threads; run it on an idle machine.
"""
import argparse
import json
import math
import os
import statistics
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import conformance  # noqa: E402
import helmet_equal_error as helmet  # noqa: E402

SUBSET = ("BoxTextured", "NormalTangentTest", "CesiumMan", "TextureSettingsTest")


def case_list(args):
    out = []
    helmet_path = os.path.join(args.assets, "gltf", "DamagedHelmet", "glTF", "DamagedHelmet.gltf")
    out.append({"case": "DamagedHelmet", "path": helmet_path, "width": helmet.WIDTH,
                "height": helmet.HEIGHT, "position": helmet.POSITION, "look_at": helmet.LOOK_AT,
                "fov": helmet.YFOV})
    for name in SUBSET:
        path = os.path.join(args.assets, "gltf", name, "glTF", name + ".gltf")
        lo, hi, _ = conformance.bounds(args.glint, path)
        pos, look = conformance.camera(lo, hi, 40, 4 / 3)
        out.append({"case": name, "path": path, "width": 400, "height": 300, "position": pos,
                    "look_at": look, "fov": 40})
    if args.only:
        out = [c for c in out if args.only in c["case"]]
    return out


def render_glint(args, case, seed, exr):
    sidecar = exr[:-4] + ".glint.json"
    with open(sidecar, "w") as f:
        json.dump({"environment": {"color": [1, 1, 1]},
                   "render": {"width": case["width"], "height": case["height"],
                              "filter": {"type": "box", "radius": 0.5}},
                   "cameras": [{"name": "front", "position": case["position"],
                                "look_at": case["look_at"], "up": [0, 1, 0],
                                "yfov_degrees": case["fov"], "znear": 0.001, "zfar": 1e6}]}, f)
    stats = exr[:-4] + ".stats.json"
    base = [args.glint, "render", case["path"], "--sidecar", sidecar, "--integrator", "path",
            "--max-depth", "8", "--threads", str(args.threads), "--quiet"]
    cmd = base + ["--spp", str(args.spp), "--seed", str(seed), "--stats", stats, "-o", exr]
    wall, cpu = helmet.timed(cmd, exr[:-4] + ".log")
    with open(stats) as f:
        s = json.load(f)
    # Render CPU: the process's CPU less that of a one-pixel render of the same scene (loading,
    # decoding, building), as helmet_equal_error.py estimates it.
    setup = base + ["--crop", "0,0,1,1", "--spp", "1", "-o", exr[:-4] + "_setup.exr"]
    _, setup_cpu = helmet.timed(setup, exr[:-4] + "_setup.log")
    return {"wall_seconds": wall, "cpu_seconds": cpu, "render_seconds": s["render_seconds"],
            "render_cpu_seconds": cpu - setup_cpu}


def render_cycles(args, case, seed, exr):
    timing = exr[:-4] + ".timing.json"
    log_path = exr[:-4] + ".log"
    cmd = [args.blender, "-b", "-t", str(args.threads), "-P", args.blender_script, "--",
           case["path"], exr, str(case["width"]), str(case["height"]), str(args.spp),
           *map(str, case["position"]), *map(str, case["look_at"]), str(case["fov"]), str(seed),
           timing, str(args.threads)]
    wall, cpu = helmet.timed(cmd, log_path, env=conformance.blender_env())
    with open(timing) as f:
        t = json.load(f)
    with open(log_path, errors="replace") as f:
        text = f.read()

    sampling, _ = helmet.cycles_sampling_seconds(text)
    return {"wall_seconds": wall, "cpu_seconds": cpu, "render_seconds": t["render_call_seconds"],
            "render_cpu_seconds": t["render_call_cpu_seconds"], "sampling_seconds": sampling}


def per_sample_variance(a, b, spp):
    d = a - b
    return float(np.mean(d * d)) / 2 * spp


def flip(glint, a, b):
    r = subprocess.run([glint, "diff", a, b, "--flip", "--json"], capture_output=True, text=True)
    return json.loads(r.stdout)["flip"]["mean"] if r.stdout.strip() else None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--glint", required=True)
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--assets", default=os.environ.get(
        "GLINT_ASSETS", os.path.join(conformance.ROOT, "..", "shared", "assets")))
    ap.add_argument("--work", required=True)
    ap.add_argument("--out", default=os.path.join(conformance.ROOT, "benchmarks", "results",
                                                  "equal_error_speed"))
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--only", help="run only cases whose name contains this")
    ap.add_argument("--note", default="", help="recorded in the results: the binary's origin")
    args = ap.parse_args()
    args.glint = os.path.abspath(args.glint)
    os.makedirs(args.work, exist_ok=True)
    os.makedirs(args.out, exist_ok=True)
    args.blender_script = os.path.join(args.work, "cycles.py")
    with open(args.blender_script, "w") as f:
        f.write(helmet.blender_script())
    rows = []
    for case in case_list(args):
        row = {"case": case["case"], "spp": args.spp, "load_before": helmet.load_average()}
        runs = {"glint": [], "cycles": []}
        for seed in (1, 2):
            for name, fn in (("glint", render_glint), ("cycles", render_cycles)):
                exr = os.path.join(args.work, f"{case['case']}_{name}_{seed}.exr")
                r = fn(args, case, seed, exr)
                r["image"] = exr
                runs[name].append(r)
                print(json.dumps({"case": case["case"], "renderer": name, "seed": seed, **r}),
                      flush=True)
        for name in runs:
            a, b = (helmet.read_rgb(r["image"]) for r in runs[name])
            row[f"{name}_variance"] = per_sample_variance(a, b, args.spp)
            for key in ("render_seconds", "render_cpu_seconds", "sampling_seconds", "cpu_seconds",
                        "wall_seconds"):
                values = [r.get(key) for r in runs[name]]
                if all(v is not None for v in values):
                    row[f"{name}_{key}"] = values
            row[f"{name}_tails"] = helmet.tails(a)
        for label, gkey, ckey in (("render", "glint_render_seconds", "cycles_render_seconds"),
                                  ("sampling", "glint_render_seconds", "cycles_sampling_seconds"),
                                  ("render_cpu", "glint_render_cpu_seconds",
                                   "cycles_render_cpu_seconds")):
            if gkey in row and ckey in row:
                g_t = statistics.mean(row[gkey]) / args.spp
                c_t = statistics.mean(row[ckey]) / args.spp
                row[f"speed_{label}"] = (row["cycles_variance"] * c_t) / (row["glint_variance"] * g_t)
        row["flip_mean"] = flip(args.glint, runs["glint"][0]["image"], runs["cycles"][0]["image"])
        rows.append(row)
        print(json.dumps(row), flush=True)
    with open(os.path.join(args.out, "equal_error_speed.json"), "w") as f:
        json.dump({"note": args.note, "machine": helmet.cpu_model(), "threads": args.threads,
                   "spp": args.spp, "rows": rows}, f, indent=1)
    with open(os.path.join(args.out, "equal_error_speed.md"), "w") as f:
        f.write("| case | FLIP mean | glint variance / sample | Cycles variance / sample "
                "| glint render s | Cycles render s (sampling s) | speed at equal error, "
                "by render s (by Cycles' sampling s) | by render CPU s |\n"
                "|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            gs = "/".join(f"{v:.2f}" for v in r["glint_render_seconds"])
            cs = "/".join(f"{v:.2f}" for v in r["cycles_render_seconds"])
            ss = ("/".join(f"{v:.2f}" for v in r["cycles_sampling_seconds"])
                  if "cycles_sampling_seconds" in r else "?")
            f.write(f"| {r['case']} | {r['flip_mean']:.3f} | {r['glint_variance']:.4g} "
                    f"| {r['cycles_variance']:.4g} | {gs} | {cs} ({ss}) "
                    f"| **{r['speed_render']:.2f}** ({r.get('speed_sampling', math.nan):.2f}) "
                    f"| {r.get('speed_render_cpu', math.nan):.2f} |\n")
    print(open(os.path.join(args.out, "equal_error_speed.md")).read())


if __name__ == "__main__":
    main()
