#!/usr/bin/env python3
"""The Python module's overhead (issue 53): a render from Python against the command line's at
the same settings, and the time to hand back a 1920x1080 image's arrays with AOVs.

    PYTHONPATH=build/python python3 benchmarks/python_overhead.py [--build build] [--runs 5]

Renders scenes/first_image (the five spheres, path tracer) at 640x480, 64 spp, all threads,
alternating the command line (`glint render --stats`, its render_seconds) and Python
(Scene.render on a loaded scene, its stats' render_seconds and the call's wall time), RUNS
times each, and prints min / median / max of each and the ratio of the medians. Then the arrays:
image.arrays of a 1920x1080 render with AOVs (seven numpy views), timed over 1,000 calls.
Run it on an idle machine (`uptime` is printed with the figures).
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def spread(values):
    return f"{min(values):.3f} / {statistics.median(values):.3f} / {max(values):.3f}"


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--spp", type=int, default=64)
    args = parser.parse_args()
    sys.path.insert(0, os.path.join(args.build, "python"))
    import glint

    scene_path = os.path.join(ROOT, "scenes", "first_image", "first_image.gltf")
    settings = {"spp": args.spp, "width": 640, "height": 480, "seed": 1}
    flags = [f"--{k}={v}" for k, v in settings.items()]
    cli, python_render, python_wall = [], [], []
    scene = glint.load(scene_path)
    scene.render(spp=1, width=640, height=480)  # builds the render scene once, as the CLI does
    with tempfile.TemporaryDirectory() as folder:
        for _ in range(args.runs):
            stats = os.path.join(folder, "stats.json")
            subprocess.run([os.path.join(args.build, "glint"), "render", scene_path, "-o",
                            os.path.join(folder, "x.exr"), "--stats", stats, "--quiet", *flags],
                           check=True)
            with open(stats) as f:
                cli.append(json.load(f)["render_seconds"])
            start = time.perf_counter()
            image = scene.render(**settings)
            python_wall.append(time.perf_counter() - start)
            python_render.append(image.stats["render_seconds"])
    print(f"load: {os.getloadavg()[0]:.2f} (1-minute average), {args.runs} alternated runs")
    print(f"command line render_seconds  (min / median / max): {spread(cli)}")
    print(f"Python render_seconds        (min / median / max): {spread(python_render)}")
    print(f"Python render() wall time    (min / median / max): {spread(python_wall)}")
    print(f"median ratio Python / command line: render {statistics.median(python_render) / statistics.median(cli):.3f}, "
          f"wall {statistics.median(python_wall) / statistics.median(cli):.3f}")

    big = scene.render(spp=1, width=1920, height=1080, aovs=True)
    calls = 1000
    times = []
    for _ in range(calls):
        start = time.perf_counter()
        arrays = big._native.arrays
        times.append(time.perf_counter() - start)
    assert len(arrays) == 7
    print(f"1920x1080 arrays with AOVs ({len(arrays)} views), {calls} calls: "
          f"{spread([t * 1e6 for t in times])} microseconds")


if __name__ == "__main__":
    main()
