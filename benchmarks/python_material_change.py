#!/usr/bin/env python3
"""What a material change costs from Python (issue 53): Scene.update of one material and a
render, against loading the changed scene afresh and rendering it.

    PYTHONPATH=build/python python3 benchmarks/python_material_change.py [--build build] [--runs 5]

Venus Garden (scenes/venus_garden: two 202k-triangle dragons, procedural textures, media) at
a small size and 1 spp, so that the figures are the scene's preparation rather than its render.
Each round changes the iron's specular colour (and back, alternately) in the kept scene, then
loads the changed scene from its file and renders it; the two are alternated RUNS times, and
the rounds print min / median / max of each, and the kept scene's builds and refreshes (a
material change is a refresh: no build, no accelerator). The images of both are compared bit
for bit.
"""
import argparse
import os
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def spread(values):
    return f"{min(values):.3f} / {statistics.median(values):.3f} / {max(values):.3f}"


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()
    sys.path.insert(0, os.path.join(args.build, "python"))
    import glint
    import numpy as np

    path = os.path.join(ROOT, "scenes", "venus_garden", "venus_garden.json")
    settings = {"spp": 1, "width": 160, "height": 120, "threads": 0}
    scene = glint.load(path)
    scene.render(**settings)
    kept, fresh = [], []
    for i in range(args.runs):
        iron = {"name": "Iron", "specular": [0.5, 0.2, 0.1] if i % 2 == 0 else [0.35, 0.35, 0.35]}
        start = time.perf_counter()
        scene.update({"materials": [iron]})
        changed = scene.render(**settings)
        kept.append(time.perf_counter() - start)
        start = time.perf_counter()
        loaded = glint.load(path, sidecar={"materials": [iron]})
        image = loaded.render(**settings)
        fresh.append(time.perf_counter() - start)
        assert np.array_equal(changed.beauty, image.beauty), "the images differ"
    print(f"material change and render: {spread(kept)} s (min / median / max, {args.runs} runs)")
    print(f"fresh load and render:      {spread(fresh)} s")
    print(f"median ratio: {statistics.median(fresh) / statistics.median(kept):.1f}x")
    print(f"kept scene: builds {scene.builds}, refreshes {scene.refreshes}")
    print("load:", subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())


if __name__ == "__main__":
    main()
