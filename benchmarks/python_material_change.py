#!/usr/bin/env python3
"""What a material change costs from Python (issue 53): Scene.update of one material and a
render, against loading the changed scene afresh and rendering it.

    PYTHONPATH=build/python python3 benchmarks/python_material_change.py [--build build] [--runs 5]

Venus Garden (scenes/venus_garden: two 202k-triangle dragons, procedural textures, media) at
40x30 pixels and 1 spp, so that the figures are the scene's preparation rather than its render.
Each round, RUNS times:
  - renders the kept scene unchanged (the render alone);
  - changes the iron's specular colour (and back, alternately) in the kept scene and renders
    (refreshMaterials: no build, no accelerator);
  - makes the same change in a second kept scene together with a new, unused material, which
    takes a whole build from the kept description (what every material change took before);
  - loads the scene from its file, changes it before its first render and renders it.
It prints min / median / max of each, the medians less the render alone, and the scenes' build
and refresh counts. The kept scene's image and the fresh load's are compared bit for bit.
"""
import argparse
import os
import statistics
import subprocess
import sys
import time

from python_overhead import ROOT, spread  # the folder and min / median / max, as printed there

def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()
    sys.path.insert(0, os.path.join(args.build, "python"))
    import glint
    import numpy as np

    path = os.path.join(ROOT, "scenes", "venus_garden", "venus_garden.json")
    settings = {"spp": 1, "width": 40, "height": 30, "threads": 0}
    scene = glint.load(path)
    scene.render(**settings)
    rebuilt = glint.load(path)  # the same change through a whole build, as before refreshMaterials
    rebuilt.render(**settings)
    kept, fresh, again, built = [], [], [], []
    for i in range(args.runs):
        start = time.perf_counter()
        scene.render(**settings, seed=i + 1)  # nothing changed: the render alone
        again.append(time.perf_counter() - start)
        iron = {"name": "Iron", "specular": [0.5, 0.2, 0.1] if i % 2 == 0 else [0.35, 0.35, 0.35]}
        start = time.perf_counter()
        scene.update({"materials": [iron]})
        changed = scene.render(**settings)
        kept.append(time.perf_counter() - start)
        start = time.perf_counter()
        # A new, unused material needs a build (it could change which mesh takes which).
        rebuilt.update({"materials": [iron, {"name": f"Unused{i}", "type": "lambert"}]})
        rebuilt.render(**settings)
        built.append(time.perf_counter() - start)
        start = time.perf_counter()
        loaded = glint.load(path)  # a .json scene takes no sidecar: changed before its build
        loaded.update({"materials": [iron]})
        image = loaded.render(**settings)
        fresh.append(time.perf_counter() - start)
        assert np.array_equal(changed.beauty, image.beauty), "the images differ"
    print(f"material change and render: {spread(kept)} s (min / median / max, {args.runs} runs)")
    print(f"whole build and render:     {spread(built)} s (kept description, no file read)")
    print(f"fresh load and render:      {spread(fresh)} s")
    print(f"render alone (no change):   {spread(again)} s")
    render = statistics.median(again)
    print("without the render alone's median: change "
          f"{statistics.median(kept) - render:.3f} s, whole build "
          f"{statistics.median(built) - render:.3f} s, fresh load {statistics.median(fresh) - render:.3f} s")
    print(f"kept scene: builds {scene.builds}, refreshes {scene.refreshes}; rebuilt scene: builds "
          f"{rebuilt.builds}")
    print("load:", subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())


if __name__ == "__main__":
    main()
