#!/usr/bin/env python3
"""Coloured extinction: spectral MIS over a hero channel against tracking the largest channel.

A noise cloud in a sphere with sigma_s = (1, 4, 16) (no absorption, g = 0.3) over a grey
ground under a sun and a sky, path tracer, depth 8, rendered with the medium's
`chromatic_tracking` "spectral_mis" (the default: renderer/volume.cpp's heroTrack) and
"max_channel" (delta tracking at the largest channel's majorant with channel-mean event
probabilities, the estimator before). Per round each variant renders twice with different
seeds, interleaved. Reported per variant: the variance of one sample (half the mean squared
difference of its two images, times spp; R, G and B), render seconds, tentative collisions
per real one, and the tail of the pixel values of its images (99.99th percentile and maximum
over pixels and channels, and per channel). The two variants' first images are compared with
`glint diff --statistical` (the same converged image up to noise, or not).

    /usr/bin/python3 benchmarks/chromatic_tracking.py --glint build/glint --work /tmp/chroma \\
        --rounds 3 --out benchmarks/results/chromatic_tracking.json

Needs the glint Python module (BUILD/python on PYTHONPATH; found next to --glint otherwise)
and numpy.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys

MODES = ("spectral_mis", "max_channel")


def scene(width, height, spp, mode):
    return {
        "render": {"width": width, "height": height, "spp": spp, "seed": 1,
                   "integrator": {"type": "path", "max_depth": 8}},
        "cameras": [{"name": "View", "position": [0, 1, 4], "look_at": [0, 1, 0],
                     "yfov_degrees": 40}],
        "environment": {"color": [0.5, 0.6, 0.8], "intensity": 1},
        "lights": [{"name": "Sun", "type": "directional", "direction": [-0.5, -0.6, -0.6],
                    "color": [1, 1, 1], "intensity": 3}],
        "materials": [{"name": "ground", "type": "lambert", "diffuse": [0.5, 0.5, 0.5]}],
        "objects": [{"name": "ground", "type": "plane", "material": "ground"}],
        "media": [{"name": "fog", "sigma_s": [1, 4, 16], "sigma_a": 0, "g": 0.3,
                   "chromatic_tracking": mode,
                   "region": {"type": "sphere", "radius": 1,
                              "transform": [{"translate": [0, 1, 0]}]},
                   "density": {"type": "noise", "scale": 2, "octaves": 3, "threshold": 0.3,
                               "seed": 3}}]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--glint", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--width", type=int, default=240)
    ap.add_argument("--height", type=int, default=180)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(args.glint)), "python"))
    import glint  # noqa: E402  (the module of the same build)
    import numpy as np  # noqa: E402
    os.makedirs(args.work, exist_ok=True)
    paths = {}
    for mode in MODES:
        paths[mode] = os.path.join(args.work, f"{mode}.json")
        with open(paths[mode], "w") as f:
            json.dump(scene(args.width, args.height, args.spp, mode), f)
    rounds = []
    for rnd in range(args.rounds):
        row = {"load_before": float(open("/proc/loadavg").read().split()[0])}
        images = {m: [] for m in MODES}
        for seed in (1, 2):
            for mode in MODES:
                exr = os.path.join(args.work, f"{mode}_{rnd}_{seed}.exr")
                stats = exr[:-4] + ".stats.json"
                subprocess.run([args.glint, "render", paths[mode], "--seed",
                                str(100 * rnd + seed), "--threads", str(args.threads), "--quiet",
                                "--aovs", "--stats", stats, "-o", exr], check=True)
                with open(stats) as f:
                    s = json.load(f)
                s = s["frames"][0] if "frames" in s else s
                images[mode].append(exr)
                row.setdefault(f"{mode}_render_seconds", []).append(s["render_seconds"])
                row[f"{mode}_null_per_real"] = s["tracking_collisions"]["null_per_real"]
        for mode in MODES:
            a, b = (np.asarray(glint.read(p).beauty, dtype=np.float64)[..., :3]
                    for p in images[mode])
            v = ((a - b) ** 2).mean(axis=(0, 1)) / 2 * args.spp
            both = np.stack([a, b])
            row[f"{mode}_variance_rgb"] = [float(x) for x in v]
            row[f"{mode}_variance"] = float(v.mean())
            row[f"{mode}_p9999"] = float(np.percentile(both, 99.99))
            row[f"{mode}_max"] = float(both.max())
            row[f"{mode}_p9999_rgb"] = [float(np.percentile(both[..., c], 99.99))
                                        for c in range(3)]
            row[f"{mode}_max_rgb"] = [float(both[..., c].max()) for c in range(3)]
        r = subprocess.run([args.glint, "diff", images["spectral_mis"][0],
                            images["max_channel"][0], "--json", "--statistical"],
                           capture_output=True, text=True)
        same = json.loads(r.stdout)
        row["mis_vs_max"] = {k: same.get(k) for k in ("verdict", "pass_percent", "global_z")}
        t = {m: statistics.mean(row[f"{m}_render_seconds"]) for m in MODES}
        row["speed"] = (row["max_channel_variance"] * t["max_channel"]) / (
            row["spectral_mis_variance"] * t["spectral_mis"])
        rounds.append(row)
        print(json.dumps(row), flush=True)
    speeds = [r["speed"] for r in rounds]
    result = {"width": args.width, "height": args.height, "spp": args.spp,
              "threads": args.threads, "rounds": rounds,
              "speed_median": statistics.median(speeds), "speed_min": min(speeds),
              "speed_max": max(speeds)}
    with open(args.out, "w") as f:
        json.dump(result, f, indent=1)
    print(f"spectral MIS against the largest channel at equal error: median "
          f"{result['speed_median']:.2f} (min {result['speed_min']:.2f}, max "
          f"{result['speed_max']:.2f}) over {args.rounds} rounds")


if __name__ == "__main__":
    main()
