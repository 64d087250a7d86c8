#!/usr/bin/env python3
"""Time to equal error against Blender Cycles on Khronos' DamagedHelmet (issue 49, item 0).

The helmet (`$GLINT_ASSETS/gltf/DamagedHelmet/glTF/DamagedHelmet.gltf`, not copied) under a
uniform white sky of radiance 1, 400x400, a 45-degree camera in front of it, box pixel filter
one pixel wide, path depth 8, each renderer on the CPU with 2 threads:

- glint: `glint render --integrator path --max-depth 8 --threads 2` with the issue's sidecar
  (written to the work folder and passed with --sidecar);
- Cycles: Debian's `blender` 3.4 headless, through conformance.py's Blender script (import,
  camera, sky, max_bounces 7 = glint's depth 8), with more settings appended: no denoising, no
  adaptive sampling, no clamping (direct and indirect 0), no glossy filter (blur_glossy 0),
  pixel filter BOX of width 1, a fixed seed, and diffuse/glossy/transmission bounces 7 as well
  (Cycles' defaults, 4/4/12, would end diffuse and glossy paths before glint's do). The render
  call is timed inside Blender (wall and the process's CPU), the image saved after it.

Steps: (1) each renderer's reference, once (default 1024 spp, seed 1000; kept and reused
with --reuse-references); (2) --rounds rounds (default 3) of ladders, glint at 4..256 spp and
Cycles at 16..128 spp, interleaved glint/Cycles, seed = round + 1, the load average noted
before each image; (3) for each image: RMSE and mean relative error (|x - r| / (r + 0.01),
mean over pixels and RGB) against its own renderer's reference, the brightest pixel and the
99.99th percentile (of each pixel's largest channel), the pixels above 1.5, and the pixels
differing from the reference by more than 0.1 and 1.5 (largest channel); times: render only
(glint `--stats` render_seconds; Cycles the timed render call, which includes its scene sync,
and its sampling alone from the progress lines), CPU seconds of the whole process (user+sys,
os.wait4) and wall seconds of the whole process; (4) the spp and time glint needs to reach
Cycles' error at --target-spp (64) against Cycles' own reference, log-log interpolated along
glint's ladder, per round and from the medians, and the ratio Cycles time / glint time.

RMSE is also given with the reference's own noise taken out ("corrected"): both images are
independent estimates of the same pixels, so MSE(image, reference) = MSE(image) + MSE(reference),
and with MSE proportional to 1/spp, MSE(image) = MSE measured x N_ref / (N_ref + n). The
equal-error figures use the corrected RMSE; the raw ones are in the JSON.

    /usr/bin/python3 benchmarks/helmet_equal_error.py --glint /tmp/helmet/glint \\
        --work /tmp/helmet/work --out benchmarks/results/helmet_equal_error

How long: on the 2-core machine under a load of 4-7 (2026-11-28) a sample per pixel took
glint ~1 s of wall time (0.64 CPU s) and Cycles ~0.85 s (0.6 CPU s): the two 1024-spp
references 32 minutes, each round of ladders (508 glint spp, 240 Cycles spp) 11-12 minutes,
66 minutes in all; 35 with --reuse-references. Each renderer got about one of the two
cores there; an idle machine should take less.
--analyse-only recomputes the results from the records in --work (a few seconds).

Needs /usr/bin/python3 with numpy and OpenImageIO (a pyenv python3 may lack them), `blender`
and `oiiotool`. EXRs stay in --work; --out gets helmet_equal_error.json, .md and a small
side-by-side PNG of the two references (glint left, Cycles right).
"""
import argparse
import datetime
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import time

import numpy as np
import OpenImageIO as oiio

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "accuracy"))
import conformance  # noqa: E402  (the Blender harness: import, camera, sky, bounces)
from accel_report import cpu_model  # noqa: E402
from accuracy import spp_for_error  # noqa: E402  (log-log interpolation along a ladder)

SIDECAR = {"environment": {"color": [1, 1, 1]},
           "render": {"width": 400, "height": 400, "spp": 512,
                      "filter": {"type": "box", "radius": 0.5}},
           "cameras": [{"name": "front", "position": [0, 0.5614, 2.641], "look_at": [0, 0, 0],
                        "yfov_degrees": 45}]}
WIDTH, HEIGHT = 400, 400
POSITION, LOOK_AT, YFOV = [0, 0.5614, 2.641], [0, 0, 0], 45
GLINT_DEPTH = 8

# The end of a Blender script that renders with its render call timed: wall and CPU seconds,
# then the image to `out` and the times, with the script's `timing_extra` dict, to `timing`
# as JSON (this script's and cycles_vdb.py's).
TIMED_RENDER = r'''
import json, resource, time
r0 = resource.getrusage(resource.RUSAGE_SELF)
t0 = time.perf_counter()
bpy.ops.render.render()
t1 = time.perf_counter()
r1 = resource.getrusage(resource.RUSAGE_SELF)
bpy.data.images["Render Result"].save_render(out)
with open(timing, "w") as f:
    json.dump(dict({"render_call_seconds": t1 - t0,
                    "render_call_cpu_seconds": (r1.ru_utime - r0.ru_utime) +
                                               (r1.ru_stime - r0.ru_stime)}, **timing_extra), f)
'''

# conformance.py's script ends by rendering and writing the image; this replaces that last
# line with the settings an equal-error comparison needs and a timed render call.
_TAIL = "bpy.ops.render.render(write_still=True)\n"
BLENDER_EXTRA = r'''
seed, timing, threads = int(a[12]), a[13], int(a[14])
c = scene.cycles
c.use_adaptive_sampling = False
c.sample_clamp_direct = 0.0
c.sample_clamp_indirect = 0.0
c.blur_glossy = 0.0
c.pixel_filter_type = "BOX"
c.filter_width = 1.0
c.seed = seed
c.use_animated_seed = False
c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = c.max_bounces
scene.render.threads_mode = "FIXED"
scene.render.threads = threads
keys = ("samples", "max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
        "transparent_max_bounces", "volume_bounces", "use_adaptive_sampling",
        "sample_clamp_direct", "sample_clamp_indirect", "blur_glossy", "pixel_filter_type",
        "filter_width", "seed", "use_animated_seed", "sampling_pattern", "use_denoising",
        "caustics_reflective", "caustics_refractive", "light_sampling_threshold", "device")
settings = {k: getattr(c, k) for k in keys}
settings["threads"] = scene.render.threads
settings["blender"] = bpy.app.version_string
timing_extra = {"settings": settings}
''' + TIMED_RENDER


def blender_script():
    base = conformance.BLENDER_SCRIPT
    if not base.endswith(_TAIL):
        sys.exit("helmet_equal_error: conformance.BLENDER_SCRIPT no longer ends with its render "
                 "call; update BLENDER_EXTRA")
    return base[:-len(_TAIL)] + BLENDER_EXTRA


def load_average():
    with open("/proc/loadavg") as f:
        return [float(v) for v in f.read().split()[:3]]


def timed(cmd, log_path, env=None):
    """Runs cmd (stdout and stderr to log_path); its wall seconds and user+sys CPU seconds."""
    with open(log_path, "w") as log:
        start = time.perf_counter()
        p = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, env=env)
        _, status, usage = os.wait4(p.pid, 0)
        wall = time.perf_counter() - start
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        raise RuntimeError(f"{os.path.basename(cmd[0])} exited with {p.returncode}; see {log_path}")
    return wall, usage.ru_utime + usage.ru_stime


def render_glint(args, spp, seed, exr):
    stats = exr[:-4] + ".stats.json"
    cmd = [args.glint, "render", args.scene, "--sidecar", args.sidecar, "--integrator", "path",
           "--max-depth", str(GLINT_DEPTH), "--spp", str(spp), "--seed", str(seed),
           "--threads", str(args.threads), "--quiet", "--stats", stats, "-o", exr]
    load = load_average()
    wall, cpu = timed(cmd, exr[:-4] + ".log")
    with open(stats) as f:
        s = json.load(f)
    return {"renderer": "glint", "spp": spp, "seed": seed, "image": exr, "load_before": load,
            "wall_seconds": wall, "cpu_seconds": cpu, "render_seconds": s["render_seconds"],
            "load_seconds": s.get("load_seconds"), "build_seconds": s.get("build_seconds"),
            "brightest_sample": s.get("brightest_sample"),
            "nonfinite_samples": s.get("nonfinite_samples")}


def glint_setup(args, rnd):
    """One glint run per round that renders a single pixel (--crop 0,0,1,1, 1 spp): its CPU
    seconds are glint's loading, building and start, taken from the ladder's CPU seconds to
    estimate glint's render-only CPU time (its --stats have no CPU time)."""
    exr = os.path.join(args.work, f"glint_setup_r{rnd}.exr")
    cmd = [args.glint, "render", args.scene, "--sidecar", args.sidecar, "--integrator", "path",
           "--max-depth", str(GLINT_DEPTH), "--spp", "1", "--crop", "0,0,1,1",
           "--threads", str(args.threads), "--quiet", "-o", exr]
    load = load_average()
    wall, cpu = timed(cmd, exr[:-4] + ".log")
    return {"renderer": "glint_setup", "round": rnd, "load_before": load, "wall_seconds": wall,
            "cpu_seconds": cpu}


def _clock(stamp):
    """Seconds from Blender's progress time, [hh:]mm:ss.cc."""
    parts = [float(p) for p in stamp.split(":")]
    return sum(v * 60 ** i for i, v in enumerate(reversed(parts)))


def cycles_sampling_seconds(log_text):
    """Cycles' sampling seconds and its scene sync seconds, from its progress lines (None when
    missing). It prints "Time:MM:SS.cc | ... | Sample 0/N" once its scene is synchronised
    (images loaded, BVH built) and "Finished" at the end: sampling alone is the difference."""
    first = re.search(r"Time:([\d:.]+) \|[^\n]*\| Sample 0/\d+", log_text)
    done = re.search(r"Time:([\d:.]+) \|[^\n]*\| Finished", log_text)
    sampling = _clock(done.group(1)) - _clock(first.group(1)) if first and done else None
    return sampling, _clock(first.group(1)) if first else None


def render_cycles(args, spp, seed, exr):
    timing = exr[:-4] + ".timing.json"
    log_path = exr[:-4] + ".log"
    cmd = [args.blender, "-b", "-t", str(args.threads), "-P", args.blender_script, "--",
           args.scene, exr, str(WIDTH), str(HEIGHT), str(spp), *map(str, POSITION),
           *map(str, LOOK_AT), str(YFOV), str(seed), timing, str(args.threads)]
    load = load_average()
    wall, cpu = timed(cmd, log_path, env=conformance.blender_env())
    with open(timing) as f:
        t = json.load(f)
    with open(log_path, errors="replace") as f:
        text = f.read()
    sampling, sync = cycles_sampling_seconds(text)
    return {"renderer": "cycles", "spp": spp, "seed": seed, "image": exr, "load_before": load,
            "wall_seconds": wall, "cpu_seconds": cpu,
            "render_seconds": t["render_call_seconds"],
            "render_cpu_seconds": t["render_call_cpu_seconds"],
            "sampling_seconds": sampling,
            "sync_seconds": sync,
            "settings": t["settings"]}


def read_rgb(path):
    img = oiio.ImageBuf(path)
    spec = img.spec()
    names = list(spec.channelnames)
    idx = [names.index(c) for c in ("R", "G", "B")]
    px = img.get_pixels(oiio.FLOAT).reshape(spec.height, spec.width, spec.nchannels)
    return px[:, :, idx].astype(np.float64)


def tails(img):
    peak = img.max(axis=2)
    y, x = np.unravel_index(int(np.argmax(peak)), peak.shape)
    return {"brightest": float(peak.max()), "brightest_xy": [int(x), int(y)],
            "p99_99": float(np.percentile(peak, 99.99)), "mean": float(img.mean()),
            "pixels_above_1_5": int((peak > 1.5).sum()),
            "nonfinite": int((~np.isfinite(img)).sum())}


def errors(img, ref, n, n_ref):
    d = img - ref
    mse = float(np.mean(d * d))
    worst = np.abs(d).max(axis=2)
    y, x = np.unravel_index(int(np.argmax(worst)), worst.shape)
    return {"rmse": math.sqrt(mse),
            "rmse_corrected": math.sqrt(mse * n_ref / (n_ref + n)),
            "mean_relative_error": float(np.mean(np.abs(d) / (ref + 0.01))),
            "pixels_off_by_0_1": int((worst > 0.1).sum()),
            "pixels_off_by_1_5": int((worst > 1.5).sum()),
            "largest_difference": float(worst.max()), "largest_difference_xy": [int(x), int(y)]}


def append(path, record):
    with open(path, "a") as f:
        f.write(json.dumps(record) + "\n")


def read_records(path):
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


def median_spread(values):
    values = [v for v in values if v is not None]
    if not values:
        return None
    return {"median": statistics.median(values), "min": min(values), "max": max(values),
            "n": len(values)}


def time_at_spp(curve, spp):
    """Log-log interpolation of [(spp, seconds)] at spp (linear extrapolation past the ends)."""
    pts = sorted(curve)
    for (s0, t0), (s1, t1) in zip(pts, pts[1:]):
        if s0 <= spp <= s1:
            f = (math.log(spp) - math.log(s0)) / (math.log(s1) - math.log(s0))
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0)))
    s, t = pts[0] if spp < pts[0][0] else pts[-1]
    return t * spp / s


# (label, glint's key, Cycles' key). glint's render_seconds leaves out loading and building;
# Cycles' render call includes its scene sync (images, BVH), its sampling_seconds do not.
TIMES = (("render", "render_seconds", "render_seconds"),
         ("render_vs_sampling", "render_seconds", "sampling_seconds"),
         ("render_cpu", "render_cpu_seconds", "render_cpu_seconds"),
         ("cpu", "cpu_seconds", "cpu_seconds"),
         ("wall", "wall_seconds", "wall_seconds"))


def equal_error(glint_rows, cycles_rows, target_spp, error_key):
    """glint's spp and times at the error of Cycles' target_spp image, and the ratios."""
    target = [r for r in cycles_rows if r["spp"] == target_spp]
    if not target:
        return None
    err = statistics.median(r[error_key] for r in target)
    by_spp = {}
    for r in glint_rows:
        by_spp.setdefault(r["spp"], []).append(r)
    curve = [(s, statistics.median(r[error_key] for r in rs)) for s, rs in by_spp.items()]
    spp = spp_for_error(curve, err)
    out = {"cycles_spp": target_spp, "cycles_error": err, "glint_spp": spp}
    for label, gkey, ckey in TIMES:
        if any(r.get(gkey) is None for r in glint_rows) or any(r.get(ckey) is None
                                                               for r in target):
            continue
        g = time_at_spp([(s, statistics.median(r[gkey] for r in rs)) for s, rs in by_spp.items()],
                        spp)
        c = statistics.median(r[ckey] for r in target)
        out[f"glint_{label}"] = g
        out[f"cycles_{label}"] = c
        out[f"ratio_{label}"] = c / g
    return out


def analyse(args):
    records = read_records(args.records)
    refs = {r["renderer"]: r for r in records if r.get("reference")}
    setup = [r for r in records if r["renderer"] == "glint_setup"]
    ladder = [r for r in records if not r.get("reference") and r["renderer"] != "glint_setup"]
    for r in ladder:
        if r["renderer"] == "glint":
            own = [s["cpu_seconds"] for s in setup if s["round"] == r["round"]]
            if own:
                r["render_cpu_seconds"] = r["cpu_seconds"] - statistics.median(own)
    ref_img = {k: read_rgb(v["image"]) for k, v in refs.items()}
    for r in list(refs.values()) + ladder:
        img = read_rgb(r["image"])
        r.update(tails(img))
        if not r.get("reference"):
            ref = refs[r["renderer"]]
            r.update(errors(img, ref_img[r["renderer"]], r["spp"], ref["spp"]))
    result = {"date": datetime.date.today().isoformat(), "machine": cpu_model(),
              "cores": os.cpu_count(), "glint": args.glint, "note": args.note,
              "scene": args.scene_rel,
              "sidecar": SIDECAR, "glint_depth": GLINT_DEPTH, "threads": args.threads,
              "references": {k: {kk: vv for kk, vv in v.items() if kk != "image"}
                             for k, v in refs.items()},
              "images": [{k: v for k, v in r.items() if k != "image"} for r in ladder],
              "glint_setup": setup, "rounds": sorted({r["round"] for r in ladder})}
    table = {}
    for r in ladder:
        table.setdefault((r["renderer"], r["spp"]), []).append(r)
    summary = []
    for (renderer, spp), rs in sorted(table.items()):
        row = {"renderer": renderer, "spp": spp, "runs": len(rs)}
        for key in ("rmse", "rmse_corrected", "mean_relative_error", "brightest", "p99_99",
                    "pixels_above_1_5", "pixels_off_by_0_1", "pixels_off_by_1_5",
                    "render_seconds", "cpu_seconds", "wall_seconds", "sampling_seconds",
                    "render_cpu_seconds"):
            if any(key in r for r in rs):
                row[key] = median_spread([r.get(key) for r in rs])
        summary.append(row)
    result["summary"] = summary
    g = [r for r in ladder if r["renderer"] == "glint"]
    c = [r for r in ladder if r["renderer"] == "cycles"]
    result["equal_error"] = {}
    for key in ("rmse_corrected", "rmse", "mean_relative_error"):
        entry = {"from_medians": equal_error(g, c, args.target_spp, key), "per_round": []}
        for rnd in result["rounds"]:
            e = equal_error([r for r in g if r["round"] == rnd], [r for r in c if r["round"] == rnd],
                            args.target_spp, key)
            if e:
                entry["per_round"].append(dict(e, round=rnd))
        result["equal_error"][key] = entry
    result["loads"] = {rnd: [r["load_before"][0] for r in ladder if r["round"] == rnd]
                       for rnd in result["rounds"]}
    return result


def fmt_ms(m, digits=3, scale=1.0):
    if m is None:
        return ""
    if m["n"] == 1:
        return f"{m['median'] * scale:.{digits}f}"
    return (f"{m['median'] * scale:.{digits}f} ({m['min'] * scale:.{digits}f}–"
            f"{m['max'] * scale:.{digits}f})")


def markdown(res):
    lines = [f"{res['date']}, {res['machine']}, {res['cores']} cores, {res['threads']} threads "
             f"each; glint {res['glint']} {res['note']}; rounds {len(res['rounds'])}, medians "
             f"(min-max); load average before each image: "
             + "; ".join(f"round {k} {min(v):.1f}-{max(v):.1f}" for k, v in res["loads"].items()),
             "",
             "| renderer | spp | RMSE (raw) | RMSE (corrected) | mean rel. error | brightest | "
             "p99.99 | px > 1.5 | px off > 0.1 | px off > 1.5 | render s | CPU s | wall s |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for k, r in sorted(res["references"].items()):
        lines.append(f"| {k} reference | {r['spp']} | | | | {r['brightest']:.3f} | "
                     f"{r['p99_99']:.3f} | {r['pixels_above_1_5']} | | | "
                     f"{r['render_seconds']:.1f} | {r['cpu_seconds']:.1f} | "
                     f"{r['wall_seconds']:.1f} |")
    for r in res["summary"]:
        lines.append(
            f"| {r['renderer']} | {r['spp']} | {fmt_ms(r['rmse'], 5)} | "
            f"{fmt_ms(r['rmse_corrected'], 5)} | {fmt_ms(r['mean_relative_error'], 4)} | "
            f"{fmt_ms(r['brightest'], 2)} | {fmt_ms(r['p99_99'], 2)} | "
            f"{fmt_ms(r['pixels_above_1_5'], 0)} | {fmt_ms(r['pixels_off_by_0_1'], 0)} | "
            f"{fmt_ms(r['pixels_off_by_1_5'], 0)} | {fmt_ms(r['render_seconds'], 1)} | "
            f"{fmt_ms(r['cpu_seconds'], 1)} | {fmt_ms(r['wall_seconds'], 1)} |")
    lines.append("")
    for key, entry in res["equal_error"].items():
        e = entry["from_medians"]
        if not e:
            continue
        lines.append(f"Equal {key} (Cycles {e['cycles_spp']} spp: {e['cycles_error']:.5f}): "
                     f"glint {e['glint_spp']:.1f} spp; Cycles/glint "
                     + ", ".join(f"{t[0]} {e['ratio_' + t[0]]:.2f}" for t in TIMES
                                 if "ratio_" + t[0] in e)
                     + "; per round: "
                     + "; ".join(f"{p['glint_spp']:.1f} spp, "
                                 + ", ".join(f"{p.get('ratio_' + t[0], float('nan')):.2f}"
                                             for t in TIMES)
                                 for p in entry["per_round"]))
    return "\n".join(lines) + "\n"


def side_by_side(args, out_png):
    tiles = []
    for name in ("glint_ref", "cycles_ref"):
        png = os.path.join(args.work, name + ".png")
        subprocess.run([args.glint, "tonemap", os.path.join(args.work, name + ".exr"), "-o", png],
                       check=True, stdout=subprocess.DEVNULL)
        tiles.append(png)
    subprocess.run(["oiiotool", *tiles, "--mosaic", "2x1", "--resize", "600x300", "--ch",
                    "R,G,B", "-d", "uint8", "-o", out_png], check=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--glint", default=os.path.join(ROOT, "build-rel", "glint"))
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--assets", default=os.environ.get(
        "GLINT_ASSETS", os.path.join(ROOT, "..", "shared", "assets")))
    ap.add_argument("--work", default="/tmp/glint_helmet_equal_error")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "helmet_equal_error"))
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--glint-reference-spp", type=int, default=1024)
    ap.add_argument("--cycles-reference-spp", type=int, default=1024)
    ap.add_argument("--glint-spp", default="4,8,16,32,64,128,256")
    ap.add_argument("--cycles-spp", default="16,32,64,128")
    ap.add_argument("--target-spp", type=int, default=64, help="Cycles' rung to equal")
    ap.add_argument("--reuse-references", action="store_true")
    ap.add_argument("--analyse-only", action="store_true")
    ap.add_argument("--note", default="", help="recorded in the results: the binary's origin")
    args = ap.parse_args()
    args.glint = os.path.abspath(args.glint)
    args.scene = os.path.abspath(os.path.join(args.assets, "gltf", "DamagedHelmet", "glTF",
                                              "DamagedHelmet.gltf"))
    args.scene_rel = "$GLINT_ASSETS/gltf/DamagedHelmet/glTF/DamagedHelmet.gltf"
    if not os.path.exists(args.scene):
        sys.exit(f"helmet_equal_error: {args.scene} is missing (GLINT_ASSETS; get_assets.sh)")
    os.makedirs(args.work, exist_ok=True)
    os.makedirs(args.out, exist_ok=True)
    args.records = os.path.join(args.work, "records.jsonl")
    args.sidecar = os.path.join(args.work, "DamagedHelmet.glint.json")
    with open(args.sidecar, "w") as f:
        json.dump(SIDECAR, f)
    args.blender_script = os.path.join(args.work, "cycles.py")
    with open(args.blender_script, "w") as f:
        f.write(blender_script())
    if not args.analyse_only:
        if not shutil.which(args.blender):
            sys.exit("helmet_equal_error: no blender (apt-get install blender)")
        old = read_records(args.records)
        keep = [r for r in old if r.get("reference")] if args.reuse_references else []
        with open(args.records, "w") as f:
            for r in keep:
                f.write(json.dumps(r) + "\n")
        have = {r["renderer"] for r in keep}
        for name, fn, spp in (("glint", render_glint, args.glint_reference_spp),
                              ("cycles", render_cycles, args.cycles_reference_spp)):
            if name in have:
                continue
            print(f"reference: {name} {spp} spp", flush=True)
            r = fn(args, spp, 1000, os.path.join(args.work, f"{name}_ref.exr"))
            r["reference"] = True
            append(args.records, r)
            print(json.dumps(r), flush=True)
        gl = [int(s) for s in args.glint_spp.split(",")]
        cy = [int(s) for s in args.cycles_spp.split(",")]
        for rnd in range(args.rounds):
            print(f"round {rnd}: load {load_average()}", flush=True)
            r = glint_setup(args, rnd)
            append(args.records, r)
            print(json.dumps(r), flush=True)
            jobs = []
            for i in range(max(len(gl), len(cy))):
                if i < len(gl):
                    jobs.append(("glint", render_glint, gl[i]))
                if i < len(cy):
                    jobs.append(("cycles", render_cycles, cy[i]))
            for name, fn, spp in jobs:
                r = fn(args, spp, rnd + 1, os.path.join(args.work, f"{name}_{spp}_r{rnd}.exr"))
                r["round"] = rnd
                append(args.records, r)
                print(json.dumps({k: r[k] for k in ("renderer", "spp", "round", "render_seconds",
                                                     "cpu_seconds", "wall_seconds",
                                                     "load_before")}), flush=True)
    res = analyse(args)
    with open(os.path.join(args.out, "helmet_equal_error.json"), "w") as f:
        json.dump(res, f, indent=1)
    md = markdown(res)
    with open(os.path.join(args.out, "helmet_equal_error.md"), "w") as f:
        f.write(md)
    print(md)
    side_by_side(args, os.path.join(args.out, "references.png"))


if __name__ == "__main__":
    main()
