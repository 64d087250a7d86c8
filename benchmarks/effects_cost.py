#!/usr/bin/env python3
"""What lens and motion blur cost: time per image at equal spp, and the spp (and time) each
needs to reach the same error against its own high-spp reference.

Usage: effects_cost.py [--glint build/glint] [--scene scenes/motion/effects.json]
                       [--reference-spp 1024] [--spp 1,2,4,...] [--width 640 --height 360]
                       [--repeat 3] [--out benchmarks/results/effects]

For every camera of the scene (one per effect, all at the same placement: `pinhole`, `lens`,
`motion`, `lens+motion`) it renders a reference at --reference-spp and a ladder of lower spp,
each with `glint render --stats` (render time) and `glint diff --json` (RMSE against that
camera's reference). Writes effects.json and effects.md into --out.

Why an error target and not only equal spp: depth of field and motion blur add integration
dimensions (lens position, time), so at equal spp their images are noisier; the honest cost of
an effect is the time to reach the same quality, read off each camera's error-versus-spp curve
at the pinhole's error for the target spp (log-log interpolation between measured points).
"""
import argparse
import datetime
import json
import os
import sys

from accel_report import cpu_model  # beside this script

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "accuracy"))
from accuracy import diff, spp_for_error  # noqa: E402  (the render and diff helpers are shared)
from accuracy import render as render_with_stats  # noqa: E402

CAMERAS = ["pinhole", "lens", "motion", "lens+motion"]


def render(args, camera, spp, path, repeat=1):
    """The stats of the fastest of `repeat` runs (accuracy.render; no early stop here)."""
    return render_with_stats(args.glint, args.scene, path, spp, args.width, args.height, seed=7,
                             camera=camera, repeat=repeat, repeat_below=float("inf"))


def rmse(args, image, reference):
    return diff(args.glint, image, reference)["rmse"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--glint", default="build/glint")
    ap.add_argument("--scene", default="scenes/motion/effects.json")
    ap.add_argument("--reference-spp", type=int, default=1024)
    ap.add_argument("--spp", default="1,2,4,8,16,32,64")
    ap.add_argument("--target-spp", type=int, default=16,
                    help="the pinhole spp whose error the others must reach")
    ap.add_argument("--out", default="benchmarks/results/effects")
    ap.add_argument("--width", type=int, default=640)
    ap.add_argument("--height", type=int, default=360)
    ap.add_argument("--repeat", type=int, default=3, help="timed runs per point; the fastest counts")
    args = ap.parse_args()
    ladder = [int(s) for s in args.spp.split(",")]
    os.makedirs(args.out, exist_ok=True)
    work = os.path.join(args.out, "images")
    os.makedirs(work, exist_ok=True)

    results = {}
    for cam in CAMERAS:
        tag = cam.replace("+", "_")
        ref = os.path.join(work, f"{tag}_ref.exr")
        ref_stats = render(args, cam, args.reference_spp, ref)
        rows = []
        for spp in ladder:
            img = os.path.join(work, f"{tag}_{spp}.exr")
            st = render(args, cam, spp, img, args.repeat)
            rows.append({"spp": spp, "seconds": st["render_seconds"], "rmse": rmse(args, img, ref),
                         "rays": st["rays"]["total"]})
            print(f"{cam:12s} {spp:5d} spp  {st['render_seconds']:8.3f} s  rmse {rows[-1]['rmse']:.5f}",
                  file=sys.stderr)
        results[cam] = {"effects": ref_stats["effects"], "reference_spp": args.reference_spp,
                        "reference_seconds": ref_stats["render_seconds"], "ladder": rows}

    base = {r["spp"]: r for r in results["pinhole"]["ladder"]}
    target = base[args.target_spp]["rmse"]
    summary = []
    for cam in CAMERAS:
        rows = results[cam]["ladder"]
        at = {r["spp"]: r for r in rows}
        sec_per_spp = sum(r["seconds"] for r in rows) / sum(r["spp"] for r in rows)
        need = spp_for_error([(r["spp"], r["rmse"]) for r in rows], target)
        summary.append({
            "camera": cam,
            "time_ratio_equal_spp": at[args.target_spp]["seconds"] / base[args.target_spp]["seconds"],
            "rmse_at_target_spp": at[args.target_spp]["rmse"],
            "spp_for_pinhole_error": need,
            "seconds_for_pinhole_error": need * sec_per_spp,
        })
    doc = {"scene": args.scene, "date": datetime.date.today().isoformat(),
           "target_spp": args.target_spp, "target_rmse": target, "cameras": results,
           "summary": summary}
    with open(os.path.join(args.out, "effects.json"), "w") as f:
        json.dump(doc, f, indent=2)

    lines = [f"# What lens and motion blur cost ({doc['date']})", "",
             f"Scene `{args.scene}` at {args.width}x{args.height}, references at "
             f"{args.reference_spp} spp, seed 7, fastest of {args.repeat} runs per point, "
             f"`{os.path.basename(args.glint)}` on {cpu_model()} ({os.cpu_count()} threads). "
             f"Error target: the pinhole camera's RMSE at {args.target_spp} spp ({target:.5f}).", "",
             "| camera | time vs pinhole at equal spp | RMSE at equal spp | spp for the pinhole's error | seconds for it |",
             "|---|---|---|---|---|"]
    for s in summary:
        lines.append(f"| {s['camera']} | {s['time_ratio_equal_spp']:.2f}x | {s['rmse_at_target_spp']:.5f} | "
                     f"{s['spp_for_pinhole_error']:.0f} | {s['seconds_for_pinhole_error']:.2f} |")
    lines += ["", "Per camera (spp, seconds, RMSE):", ""]
    for cam in CAMERAS:
        cells = ", ".join(f"{r['spp']}: {r['seconds']:.3f} s / {r['rmse']:.5f}"
                          for r in results[cam]["ladder"])
        lines.append(f"- **{cam}** ({', '.join(results[cam]['effects'])}): {cells}")
    with open(os.path.join(args.out, "effects.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
