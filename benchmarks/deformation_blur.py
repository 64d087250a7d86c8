#!/usr/bin/env python3
"""What deformation blur costs: Khronos CesiumMan (skinned, walking) rendered at one frame with
a quarter-second shutter, against the same frame with the shutter closed.

    python3 benchmarks/deformation_blur.py [--glint build-rel/glint] [--runs 3] [--spp 64]

Both renders use the path tracer under the default studio light at 400x400 and the same
camera (a sidecar written to $TMPDIR/glint_deformation/); the closed shutter sits at the
middle of the open one, so both show the same pose on average. Prints the time steps glint
chose (`glint info`'s motion line), each render's seconds (glint's own render time from its
summary line, min / median / max over RUNS), their ratio, and writes both images and a side
by side PNG there. The model is read from $GLINT_ASSETS (default ../shared/assets; see
get_assets.sh). Nothing is written into the repository.
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import tempfile

from process_timing import spread


def render_seconds(cmd):
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{out.stderr}")
    m = re.search(r"spp, ([0-9.]+) s,", out.stderr)
    if not m:
        raise SystemExit(f"no render time in: {out.stderr}")
    return float(m.group(1))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(here)
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--glint", default=os.path.join(root, "build-rel", "glint"))
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--time", type=float, default=0.6, help="frame time, seconds")
    ap.add_argument("--shutter", type=float, default=0.25, help="shutter length, seconds")
    args = ap.parse_args()

    assets = os.environ.get("GLINT_ASSETS", os.path.join(root, "..", "shared", "assets"))
    model = os.path.join(assets, "gltf", "CesiumMan", "glTF", "CesiumMan.gltf")
    if not os.path.exists(model):
        raise SystemExit(f"{model} not found (set GLINT_ASSETS; see benchmarks/get_assets.sh)")
    out = os.path.join(tempfile.gettempdir(), "glint_deformation")
    os.makedirs(out, exist_ok=True)

    def sidecar(name, shutter):
        path = os.path.join(out, name + ".json")
        with open(path, "w") as f:
            json.dump({"cameras": [{"name": "Main", "type": "perspective",
                                    "position": [0.5, 0.9, 3.2], "look_at": [0, 0.7, 0],
                                    "yfov_degrees": 40, "shutter": shutter}],
                       "render": {"camera": "Main", "time": args.time}}, f)
        return path

    half = args.shutter / 2
    cases = {"blurred": sidecar("blurred", [0, args.shutter]),
             "still": sidecar("still", [half, half])}
    info = subprocess.run([args.glint, "info", model, "--sidecar", cases["blurred"]],
                          capture_output=True, text=True, check=True).stdout
    motion = next((line for line in info.splitlines() if line.startswith("motion:")),
                  "motion: none")
    print(f"CesiumMan at t = {args.time} s, shutter {args.shutter} s, 400x400, {args.spp} spp, "
          f"path tracer, {args.runs} runs each")
    print(motion)
    seconds = {}
    for name, side in cases.items():
        image = os.path.join(out, name + ".exr")
        cmd = [args.glint, "render", model, "--sidecar", side, "-o", image,
               "-o", os.path.join(out, name + ".png"), "--spp", str(args.spp),
               "--width", "400", "--height", "400"]
        seconds[name] = [render_seconds(cmd) for _ in range(args.runs)]
        print(f"{name:8s} {spread(seconds[name], 's')}")
    ratio = statistics.median(seconds["blurred"]) / statistics.median(seconds["still"])
    print(f"blurred / still (medians): {ratio:.2f}")
    pair = os.path.join(out, "still_blurred.png")
    subprocess.run(["oiiotool", os.path.join(out, "still.png"), os.path.join(out, "blurred.png"),
                    "--mosaic", "2x1", "-o", pair], check=False)
    print(f"images: {out}")


if __name__ == "__main__":
    main()
