#!/usr/bin/env python3
"""The majorant grid against glint's single-majorant tracker on a sparse VDB cloud, at equal error.

The cloud is scenes/volumes/cloud.vdb (tools/make_vdb_scenes.cpp: a cumulus with a dense core in
a mostly empty box) in scenes/volumes/cloud.json (sun and sky, path tracer, depth 8), rendered at
--width x --height with `majorant_cells` --cells (the grid; 16 by default) and 1 (one
majorant for the whole volume, the tracker every other medium uses). Each variant renders twice at the same spp with different
seeds, interleaved (grid, single, grid, single) so that a change in the machine's load falls on
both; --rounds repeats that. Half the mean squared difference of a variant's two images is its
variance at that spp; times spp, the variance of one sample. With t the render seconds per
sample (`render_seconds` of --stats),

    speed of the grid at equal error = (v_single * t_single) / (v_grid * t_grid)

Both trackers are unbiased, so the variance is the error; the mean squared difference comes
from `glint diff --json` (its rmse, over R, G, B and A alike for both variants, so the ratio
holds). The script also compares each round's first grid and single images with `glint diff
--statistical` (both carry their variance, --aovs): the same image up to noise, or not. From
--stats: the delta tracker's tentative collisions per real one ("null per real") and the ratio
tracker's collisions.

    python3 benchmarks/vdb_majorant.py --glint build/glint --tool build/tools/glint_make_vdb_scenes \\
        --work /tmp/vdbm --rounds 3 --out benchmarks/results/vdb_majorant_16.json

With --scene, any scene whose first medium is a VDB (a Blender cache, say: the scene written by
`blender_fluid.py`) takes the cloud's place, at its own resolution unless --width and --height
say otherwise; relative `.vdb` paths are resolved from the scene's folder.

    python3 benchmarks/vdb_majorant.py --glint build/glint --scene /tmp/bfl/fire.json \\
        --work /tmp/vdbm_blender --rounds 3 --out /tmp/vdbm_blender.json

Memory: with --memory-size N it also writes an N-voxel-wide cloud and reports the process's
peak resident memory rendering it (1 spp) against the same scene without the medium, beside
the OpenVDB grid's own in-memory size (`glint info`) and glint's (NanoVDB + majorant grid).
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import accel_report  # noqa: E402


def scene(work, vdb, cells, width, height, with_medium=True, source=None):
    """The scene to render: the cloud of scenes/volumes/ with the file `vdb`, or `source` with its
    own file (made absolute), its first medium's majorant grid `cells` wide."""
    cloud = os.path.join(ROOT, "scenes", "volumes", "cloud.json")
    with open(source or cloud) as f:
        s = json.load(f)
    if width:
        s["render"]["width"] = width
    if height:
        s["render"]["height"] = height
    if with_medium:
        density = s["media"][0]["density"]
        if source:
            density["file"] = os.path.join(os.path.dirname(os.path.abspath(source)),
                                           density["file"])
        else:
            density["file"] = vdb
        density["majorant_cells"] = cells
    else:
        del s["media"]
    name = os.path.splitext(os.path.basename(source or cloud))[0]
    path = os.path.join(work, f"{name}_{cells if with_medium else 'none'}.json")
    with open(path, "w") as f:
        json.dump(s, f)
    return path


def render(args, json_path, spp, seed, exr):
    stats = exr[:-4] + ".stats.json"
    cmd = [args.glint, "render", json_path, "--spp", str(spp), "--seed", str(seed), "--threads",
           str(args.threads), "--quiet", "--aovs", "--stats", stats, "-o", exr]
    subprocess.run(cmd, check=True)
    with open(stats) as f:
        return json.load(f)


def diff(args, a, b, *extra):
    r = subprocess.run([args.glint, "diff", a, b, "--json", *extra], capture_output=True,
                       text=True)
    return json.loads(r.stdout)


def load_average():
    with open("/proc/loadavg") as f:
        return float(f.read().split()[0])


def frame_stats(s):
    return s["frames"][0] if "frames" in s else s


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--glint", required=True)
    ap.add_argument("--tool", help="glint_make_vdb_scenes (for the cloud and --memory-size)")
    ap.add_argument("--scene", help="a scene whose first medium is a VDB, instead of the cloud")
    ap.add_argument("--work", required=True)
    ap.add_argument("--width", type=int, help="320 for the cloud; --scene's own by default")
    ap.add_argument("--height", type=int, help="180 for the cloud; --scene's own by default")
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--cells", type=int, default=16, help="the grid's majorant_cells")
    ap.add_argument("--memory-size", type=int, default=0)
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    if not args.scene:
        args.width, args.height = args.width or 320, args.height or 180
    if (not args.scene or args.memory_size) and not args.tool:
        ap.error("--tool is needed for the cloud and for --memory-size")
    os.makedirs(args.work, exist_ok=True)
    vdb = None
    if not args.scene:
        subprocess.run([args.tool, args.work], check=True, capture_output=True)
        vdb = os.path.join(args.work, "cloud.vdb")
    paths = {"grid": scene(args.work, vdb, args.cells, args.width, args.height, source=args.scene),
             "single": scene(args.work, vdb, 1, args.width, args.height, source=args.scene)}
    rounds = []
    for rnd in range(args.rounds):
        row = {"load_before": load_average()}
        images = {k: [] for k in paths}
        for seed in (1, 2):
            for name, path in paths.items():
                exr = os.path.join(args.work, f"{name}_{rnd}_{seed}.exr")
                s = frame_stats(render(args, path, args.spp, 100 * rnd + seed, exr))
                images[name].append(exr)
                row.setdefault(f"{name}_render_seconds", []).append(s["render_seconds"])
                row[f"{name}_tracking"] = s.get("tracking_collisions")
        for name in paths:
            a, b = images[name]
            row[f"{name}_variance"] = diff(args, a, b)["rmse"] ** 2 / 2 * args.spp
        same = diff(args, images["grid"][0], images["single"][0], "--statistical")
        row["grid_vs_single"] = {k: same.get(k) for k in ("verdict", "pass_percent", "global_z",
                                                          "biased", "mean_z2")}
        t = {n: statistics.mean(row[f"{n}_render_seconds"]) / args.spp for n in paths}
        row["speed"] = (row["single_variance"] * t["single"]) / (row["grid_variance"] * t["grid"])
        rounds.append(row)
        print(json.dumps(row), flush=True)
    speeds = [r["speed"] for r in rounds]
    result = {"scene": args.scene or "scenes/volumes/cloud.json", "cells": args.cells,
              "width": args.width, "height": args.height, "spp": args.spp,
              "threads": args.threads, "machine": accel_report.cpu_model(), "rounds": rounds,
              "speed_median": statistics.median(speeds), "speed_min": min(speeds),
              "speed_max": max(speeds)}
    if args.memory_size:
        mem = os.path.join(args.work, "memory")
        os.makedirs(mem, exist_ok=True)
        subprocess.run([args.tool, mem, "--cloud-size", str(args.memory_size)], check=True,
                       capture_output=True)
        big = os.path.join(mem, "cloud.vdb")
        info = subprocess.run([args.glint, "info", scene(mem, big, 64, 64, 36)],
                              capture_output=True, text=True, check=True).stdout
        with_medium = frame_stats(render(args, scene(mem, big, 64, 64, 36), 1, 1,
                                         os.path.join(mem, "m.exr")))
        without = frame_stats(render(args, scene(mem, big, 64, 64, 36, False), 1, 1,
                                     os.path.join(mem, "n.exr")))
        grid = re.search(r"grid 'density': float, .*?, (\d+) active voxels.*?([\d.]+) MiB", info)
        glint_mib = re.search(r"vdb .*?: ([\d.]+) MiB in memory", info)
        result["memory"] = {
            "cloud_size": args.memory_size, "active_voxels": int(grid.group(1)),
            "openvdb_grid_mib": float(grid.group(2)), "glint_grids_mib": float(glint_mib.group(1)),
            "peak_resident_mib_with": with_medium["peak_resident_mib"],
            "peak_resident_mib_without": without["peak_resident_mib"]}
        print(json.dumps(result["memory"]), flush=True)
    with open(args.out, "w") as f:
        json.dump(result, f, indent=1)
    print(f"speed of the majorant grid at equal error: median {result['speed_median']:.2f} "
          f"(min {result['speed_min']:.2f}, max {result['speed_max']:.2f}) over {args.rounds} rounds")


if __name__ == "__main__":
    main()
