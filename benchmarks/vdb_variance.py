#!/usr/bin/env python3
"""Where a volume's noise comes from: the variance of one sample, per renderer and per variant.

Renders a scene twice at --spp with two seeds and reports the variance of one sample, the
mean over the pixels of (a - b)^2 / 2 x spp, over the pixels a mask picks, and the render
time: the figure that, times the seconds per sample, sets the time to an error. Used on the
cloud and fire of `cycles_vdb.py` (issue 52) to take their noise apart: the same scene with
the sun or the sky alone, with one bounce, and so on, in glint and in Cycles.

    /usr/bin/python3 benchmarks/vdb_variance.py glint --glint build-tests/glint \\
        --scene /tmp/cyc/cloud.json --mask /tmp/cyc/cloud_glint_mean.exr \\
        --empty /tmp/cyc/cloud_glint_empty.exr --spp 16 [--set environment.intensity=0] \\
        [--pairs 6]
    /usr/bin/python3 benchmarks/vdb_variance.py cycles --script /tmp/cyc/cycles_cloud.py \\
        --mask ... --empty ... --spp 16 [--set bounces=0]

glint's --set KEY=VALUE patches the scene JSON (dotted keys, list indices as numbers); Cycles'
patches the scene dictionary cycles_vdb.py embeds in its Blender script ("sky", "bounces",
"suns.0.irradiance", ...); glint's patched scene is written beside the original for the
render and removed after. Any glint scene works: with --bright -1 the mask is every pixel
(how the roulette rule was measured on surface scenes). The mask: pixels where --mask (a converged image) differs from
--empty (the scene without the medium) by more than 2%, or with --bright Y, where --mask's
luminance exceeds Y (a fire's flame). Needs /usr/bin/python3 with numpy and OpenImageIO.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import conformance  # noqa: E402  (blender_env)

LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def read(path):
    # No ImageCache: the same file name is written again by the next render.
    inp = oiio.ImageInput.open(path)
    pixels = inp.read_image(0, 0, 0, 3, "float")
    inp.close()
    return pixels


def patch(d, key, value):
    parts = key.split(".")
    for p in parts[:-1]:
        d = d[int(p)] if isinstance(d, list) else d[p]
    last = parts[-1]
    if isinstance(d, list):
        d[int(last)] = value
    else:
        d[last] = value


def patches(items):
    return [(k, json.loads(v)) for k, v in (s.split("=", 1) for s in items)]


def render_glint(args, work, seed):
    with open(args.scene) as f:
        scene = json.load(f)
    for k, v in patches(args.set):
        patch(scene, k, v)
    # Beside the original, so that the file names the scene gives relative to itself hold.
    path = os.path.join(os.path.dirname(os.path.abspath(args.scene)),
                        f".vdb_variance_{os.getpid()}.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    out, stats = os.path.join(work, f"g{seed}.exr"), os.path.join(work, f"g{seed}.json")
    try:
        subprocess.run([args.glint, "render", path, "--spp", str(args.spp), "--seed", str(seed),
                        "--threads", str(args.threads), "--quiet", "-o", out, "--stats", stats],
                       check=True)
    finally:
        os.remove(path)
    with open(stats) as f:
        st = json.load(f)
    return read(out), (st["frames"][0] if "frames" in st else st)["render_seconds"]


def render_cycles(args, work, seed):
    with open(args.script) as f:
        text = f.read()
    m = re.search(r'^SCENE = json\.loads\(r"""(.*)"""\)$', text, re.M)
    if not m:
        sys.exit("vdb_variance: no SCENE line (cycles_vdb.py's) in the Blender script")
    scene = json.loads(m.group(1))
    for k, v in patches(args.set):
        patch(scene, k, v)
    text = text[:m.start(1)] + json.dumps(scene) + text[m.end(1):]
    script = os.path.join(work, "cycles.py")
    with open(script, "w") as f:
        f.write(text)
    out, timing = os.path.join(work, f"c{seed}.exr"), os.path.join(work, f"c{seed}.json")
    subprocess.run([args.blender, "-b", "--factory-startup", "-noaudio", "-t", str(args.threads),
                    "--python", script, "--", out, str(args.spp), str(seed), "1",
                    str(args.threads), timing], env=conformance.blender_env(), check=True,
                   capture_output=True)
    with open(timing) as f:
        return read(out), json.load(f)["render_call_seconds"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("renderer", choices=("glint", "cycles"))
    ap.add_argument("--glint", default="build-tests/glint")
    ap.add_argument("--scene", help="glint's scene JSON")
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--script", help="cycles_vdb.py's Blender script")
    ap.add_argument("--mask", required=True, help="a converged image of the scene")
    ap.add_argument("--empty", help="the scene without the medium (for the volume's pixels)")
    ap.add_argument("--bright", type=float, help="mask: --mask's luminance above this instead")
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--seeds", type=int, nargs=2, default=[11, 12])
    ap.add_argument("--pairs", type=int, default=1,
                    help="seed pairs (--seeds, then each +2): median, min and max over them; "
                         "one pair's variance over a fire's flame varies by about 15%%")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=JSON")
    args = ap.parse_args()
    ref = read(args.mask)
    if args.bright is not None:
        mask = ref @ LUMINANCE > args.bright
    else:
        if not args.empty:
            sys.exit("vdb_variance: --empty or --bright is needed for the mask")
        empty = read(args.empty)
        mask = np.abs(ref - empty).max(axis=2) > 0.02 * (np.abs(empty).max(axis=2) + 1e-3)
    render = render_glint if args.renderer == "glint" else render_cycles
    rows = []
    for k in range(args.pairs):
        with tempfile.TemporaryDirectory() as work:
            (a, ta), (b, tb) = (render(args, work, s + 2 * k) for s in args.seeds)
        var = ((a - b) ** 2 / 2 * args.spp).mean(axis=2)
        seconds = (ta + tb) / 2
        rows.append({"variance_per_sample": float(var[mask].mean()),
                     "variance_per_sample_all_pixels": float(var.mean()),
                     "seconds": seconds, "mean": float(a[mask].mean()),
                     "efficiency": float(args.spp / (var[mask].mean() * seconds))})
    out = {"renderer": args.renderer, "set": args.set, "spp": args.spp,
           "pixels": int(mask.sum()), "pairs": args.pairs}
    for key in rows[0]:
        values = sorted(r[key] for r in rows)
        out[key] = float(np.median(values))
        if args.pairs > 1:
            out[key + "_range"] = [values[0], values[-1]]
    print(json.dumps(out))


if __name__ == "__main__":
    main()
