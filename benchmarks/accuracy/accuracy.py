#!/usr/bin/python3
"""Accuracy against time: for each effect's scene and each method, the error of a ladder of
renders against a converged reference, and the wall time each took.

Usage: accuracy.py [--glint build/glint] [--out benchmarks/results/accuracy] [--work DIR]
                   [--effects dragon,glass,...] [--quick] [--check] [--repeat 3]
                   [--fresh-references] [--threads N]

Run from anywhere; paths in EFFECTS are relative to the repository root. For every effect
(one scene, below) it renders each reference once (cached under --work by a hash of the scene
file and the settings), then each method's ladder (more spp, or more of the method's own
quality knob: VPL light paths, march step), measures the time (`glint render --stats`:
accel_build_seconds + render_seconds, the fastest of --repeat runs for renders under two
seconds) and the error against every reference the method is compared with (`glint diff
--json`: RMSE and relative MSE), and writes into --out:

  accuracy.json   every point, the machine, the commit, the load average
  accuracy.md     the tables: per effect, every point; the winning method per time budget;
                  each method's last error and local slope (a slope near 0 is a floor)
  EFFECT.png      log-log RMSE against seconds, one curve per method, one panel per reference

--quick is the smoke test (ctest `accuracy_quick`): tiny images, two ladder points per method,
low-spp references, only the instant-radiosity box unless --effects says otherwise, output
under --work; --check then
asserts the outputs exist, hold finite numbers, and that each unbiased method's error falls
along its ladder. Needs Debian's python3-matplotlib (scripts/setup.sh installs it).
"""
import argparse
import copy
import datetime
import hashlib
import json
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.dirname(HERE))
from accel_report import cpu_model  # noqa: E402  (benchmarks/accel_report.py)

# ---------------------------------------------------------------------------------------------
# What is measured
# ---------------------------------------------------------------------------------------------
#
# An effect: one scene (`scene`, or a shared-asset mesh `asset` under $GLINT_ASSETS with a
# `sidecar`), an image size, `references` (name -> render settings and spp) and `methods`.
# A method's settings: `integrator` (keys merged into the scene's render.integrator), `accel`,
# `camera`; its ladder: `knob` ("spp", or an integrator key such as "vpl_paths") over `values`,
# at `spp` when the knob is not spp; `refs`: the references it is compared with (default: all);
# `unbiased`: the references it converges to (its error there must keep falling).
#
# Reference spp: at least 16x the highest spp of the ladders of the same integrator, so the
# reference's own noise adds at most sqrt(1 + 1/16) - 1 = 3% to the smallest error measured
# against it; accuracy.md prints each reference's estimated own RMSE (the best unbiased ladder
# point's error scaled by sqrt(spp / reference spp)).

LADDER = [1, 4, 16, 64]

EFFECTS = [
    {
        "name": "dragon",
        "title": "Dragon in a box, quad area light: path tracer on Embree and the kd-trees",
        "asset": "stanford/dragon_vrip_res2.glb",
        "sidecar": "benchmarks/accuracy/dragon_box.glint.json",
        "width": 128, "height": 96,
        # 16x the plain Embree ladder's last spp, which reaches past the adaptive ladder's
        # time (comparing against a curve held flat past its last point would flatter it).
        "references": {"path": {"integrator": {"type": "path"}, "spp": 4096}},
        "methods": [
            {"label": "path, Embree", "integrator": {"type": "path"}, "accel": "embree",
             "values": [1, 4, 16, 64, 256], "unbiased": ["path"]},
            {"label": "path, Embree, adaptive (16-128 spp)", "integrator": {"type": "path"},
             "accel": "embree", "knob": "adaptive", "values": [0.4, 0.2, 0.1, 0.05],
             "spp": 128, "min_spp": 16},
            {"label": "path, SAH kd-tree", "integrator": {"type": "path"}, "accel": "kdtree",
             "values": LADDER, "unbiased": ["path"]},
            {"label": "path, median kd-tree", "integrator": {"type": "path"},
             "accel": "kdtree-median", "values": LADDER, "unbiased": ["path"]},
            {"label": "Whitted (direct light only)", "integrator": {"type": "whitted"},
             "accel": "embree", "values": LADDER},
        ],
    },
    {
        "name": "glass",
        "title": "Glass ball and its caustic under a small sphere light",
        "scene": "benchmarks/accuracy/glass_caustic.json",
        "width": 128, "height": 96,
        "references": {"path": {"integrator": {"type": "path"}, "spp": 4096}},
        "methods": [
            {"label": "path", "integrator": {"type": "path"}, "values": [1, 4, 16, 64, 256],
             "unbiased": ["path"]},
            # Adaptive sampling: the knob is the threshold, each pixel takes 16 to 256 spp.
            {"label": "path, adaptive (16-256 spp)", "integrator": {"type": "path"},
             "knob": "adaptive", "values": [0.4, 0.2, 0.1, 0.05, 0.025], "spp": 256,
             "min_spp": 16},
            {"label": "instant radiosity, 4 spp, unclamped",
             "integrator": {"type": "instant-radiosity", "vpl_clamp": 0}, "knob": "vpl_paths",
             "values": [16, 64, 256, 1024], "spp": 4},
            {"label": "instant radiosity, 4 spp, G clamp 10",
             "integrator": {"type": "instant-radiosity", "vpl_clamp": 10}, "knob": "vpl_paths",
             "values": [16, 64, 256, 1024], "spp": 4},
            {"label": "Whitted (no caustic, no indirect)", "integrator": {"type": "whitted"},
             "values": LADDER},
        ],
    },
    {
        "name": "fog",
        "title": "Fog with volumetric shadows: single scattering (march steps, tracking) "
                 "against the path tracer's multiple scattering",
        "scene": "benchmarks/accuracy/fog_shafts.json",
        "width": 128, "height": 72,
        "references": {
            "single scattering": {"integrator": {"type": "whitted", "volume": "single",
                                                 "volume_estimator": "track"}, "spp": 1024},
            "multiple scattering": {"integrator": {"type": "path", "max_depth": 8},
                                    "spp": 1024},
        },
        "methods": [
            {"label": "Whitted, march step 0.6",
             "integrator": {"type": "whitted", "volume_estimator": "march", "volume_step": 0.6},
             "values": LADDER},
            {"label": "Whitted, march step 0.2",
             "integrator": {"type": "whitted", "volume_estimator": "march", "volume_step": 0.2},
             "values": LADDER},
            {"label": "Whitted, march step 0.07",
             "integrator": {"type": "whitted", "volume_estimator": "march", "volume_step": 0.07},
             "values": LADDER},
            {"label": "Whitted, tracking",
             "integrator": {"type": "whitted", "volume_estimator": "track"},
             "values": LADDER, "unbiased": ["single scattering"]},
            {"label": "path (multiple scattering)", "integrator": {"type": "path", "max_depth": 8},
             "values": LADDER, "unbiased": ["multiple scattering"]},
        ],
    },
    {
        "name": "smoke",
        "title": "Noise-density fog (fBm, 3 octaves): march steps against tracking, and the "
                 "path tracer's multiple scattering",
        "scene": "benchmarks/accuracy/fog_noise.json",
        "width": 128, "height": 72,
        "references": {
            "single scattering": {"integrator": {"type": "whitted", "volume": "single",
                                                 "volume_estimator": "track"}, "spp": 1024},
            "multiple scattering": {"integrator": {"type": "path", "max_depth": 8},
                                    "spp": 1024},
        },
        "methods": [
            {"label": "Whitted, march step 0.6",
             "integrator": {"type": "whitted", "volume_estimator": "march", "volume_step": 0.6},
             "values": LADDER},
            {"label": "Whitted, march step 0.2",
             "integrator": {"type": "whitted", "volume_estimator": "march", "volume_step": 0.2},
             "values": [1, 4, 16]},
            {"label": "Whitted, tracking",
             "integrator": {"type": "whitted", "volume_estimator": "track"},
             "values": LADDER, "unbiased": ["single scattering"]},
            {"label": "path (multiple scattering)", "integrator": {"type": "path", "max_depth": 8},
             "values": LADDER, "unbiased": ["multiple scattering"]},
        ],
    },
    {
        "name": "lens_motion",
        "title": "Depth of field and motion blur (scenes/motion/effects.json), Whitted: each "
                 "camera against its own reference",
        "scene": "scenes/motion/effects.json",
        "width": 192, "height": 108,
        "references": {cam: {"integrator": {"type": "whitted"}, "camera": cam, "spp": 1024}
                       for cam in ["pinhole", "lens", "motion", "lens+motion"]},
        "methods": [
            {"label": cam, "camera": cam, "integrator": {"type": "whitted"}, "values": LADDER,
             "refs": [cam], "unbiased": [cam]}
            for cam in ["pinhole", "lens", "motion", "lens+motion"]
        ],
        # The equal-error comparison effects_cost.py makes: what each camera needs to reach
        # the pinhole's error at 16 spp.
        "target": {"method": "pinhole", "spp": 16},
    },
    {
        "name": "instant_radiosity",
        "title": "Cornell box (tests/reference_images/scenes/cornell_ir.json): instant radiosity's VPL "
                 "count and clamp against the path tracer",
        "scene": "tests/reference_images/scenes/cornell_ir.json",
        "width": 64, "height": 64,
        "references": {"path": {"integrator": {"type": "path", "max_depth": 6}, "spp": 4096}},
        "methods": [
            {"label": "path", "integrator": {"type": "path", "max_depth": 6},
             "values": [1, 4, 16, 64, 256], "unbiased": ["path"]},
            {"label": "IR, 4 spp, unclamped",
             "integrator": {"type": "instant-radiosity", "max_depth": 6, "vpl_clamp": 0},
             "knob": "vpl_paths", "values": [16, 64, 256, 1024], "spp": 4},
            {"label": "IR, 4 spp, G clamp 100",
             "integrator": {"type": "instant-radiosity", "max_depth": 6, "vpl_clamp": 100},
             "knob": "vpl_paths", "values": [16, 64, 256, 1024], "spp": 4},
            {"label": "IR, 256 light paths, G clamp 100",
             "integrator": {"type": "instant-radiosity", "max_depth": 6, "vpl_clamp": 100,
                            "vpl_paths": 256},
             "values": [1, 4, 16]},
        ],
    },
]

QUICK_WIDTH = 32
# The smoke test's default: spp and knob ladders, biased and unbiased methods, in few renders
# (each glint process costs about half a second of start-up).
QUICK_EFFECTS = ["instant_radiosity"]
QUICK_REFERENCE_SPP = 64

# ---------------------------------------------------------------------------------------------
# Running glint (also used by benchmarks/effects_cost.py)
# ---------------------------------------------------------------------------------------------


def run(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode not in (0, 1):  # diff exits 1 for "fail", which only means "differs"
        sys.exit(f"failed ({p.returncode}): {' '.join(cmd)}\n{p.stderr}")
    if p.returncode == 1 and cmd[1] == "render":
        sys.exit(f"render failed: {' '.join(cmd)}\n{p.stderr}")
    return p.stdout


def render(glint, scene, out, spp, width, height, seed=1, camera=None, accel=None,
           sidecar=None, threads=None, repeat=1, repeat_below=2.0):
    """Renders `scene` to `out` and returns the stats of the fastest run: the first run always,
    up to `repeat` runs in all while a run takes under `repeat_below` seconds (the images are
    identical: same seed), so a busy machine inflates the times of short renders less."""
    stats = out + ".stats.json"
    cmd = [glint, "render", scene, "--spp", str(spp), "--seed", str(seed), "-o", out,
           "--stats", stats, "--quiet", "--width", str(width), "--height", str(height)]
    if camera:
        cmd += ["--camera", camera]
    if accel:
        cmd += ["--accel", accel]
    if sidecar:
        cmd += ["--sidecar", sidecar]
    if threads:
        cmd += ["--threads", str(threads)]
    best = None
    for i in range(max(1, repeat)):
        run(cmd)
        with open(stats) as f:
            st = json.load(f)
        if best is None or st["render_seconds"] < best["render_seconds"]:
            best = st
        if st["render_seconds"] >= repeat_below:
            break
    return best


def diff(glint, image, reference):
    """`glint diff --json` of an image against a reference: rmse, rel_mse, ..."""
    return json.loads(run([glint, "diff", image, reference, "--json", "--fail", "1e9"]))


def seconds(stats):
    """The time a method costs: building the accelerator (kd-trees cost more than Embree) and
    rendering. Loading the scene is the same for every method and left out; instant
    radiosity's light paths (at most 1,024 paths) are traced before render_seconds starts and
    are not counted."""
    return stats.get("accel_build_seconds", 0.0) + stats["render_seconds"]


def interpolate_loglog(points, x):
    """y at x on the log-log polyline through `points` [(x, y)], or None outside its range."""
    pts = sorted(p for p in points if p[0] > 0 and p[1] > 0)
    for (x0, y0), (x1, y1) in zip(pts, pts[1:]):
        if x0 <= x <= x1:
            if x1 == x0:
                return min(y0, y1)
            f = (math.log(x) - math.log(x0)) / (math.log(x1) - math.log(x0))
            return math.exp(math.log(y0) + f * (math.log(y1) - math.log(y0)))
    if len(pts) == 1 and pts[0][0] == x:
        return pts[0][1]
    return None


def spp_for_error(curve, target):
    """The spp at which the log-log interpolated error curve [(spp, error)] crosses `target`."""
    pts = sorted(curve)
    for (s0, e0), (s1, e1) in zip(pts, pts[1:]):
        if e0 >= target >= e1 and e0 > 0 and e1 > 0:
            f = (math.log(e0) - math.log(target)) / (math.log(e0) - math.log(e1))
            return math.exp(math.log(s0) + f * (math.log(s1) - math.log(s0)))
    if pts and target >= pts[0][1]:
        return float(pts[0][0])
    # Beyond the ladder: extrapolate with Monte Carlo's 1/sqrt(spp).
    s, e = pts[-1]
    return s * (e / target) ** 2


# ---------------------------------------------------------------------------------------------
# Scenes with settings
# ---------------------------------------------------------------------------------------------


def assets_dir():
    return os.environ.get("GLINT_ASSETS") or os.path.join(os.path.dirname(ROOT), "shared", "assets")


def scene_with(effect, integrator, work, render_keys=None):
    """The scene (or sidecar) of `effect` with `integrator` merged into render.integrator (and
    `render_keys`, e.g. adaptive sampling, into render), written under `work` (named by its
    content's hash); returns (scene, sidecar, text)."""
    base = effect.get("sidecar") or effect["scene"]
    with open(os.path.join(ROOT, base)) as f:
        doc = json.load(f)
    if "gltf" in doc or any("file" in t for t in doc.get("textures", [])):
        sys.exit(f"{base}: scenes that name files cannot be copied for their settings")
    render_block = doc.setdefault("render", {})
    current = render_block.get("integrator", {"type": "whitted"})
    if isinstance(current, str):
        current = {"type": current}
    merged = dict(current)
    if integrator.get("type", current.get("type")) != current.get("type"):
        # Keys of another integrator (say vpl_paths on a path tracer) would be kept otherwise;
        # keep only those that every integrator reads.
        merged = {k: v for k, v in current.items() if k in ("max_depth", "rr_depth")}
    merged.update(integrator)
    render_block["integrator"] = merged
    render_block.update(render_keys or {})
    text = json.dumps(doc, indent=1, sort_keys=True)
    digest = hashlib.sha256(text.encode()).hexdigest()[:16]
    os.makedirs(os.path.join(work, "scenes"), exist_ok=True)
    path = os.path.join(work, "scenes", f"{effect['name']}_{digest}.json")
    if not os.path.exists(path):
        with open(path, "w") as f:
            f.write(text)
    if effect.get("asset"):
        mesh = os.path.join(assets_dir(), effect["asset"])
        if not os.path.isfile(mesh):
            sys.exit(f"accuracy: {mesh} not found: set GLINT_ASSETS to the shared asset folder "
                     f"(see benchmarks/get_assets.sh), or leave out --effects {effect['name']}")
        return mesh, path, text
    return path, None, text


def render_spec(args, effect, spec, spp, out, repeat):
    scene, sidecar, _ = scene_with(effect, spec.get("integrator", {}), args.work,
                                   spec.get("render"))
    return render(args.glint, scene, out, spp, effect["width"], effect["height"],
                  seed=spec.get("seed", 1), camera=spec.get("camera"), accel=spec.get("accel"),
                  sidecar=sidecar, threads=args.threads, repeat=repeat)


def reference(args, effect, name, spec):
    """Renders (or finds in the cache) one reference; returns (path, record)."""
    _, _, text = scene_with(effect, spec.get("integrator", {}), args.work)
    key = json.dumps({"scene": text, "asset": effect.get("asset"), "spp": spec["spp"],
                      "width": effect["width"], "height": effect["height"],
                      "camera": spec.get("camera"), "accel": spec.get("accel"),
                      "seed": spec.get("seed", 1)}, sort_keys=True)
    digest = hashlib.sha256(key.encode()).hexdigest()[:16]
    folder = os.path.join(args.work, "references")
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, f"{effect['name']}_{digest}.exr")
    stats_path = path + ".stats.json"
    cached = os.path.exists(path) and os.path.exists(stats_path) and not args.fresh_references
    if cached:
        with open(stats_path) as f:
            st = json.load(f)
    else:
        log(f"{effect['name']}: reference '{name}' at {spec['spp']} spp ...")
        st = render_spec(args, effect, spec, spec["spp"], path, repeat=1)
    log(f"{effect['name']}: reference '{name}' {spec['spp']} spp "
        f"{seconds(st):.1f} s{' (cached)' if cached else ''}")
    return path, {"name": name, "spp": spec["spp"], "integrator": st["integrator"],
                  "settings": spec, "seconds": seconds(st), "cached": cached,
                  "file": os.path.relpath(path, args.work), "nonfinite_samples":
                  st.get("nonfinite_samples", 0)}


def log(msg):
    print(msg, file=sys.stderr, flush=True)


# ---------------------------------------------------------------------------------------------
# Measuring
# ---------------------------------------------------------------------------------------------


def quick_effect(effect):
    """The smoke test's version of an effect: tiny image, two ladder points, cheap references."""
    e = copy.deepcopy(effect)
    e["height"] = max(8, round(QUICK_WIDTH * effect["height"] / effect["width"]))
    e["width"] = QUICK_WIDTH
    for spec in e["references"].values():
        spec["spp"] = min(spec["spp"], QUICK_REFERENCE_SPP)
    for m in e["methods"]:
        m["values"] = m["values"][:2]
    return e


def measure(args, effect):
    load_start = list(os.getloadavg())
    refs = {name: reference(args, effect, name, spec)
            for name, spec in effect["references"].items()}
    folder = os.path.join(args.work, effect["name"])
    os.makedirs(folder, exist_ok=True)
    methods = []
    for m in effect["methods"]:
        knob = m.get("knob", "spp")
        compared = m.get("refs", list(refs))
        points = []
        for value in m["values"]:
            integrator = dict(m.get("integrator", {}))
            spp = value if knob == "spp" else m["spp"]
            render_keys = None
            if knob == "adaptive":  # adaptive sampling's threshold, at most `spp` per pixel
                render_keys = {"adaptive": {"threshold": value, "min_spp": m.get("min_spp", 16)}}
            elif knob != "spp":
                integrator[knob] = value
            spec = dict(m, integrator=integrator, render=render_keys)
            tag = "".join(c if c.isalnum() else "_" for c in m["label"])
            out = os.path.join(folder, f"{tag}_{knob}{value}.exr")
            st = render_spec(args, effect, spec, spp, out, args.repeat)
            point = {knob: value, "spp": spp, "mean_spp": st.get("mean_spp", spp),
                     "seconds": seconds(st),
                     "render_seconds": st["render_seconds"],
                     "accel_build_seconds": st.get("accel_build_seconds", 0.0),
                     "rays": st["rays"]["total"], "nonfinite_samples": st.get("nonfinite_samples", 0),
                     "error": {}}
            if "integrator_setup" in st:
                point["integrator_setup"] = st["integrator_setup"]
            for r in compared:
                d = diff(args.glint, out, refs[r][0])
                point["error"][r] = {"rmse": d["rmse"], "rel_mse": d["rel_mse"]}
            points.append(point)
            errs = "  ".join(f"{r}: {e['rmse']:.5f}" for r, e in point["error"].items())
            log(f"{effect['name']}: {m['label']:40s} {knob} {value:5} {point['seconds']:8.3f} s  {errs}")
        methods.append({"label": m["label"], "knob": knob, "integrator": m.get("integrator", {}),
                        "accel": m.get("accel", "embree"), "camera": m.get("camera"),
                        "spp": m.get("spp"), "refs": compared,
                        "unbiased": m.get("unbiased", []), "points": points})
    result = {"name": effect["name"], "title": effect["title"],
              "scene": effect.get("scene") or f"$GLINT_ASSETS/{effect['asset']} + {effect['sidecar']}",
              "width": effect["width"], "height": effect["height"],
              "references": {name: r[1] for name, r in refs.items()}, "methods": methods}
    # The references' own error, estimated from the most accurate unbiased point against them.
    for name, rec in result["references"].items():
        best = None
        for m in methods:
            if name in m["unbiased"] and m["knob"] == "spp":
                p = m["points"][-1]
                est = p["error"][name]["rmse"] * math.sqrt(p["spp"] / rec["spp"])
                best = est if best is None else min(best, est)
        rec["estimated_own_rmse"] = best
    # Gaps between references (e.g. single against multiple scattering): what a method that
    # converges to one of them can never get below against the other.
    names = list(refs)
    result["reference_gaps"] = []
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            if effect.get("target"):  # per-camera references of different images: no gap
                continue
            d = diff(args.glint, refs[a][0], refs[b][0])
            result["reference_gaps"].append({"a": a, "b": b, "rmse": d["rmse"],
                                             "rel_mse": d["rel_mse"]})
    if effect.get("target"):
        result["equal_error"] = equal_error(result, effect["target"])
    result["summary"] = summarise(result)
    result["measured"] = {"date": datetime.datetime.now().isoformat(timespec="seconds"),
                          "load_average_start": load_start,
                          "load_average_end": list(os.getloadavg())}
    return result


def curve(method, ref, metric="rmse"):
    return [(p["seconds"], p["error"][ref][metric]) for p in method["points"] if ref in p["error"]]


def error_within(points, budget):
    """The error a method reaches within `budget` seconds: interpolated log-log between its
    measured points; past its last point, its last error (it could stop there: conservative, no
    extrapolation); before its first point, None (it has no image yet)."""
    pts = sorted(points)
    if not pts or budget < pts[0][0]:
        return None
    if budget >= pts[-1][0]:
        return pts[-1][1]
    return interpolate_loglog(pts, budget)


def summarise(result):
    """Per reference: the winning method at log-spaced time budgets (error_within), and each
    method's last error and the local slope of log error over log seconds between its last two
    points (-0.5 is Monte Carlo's rate; near 0 a floor). Effects whose methods each have their
    own reference (the cameras of lens_motion) get no winners: their errors do not compare."""
    out = {}
    for ref in result["references"]:
        methods = [m for m in result["methods"] if ref in m["refs"]]
        times = [t for m in methods for t, _ in curve(m, ref)]
        budgets = []
        if times and len(methods) > 1:
            lo, hi = min(times), max(times)
            n = 7
            budgets = [lo * (hi / lo) ** (i / (n - 1)) for i in range(n)] if hi > lo else [lo]
        winners = []
        for b in budgets:
            reached = []  # (error, seconds at which the method had it, label)
            for m in methods:
                c = curve(m, ref)
                e = error_within(c, b)
                if e is not None:
                    reached.append((e, min(b, max(t for t, _ in c)), m["label"]))
            best = None
            if reached:
                lowest = min(r[0] for r in reached)
                e, _, label = min((r for r in reached if r[0] <= 1.01 * lowest), key=lambda r: r[1])
                best = (label, e)
            winners.append({"seconds": b, "method": best[0] if best else None,
                            "rmse": best[1] if best else None})
        per_method = []
        for m in methods:
            c = curve(m, ref)
            slope = None
            if len(c) >= 2 and c[-1][0] > c[-2][0] and c[-1][1] > 0 and c[-2][1] > 0:
                slope = (math.log(c[-1][1]) - math.log(c[-2][1])) / (math.log(c[-1][0]) - math.log(c[-2][0]))
            per_method.append({"method": m["label"], "last_rmse": c[-1][1], "last_seconds": c[-1][0],
                               "last_slope": slope, "unbiased": ref in m["unbiased"]})
        out[ref] = {"winners": winners, "methods": per_method}
    return out


def equal_error(result, target):
    """effects_cost.py's comparison: the spp and seconds each method needs to reach the target
    method's error at the target spp (each against its own reference)."""
    by_label = {m["label"]: m for m in result["methods"]}
    base = by_label[target["method"]]
    ref0 = base["refs"][0]
    at = {p["spp"]: p for p in base["points"]}
    if target["spp"] not in at:
        return None
    goal = at[target["spp"]]["error"][ref0]["rmse"]
    rows = []
    for m in result["methods"]:
        ref = m["refs"][0]
        pts = {p["spp"]: p for p in m["points"]}
        sec_per_spp = sum(p["seconds"] for p in m["points"]) / sum(p["spp"] for p in m["points"])
        need = spp_for_error([(p["spp"], p["error"][ref]["rmse"]) for p in m["points"]], goal)
        rows.append({"method": m["label"],
                     "time_ratio_equal_spp": (pts[target["spp"]]["seconds"] / at[target["spp"]]["seconds"]
                                              if target["spp"] in pts else None),
                     "spp_for_target": need, "seconds_for_target": need * sec_per_spp})
    return {"method": target["method"], "spp": target["spp"], "rmse": goal, "rows": rows}


# ---------------------------------------------------------------------------------------------
# Writing
# ---------------------------------------------------------------------------------------------


def machine(args, load_start):
    """The machine, the build and the commit, taken when the run starts."""
    def git(*a):
        try:
            return subprocess.run(["git", "-C", ROOT, *a], capture_output=True, text=True,
                                  check=True).stdout.strip()
        except (OSError, subprocess.CalledProcessError):
            return None
    build_type = None
    cache = os.path.join(os.path.dirname(os.path.abspath(args.glint)), "CMakeCache.txt")
    if os.path.exists(cache):
        with open(cache) as f:
            for line in f:
                if line.startswith("CMAKE_BUILD_TYPE:"):
                    build_type = line.split("=", 1)[1].strip()
    return {"cpu": cpu_model(), "hardware_threads": os.cpu_count(), "threads": args.threads or 0,
            "load_average_start": load_start, "load_average_end": None,
            "commit": git("rev-parse", "HEAD"), "branch": git("rev-parse", "--abbrev-ref", "HEAD"),
            "dirty": bool(git("status", "--porcelain", "--untracked-files=no")),
            "build_type": build_type, "date": datetime.datetime.now().isoformat(timespec="seconds")}


def fmt_e(x):
    return "—" if x is None else f"{x:.2e}"


def measured(eff):
    """When an effect was measured; effects kept from an earlier run carry that run's machine
    record instead (date and load average over the whole run)."""
    m = eff.get("measured")
    if not m:
        return ""
    run = m.get("machine")
    src = m if "date" in m else run
    text = (f"Measured {src['date'].replace('T', ' ')[:16]}, load average "
            f"{src['load_average_start'][0]:.1f} → {src['load_average_end'][0]:.1f}")
    if run:
        text += (f" (in an earlier run of all effects, glint at commit "
                 f"`{(run['commit'] or '?')[:12]}`)")
    return text + "."


def markdown(doc):
    mc = doc["machine"]
    lines = [f"# Accuracy against time ({mc['date'][:10]})", "",
             f"Generated by `benchmarks/accuracy/accuracy.py`{' --quick' if doc['quick'] else ''} "
             f"on {mc['cpu']} ({mc['hardware_threads']} hardware threads, "
             f"{'all' if not mc['threads'] else mc['threads']} used), glint "
             f"{mc['build_type'] or '?'} build of commit `{(mc['commit'] or '?')[:12]}`"
             f"{' (with uncommitted changes)' if mc['dirty'] else ''}; load average "
             f"{mc['load_average_start'][0]:.1f} at the start, {mc['load_average_end'][0]:.1f} at "
             f"the end (a shared machine: times from a loaded machine are slower, not noisier "
             f"in error). Seconds are accel build + render (`--stats`), the fastest of "
             f"{doc['repeat']} runs for renders under 2 s. Errors are `glint diff --json` against "
             f"the reference (RMSE over pixels and channels; relMSE = mean (a−b)²/(b²+0.01)).", ""]
    for eff in doc["effects"]:
        lines += [f"## {eff['name']}: {eff['title']}", "",
                  f"Scene `{eff['scene']}`, {eff['width']}×{eff['height']}. "
                  f"Plot: [`{eff['name']}.png`]({eff['name']}.png). " + measured(eff), "",
                  "| reference | integrator | spp | seconds | estimated own RMSE |", "|---|---|---:|---:|---:|"]
        for name, r in eff["references"].items():
            lines.append(f"| {name} | {r['integrator']} | {r['spp']} | {r['seconds']:.1f} | "
                         f"{fmt_e(r.get('estimated_own_rmse'))} |")
        for g in eff.get("reference_gaps", []):
            lines += ["", f"Gap between the references '{g['a']}' and '{g['b']}': RMSE "
                          f"{g['rmse']:.2e}, relMSE {g['rel_mse']:.2e} (the floor of a method "
                          f"converging to one of them, measured against the other)."]
        for ref, s in eff["summary"].items():
            if s["winners"]:
                lines += ["", f"**Against '{ref}'.** Best method per time budget (a method's "
                          "error interpolated log-log between its measured points; past its last "
                          "point, its last error; within 1% of each other, the one that got there "
                          "first):", "", "| budget (s) | best method | its RMSE |", "|---:|---|---:|"]
                for w in s["winners"]:
                    lines.append(f"| {w['seconds']:.3g} | {w['method'] or '—'} | {fmt_e(w['rmse'])} |")
            else:
                lines += ["", f"**Against '{ref}'.**"]
            lines += ["", "| method | last seconds | last RMSE | last slope (log RMSE / log s) | "
                          "converges to this reference |", "|---|---:|---:|---:|---|"]
            for m in s["methods"]:
                slope = "—" if m["last_slope"] is None else f"{m['last_slope']:+.2f}"
                lines.append(f"| {m['method']} | {m['last_seconds']:.3f} | {fmt_e(m['last_rmse'])} | "
                             f"{slope} | {'yes' if m['unbiased'] else 'no'} |")
        if eff.get("equal_error"):
            q = eff["equal_error"]
            lines += ["", f"Equal error (as `effects_cost.py`): the spp and seconds each camera "
                          f"needs to reach the {q['method']} camera's RMSE at {q['spp']} spp "
                          f"({q['rmse']:.2e}), each against its own reference:", "",
                      "| camera | time vs pinhole at equal spp | spp for that error | seconds |",
                      "|---|---:|---:|---:|"]
            for r in q["rows"]:
                ratio = "—" if r["time_ratio_equal_spp"] is None else f"{r['time_ratio_equal_spp']:.2f}×"
                lines.append(f"| {r['method']} | {ratio} | {r['spp_for_target']:.0f} | "
                             f"{r['seconds_for_target']:.3f} |")
        lines += ["", "<details><summary>Every point</summary>", "",
                  "| method | knob | spp | seconds | " +
                  " | ".join(f"RMSE / relMSE vs '{r}'" for r in eff["references"]) + " |",
                  "|---|---:|---:|---:|" + "---:|" * len(eff["references"])]
        for m in eff["methods"]:
            for p in m["points"]:
                cells = []
                for r in eff["references"]:
                    e = p["error"].get(r)
                    cells.append("—" if e is None else f"{e['rmse']:.2e} / {e['rel_mse']:.2e}")
                lines.append(f"| {m['label']} | {m['knob']} {p[m['knob']]} | {p['spp']} | "
                             f"{p['seconds']:.3f} | " + " | ".join(cells) + " |")
        lines += ["", "</details>", ""]
    return "\n".join(lines) + "\n"


def plot(doc, eff, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    refs = list(eff["references"])
    panels = [r for r in refs if any(r in m["refs"] for m in eff["methods"])]
    per_camera = bool(eff.get("equal_error"))
    if per_camera:  # every method against its own reference: one panel
        panels = [None]
    fig, axes = plt.subplots(1, len(panels), figsize=(6.4 * len(panels), 4.8), squeeze=False)
    markers = "osD^vP*X"
    for ax, ref in zip(axes[0], panels):
        for i, m in enumerate(eff["methods"]):
            r = m["refs"][0] if ref is None else ref
            if r not in m["refs"]:
                continue
            c = curve(m, r)
            xs, ys = [t for t, _ in c], [e for _, e in c]
            style = "-" if r in m["unbiased"] else "--"
            ax.loglog(xs, ys, style, marker=markers[i % len(markers)], label=m["label"])
            for p, x, y in zip(m["points"], xs, ys):
                ax.annotate(str(p[m["knob"]]), (x, y), textcoords="offset points", xytext=(3, 3),
                            fontsize=6, alpha=0.7)
        # A guide of slope -1/2 (Monte Carlo) through the first unbiased curve's first point.
        for m in eff["methods"]:
            r = m["refs"][0] if ref is None else ref
            if r in m["unbiased"]:
                (t0, e0) = curve(m, r)[0]
                t1 = t0 * 1e3
                ax.loglog([t0, t1], [e0, e0 * (t1 / t0) ** -0.5], ":", color="grey", lw=0.8,
                          label="slope −1/2")
                break
        ax.set_xlabel("seconds (accel build + render)")
        ax.set_ylabel("RMSE")
        ax.set_title("against its own camera's reference" if ref is None else f"against '{ref}'",
                     fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
        xs = [t for m in eff["methods"] for t, _ in curve(m, m["refs"][0] if ref is None else ref)
              if (m["refs"][0] if ref is None else ref) in m["refs"]]
        if xs:
            ax.set_xlim(min(xs) / 1.5, max(xs) * 1.5)
    mc = doc["machine"]
    fig.suptitle(f"{eff['title']}\n{eff['width']}×{eff['height']}; solid: converges to that "
                 f"reference, dashed: biased there; labels: spp or knob; {mc['cpu']}, "
                 f"{mc['date'][:10]}", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def check(doc, out):
    """The smoke test's assertions; returns a list of failures."""
    problems = []
    for name in ["accuracy.json", "accuracy.md"] + [f"{e['name']}.png" for e in doc["effects"]]:
        p = os.path.join(out, name)
        if not os.path.isfile(p) or os.path.getsize(p) == 0:
            problems.append(f"{p} missing or empty")
    for eff in doc["effects"]:
        for m in eff["methods"]:
            for p in m["points"]:
                if not (math.isfinite(p["seconds"]) and p["seconds"] > 0):
                    problems.append(f"{eff['name']}/{m['label']}: seconds {p['seconds']}")
                if p["nonfinite_samples"]:
                    problems.append(f"{eff['name']}/{m['label']}: {p['nonfinite_samples']} NaN/Inf samples")
                for r, e in p["error"].items():
                    for k, v in e.items():
                        if v is None or not math.isfinite(v) or v <= 0:
                            problems.append(f"{eff['name']}/{m['label']} vs {r}: {k} = {v}")
            # An unbiased method 4x or 16x the spp must be closer to its limit (at 32 pixels
            # wide the RMSE falls by about 2 per 4x spp; a rise means a broken ladder).
            for r in m["unbiased"]:
                c = [p["error"][r]["rmse"] for p in m["points"]]
                if m["knob"] == "spp" and len(c) >= 2 and not c[-1] < c[0]:
                    problems.append(f"{eff['name']}/{m['label']} vs {r}: RMSE did not fall: {c}")
    return problems


def write(doc, out):
    with open(os.path.join(out, "accuracy.json"), "w") as f:
        json.dump(doc, f, indent=1)
    with open(os.path.join(out, "accuracy.md"), "w") as f:
        f.write(markdown(doc))
    for eff in doc["effects"]:
        plot(doc, eff, os.path.join(out, f"{eff['name']}.png"))
    log(f"accuracy: wrote {out}/accuracy.json, accuracy.md and "
        f"{', '.join(e['name'] + '.png' for e in doc['effects'])}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--glint", default=os.path.join(ROOT, "build", "glint"))
    ap.add_argument("--out", help="default: benchmarks/results/accuracy (--quick: WORK/quick)")
    ap.add_argument("--work", help="references and ladder images (default: BUILD/accuracy)")
    ap.add_argument("--effects", help="comma-separated names (default: all; --quick: "
                                      + ", ".join(QUICK_EFFECTS) + ")")
    ap.add_argument("--quick", action="store_true", help="the smoke test: tiny and fast")
    ap.add_argument("--check", action="store_true", help="assert the outputs hold finite numbers")
    ap.add_argument("--repeat", type=int, default=3, help="timed runs of a render under 2 s")
    ap.add_argument("--threads", type=int, default=0, help="render threads (0: all)")
    ap.add_argument("--fresh-references", action="store_true", help="ignore cached references")
    ap.add_argument("--report", action="store_true",
                    help="render nothing: rewrite accuracy.md and the plots from accuracy.json")
    args = ap.parse_args()
    args.glint = os.path.abspath(args.glint)
    if not os.access(args.glint, os.X_OK):
        sys.exit(f"accuracy: {args.glint} is not an executable (build first: scripts/build.sh)")
    args.work = os.path.abspath(args.work or os.path.join(os.path.dirname(args.glint), "accuracy"))
    if args.quick:
        args.work = os.path.join(args.work, "quick")
    out = os.path.abspath(args.out or (os.path.join(args.work, "results") if args.quick else
                                       os.path.join(ROOT, "benchmarks", "results", "accuracy")))
    os.makedirs(out, exist_ok=True)
    names = [e["name"] for e in EFFECTS]
    if args.effects:
        chosen = args.effects.split(",")
        unknown = [n for n in chosen if n not in names]
        if unknown:
            sys.exit(f"accuracy: unknown effect(s) {unknown}; known: {names}")
        effects = [e for e in EFFECTS if e["name"] in chosen]
    else:
        effects = [e for e in EFFECTS if not args.quick or e["name"] in QUICK_EFFECTS]
    if args.quick:
        effects = [quick_effect(e) for e in effects]
        args.repeat = 1

    if args.report:
        with open(os.path.join(out, "accuracy.json")) as f:
            doc = json.load(f)
        for eff in doc["effects"]:
            eff["summary"] = summarise(eff)
        write(doc, out)
        return

    run_machine = machine(args, list(os.getloadavg()))
    results = [measure(args, e) for e in effects]
    run_machine["load_average_end"] = list(os.getloadavg())
    # A run of some effects keeps the others' recorded results (and says which run they are from).
    previous = os.path.join(out, "accuracy.json")
    if args.effects and os.path.exists(previous):
        with open(previous) as f:
            old = json.load(f)
        if old.get("quick") == args.quick:
            done = {e["name"] for e in results}
            kept = {e["name"]: e for e in old["effects"] if e["name"] not in done}
            for e in kept.values():
                e.setdefault("measured", {}).setdefault("machine", old["machine"])
            fresh = {e["name"]: e for e in results}
            results = [fresh.get(n) or kept[n] for n in names if n in fresh or n in kept]
    doc = {"quick": args.quick, "repeat": args.repeat, "glint": args.glint, "work": args.work,
           "machine": run_machine, "effects": results}
    write(doc, out)
    if args.check:
        problems = check(doc, out)
        for p in problems:
            log(f"accuracy check: {p}")
        if problems:
            sys.exit(1)
        log(f"accuracy check: {sum(len(m['points']) for e in results for m in e['methods'])} "
            "points, all finite; every unbiased ladder's error falls")


if __name__ == "__main__":
    main()
