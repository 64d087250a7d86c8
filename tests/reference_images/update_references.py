#!/usr/bin/env python3
"""Re-renders the reference images of tests/reference_images/references.json.

Usage: tests/reference_images/update_references.py [--glint build/glint] [NAME ...]

Each case is rendered at reference_spp_factor x its test spp, with the scene's seed and
`--aovs`, and stored as references/NAME.exr holding only what the statistical comparison reads
(R, G, B, A and the variance of each pixel's mean, variance.R/G/B) plus references/NAME.png to
look at. The tests never write here: run this after an intended change to what a scene looks
like, look at the new PNGs, and commit them with the change (say why in the message).

Glint scenes are found relative to tests/reference_images; Khronos samples (`asset`) under $GLINT_ASSETS
(default ../shared/assets beside the repository). A missing asset is an error. Use a Release
build: references are rendered at high spp.
"""
import argparse
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
KEEP = "R,G,B,A,variance.R,variance.G,variance.B"


def render_command(glint, case, assets, spp, output):
    cmd = [glint, "render"]
    if "asset" in case:
        asset = os.path.join(assets, case["asset"])
        if not os.path.isfile(asset):
            sys.exit(f"{asset}: missing (set GLINT_ASSETS to the shared asset folder; "
                     "benchmarks/get_assets.sh tells how to get it)")
        cmd += [asset, "--sidecar", os.path.join(HERE, case["sidecar"])]
    else:
        cmd.append(os.path.join(HERE, case["scene"]))
    if "camera" in case:
        cmd += ["--camera", case["camera"]]
    width, height = case["size"]
    cmd += ["--width", str(width), "--height", str(height), "--spp", str(spp), "--quiet"]
    return cmd + ["-o", output]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--glint", default=os.path.join(ROOT, "build", "glint"))
    parser.add_argument("names", nargs="*", help="only these cases (default: all)")
    args = parser.parse_args()
    assets = os.environ.get("GLINT_ASSETS", os.path.join(ROOT, "..", "shared", "assets"))
    with open(os.path.join(HERE, "references.json")) as f:
        manifest = json.load(f)
    cases = manifest["cases"]
    unknown = set(args.names) - {c["name"] for c in cases}
    if unknown:
        sys.exit(f"not in references.json: {', '.join(sorted(unknown))}")
    out_dir = os.path.join(HERE, "references")
    for case in cases:
        name = case["name"]
        if args.names and name not in args.names:
            continue
        spp = manifest["reference_spp_factor"] * case["spp"]
        full = os.path.join(out_dir, f".{name}.full.exr")
        start = time.time()
        png = os.path.join(out_dir, f"{name}.png")
        subprocess.run(render_command(args.glint, case, assets, spp, full) +
                       ["-o", png, "--aovs"], check=True)
        # Only the channels the comparison reads, zip-compressed, float.
        subprocess.run(["oiiotool", full, "--ch", KEEP, "--compression", "zip", "-d", "float",
                        "-o", os.path.join(out_dir, f"{name}.exr")], check=True)
        os.remove(full)
        print(f"updated {name}: {spp} spp, {time.time() - start:.1f} s", flush=True)


if __name__ == "__main__":
    main()
