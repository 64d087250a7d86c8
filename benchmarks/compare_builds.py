#!/usr/bin/env python3
"""Renders the same scenes with two glint builds, alternately, and compares their times.

    benchmarks/compare_builds.py BASE_GLINT NEW_GLINT [--runs 5] [--threads 2] [--out FILE.json]
        [--case NAME SCENE [-- extra render arguments ...]] ...

Without --case it runs the cases issue 23 asked for (scenes written into --scenes, default
build/bench-scenes, by benchmarks/scenes/make_textured_pbr.py and make_compare_scenes() below):

  textured_pbr   the path tracer on a glTF scene with base colour, metallicRoughness, normal and
                 emissive maps (1024^2 each) on five spheres and a floor
  specular       Whitted on a floor, Phong, Lambert, mirror and glass spheres (cheap shaders,
                 where a hit's shading is small beside its tracing)
  sun_path_d1    a scene lit only by a sun: `--integrator path --max-depth 1`
  sun_whitted    the same scene with Whitted (what the path tracer should cost here)

Each run is `glint render ... --quiet --stats`; the builds alternate (base, new, base, ...) so
that a change in the machine's load hits both. Reported per case and build: the median and
the range of render_seconds (the render loop, not loading), the rays traced, and new/base.
Standard library only.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))


def make_compare_scenes(out_dir):
    """The sun-only and specular scenes (glint .json scenes, analytic objects)."""
    base = {
        "render": {"width": 640, "height": 360, "spp": 16, "seed": 3, "camera": "main"},
        "cameras": [{"name": "main", "position": [0, 1.8, 7], "look_at": [0, 0.6, 0],
                     "yfov_degrees": 40}],
        "materials": [
            {"name": "floor", "type": "lambert", "diffuse": [0.7, 0.7, 0.7]},
            {"name": "red", "type": "phong", "diffuse": [0.7, 0.1, 0.08],
             "specular": [0.25, 0.25, 0.25], "shininess": 60},
            {"name": "white", "type": "lambert", "diffuse": [0.85, 0.85, 0.82]},
            {"name": "mirror", "type": "mirror", "color": [0.9, 0.9, 0.9]},
            {"name": "glass", "type": "glass", "ior": 1.5}],
        "objects": [
            {"name": "floor", "type": "plane", "material": "floor"},
            {"name": "a", "type": "sphere", "center": [-2, 0.6, 0], "radius": 0.6,
             "material": "red"},
            {"name": "b", "type": "sphere", "center": [0, 0.6, -1], "radius": 0.6,
             "material": "white"},
            {"name": "c", "type": "box", "min": [1.2, 0, -0.5], "max": [2.2, 1, 0.5],
             "material": "white"}],
    }
    sun = json.loads(json.dumps(base))
    sun["lights"] = [{"name": "sun", "type": "directional", "direction": [-0.3, -1, -0.4],
                      "intensity": 3}]
    spec = json.loads(json.dumps(base))
    spec["lights"] = [
        {"name": "key", "type": "point", "position": [-3, 6, 5], "intensity": 70},
        {"name": "sun", "type": "directional", "direction": [-0.3, -1, -0.4], "intensity": 1}]
    spec["objects"] += [
        {"name": "m", "type": "sphere", "center": [-0.8, 0.5, 1.4], "radius": 0.5,
         "material": "mirror"},
        {"name": "g", "type": "sphere", "center": [0.9, 0.5, 1.6], "radius": 0.5,
         "material": "glass"}]
    spec["render"]["integrator"] = {"type": "whitted", "max_depth": 8}
    for name, scene in (("sun_only.json", sun), ("specular.json", spec)):
        with open(os.path.join(out_dir, name), "w") as f:
            json.dump(scene, f, indent=1)


def default_cases(scene_dir):
    os.makedirs(scene_dir, exist_ok=True)
    if not os.path.exists(os.path.join(scene_dir, "textured_pbr.gltf")):
        subprocess.run([sys.executable, os.path.join(HERE, "scenes", "make_textured_pbr.py"),
                        scene_dir], check=True)
    make_compare_scenes(scene_dir)
    join = lambda name: os.path.join(scene_dir, name)  # noqa: E731
    return [
        ("textured_pbr", join("textured_pbr.gltf"), ["--width", "480", "--height", "360",
                                                     "--spp", "4"]),
        ("specular", join("specular.json"), []),
        ("sun_path_d1", join("sun_only.json"), ["--integrator", "path", "--max-depth", "1"]),
        ("sun_whitted", join("sun_only.json"), ["--integrator", "whitted"]),
    ]


def render(glint, scene, extra, threads):
    with tempfile.TemporaryDirectory() as tmp:
        stats = os.path.join(tmp, "stats.json")
        cmd = [glint, "render", scene, "--quiet", "--threads", str(threads),
               "-o", os.path.join(tmp, "out.exr"), "--stats", stats] + extra
        subprocess.run(cmd, check=True)
        with open(stats) as f:
            s = json.load(f)
    return s["render_seconds"], s["rays"]["total"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("base")
    ap.add_argument("new")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--scenes", default="build/bench-scenes")
    ap.add_argument("--out")
    ap.add_argument("--only", nargs="*", help="case names to run")
    args = ap.parse_args()

    cases = default_cases(args.scenes)
    if args.only:
        cases = [c for c in cases if c[0] in args.only]
    results = {}
    for name, scene, extra in cases:
        times = {"base": [], "new": []}
        rays = {}
        for run in range(args.runs):
            order = ("base", "new") if run % 2 == 0 else ("new", "base")
            for which in order:
                t, r = render(getattr(args, which), scene, extra, args.threads)
                times[which].append(t)
                rays[which] = r
        med = {k: statistics.median(v) for k, v in times.items()}
        results[name] = {"times": times, "rays": rays, "median": med,
                         "new_over_base": med["new"] / med["base"]}
        print(f"{name:14s} base {med['base']:.3f} s [{min(times['base']):.3f}-"
              f"{max(times['base']):.3f}] rays {rays['base']:,} | new {med['new']:.3f} s "
              f"[{min(times['new']):.3f}-{max(times['new']):.3f}] rays {rays['new']:,} | "
              f"new/base {med['new'] / med['base']:.3f}", flush=True)
    if args.out:
        with open(args.out, "w") as f:
            json.dump({"runs": args.runs, "threads": args.threads, "cases": results}, f,
                      indent=1)


if __name__ == "__main__":
    main()
