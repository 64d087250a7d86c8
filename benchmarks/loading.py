#!/usr/bin/env python3
"""Loading a textured glTF: from the file to the first ray, and process start.

    python3 benchmarks/loading.py [--glint build-rel/glint] [--before OTHER_GLINT] [--runs 3]

Makes a DamagedHelmet-like GLB with make_helmet.py (14,400 triangles, five 2048x2048 JPEG
textures) in $TMPDIR, then for each glint binary (--before, when given, then --glint) times,
RUNS times each with /usr/bin/time:
  - `glint --version` (process start: shared libraries and static initialisers);
  - `glint info helmet.glb` (load, build without decoding images);
  - `glint render helmet.glb` at 64x64, 1 spp (load, build with every texture decoded, a few
    rays), with its --stats JSON: load_seconds + build_seconds is "file to first ray".
Prints min / median / max of wall time, peak resident memory and the stats' seconds.
"""
import argparse
import json
import os
import subprocess
import tempfile

from process_timing import spread, timed

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--glint", default="build-rel/glint")
    ap.add_argument("--before", help="a second glint binary to measure first (e.g. an older build)")
    ap.add_argument("--runs", type=int, default=3)
    args = ap.parse_args()
    out = os.path.join(tempfile.gettempdir(), "glint_loading")
    os.makedirs(out, exist_ok=True)
    helmet = os.path.join(out, "helmet.glb")
    if not os.path.exists(helmet):
        subprocess.run(["python3", os.path.join(HERE, "make_helmet.py"), helmet], check=True)
    print(f"{helmet}: {os.path.getsize(helmet) / 1e6:.1f} MB; {args.runs} runs, min / median / max")
    for label, glint in ([("before", args.before)] if args.before else []) + [("glint", args.glint)]:
        print(f"{label} ({glint}):")
        version = [timed([glint, "--version"]) for _ in range(args.runs)]
        info = [timed([glint, "info", helmet]) for _ in range(args.runs)]
        renders, first_ray, build = [], [], []
        for _ in range(args.runs):
            stats = os.path.join(out, "stats.json")
            renders.append(timed([glint, "render", helmet, "--width", "64", "--height", "64",
                                  "--spp", "1", "--quiet", "-o", os.path.join(out, "h.png"),
                                  "--stats", stats]))
            with open(stats) as f:
                s = json.load(f)
            build.append(s["build_seconds"])
            if "load_seconds" in s:
                first_ray.append(s["load_seconds"] + s["build_seconds"])
        for name, runs in [("--version", version), ("info", info), ("render 64x64 1 spp", renders)]:
            print(f"  {name:20s} wall {spread([w for w, _ in runs], 's')}, "
                  f"peak RSS {spread([m for _, m in runs], 'MB', 0)}")
        print(f"  {'build (stats)':20s} {spread(build, 's')}")
        print(f"  {'file to first ray':20s} {spread(first_ray, 's')}")


if __name__ == "__main__":
    main()
