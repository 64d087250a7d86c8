#!/usr/bin/env python3
"""Turns the `glint bench-accel` JSON files of benchmarks/run_accel_benchmarks.sh into a
Markdown report (one table per mesh, the build-time scaling study, the 2008 reference numbers)
and a plot (ray rates and build times per backend and mesh, build-time scaling).

Usage: accel_report.py RESULTS_DIR --markdown OUT.md --plot OUT.png

RESULTS_DIR holds NAME.json (a whole mesh) and NAME_subN.json (NAME cut to N triangles).
"""
import argparse
import datetime
import glob
import json
import math
import os
import re
import sys

# The competition's numbers from 2008 (800x600, 16 rays per pixel), in seconds. Kept apart from
# ours: different machine, different rays; only the orders of magnitude compare.
REFERENCE_2008 = [
    # (structure, mesh, build s, render s)
    ("SAH kd-tree", "bunny", 19.9, 32.3),
    ("SAH kd-tree", "dragon", 91.9, 83.6),
    ("median kd-tree", "bunny", 1.37, 132.6),
    ("median kd-tree", "dragon", 4.29, 664.1),
]

MESH_ORDER = ["bun_zipper", "dragon_vrip_res2", "dragon_vrip"]


def load(results_dir):
    """Returns ({mesh: run}, [(mesh, n, run)]) for the whole meshes and the subsamples."""
    whole, cut = {}, []
    for path in sorted(glob.glob(os.path.join(results_dir, "*.json"))):
        name = os.path.splitext(os.path.basename(path))[0]
        with open(path) as f:
            run = json.load(f)
        m = re.fullmatch(r"(.+)_sub(\d+)", name)
        if m:
            cut.append((m.group(1), int(m.group(2)), run))
        else:
            whole[name] = run
    return whole, cut


def mesh_key(name):
    return (MESH_ORDER.index(name) if name in MESH_ORDER else len(MESH_ORDER), name)


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown CPU"


def fmt(x, digits=2):
    return f"{x:,.{digits}f}"


def ratio(a, b):
    return f"{a / b:.2f}" if b else "—"


def nlogn(n):
    return n * math.log2(n) if n > 1 else 1.0


def mesh_table(name, run):
    rays = run["width"] * run["height"] * run["spp"]
    lines = [
        f"### {name} ({run['triangles']:,} triangles)",
        "",
        f"{run['width']}×{run['height']}, {run['spp']} spp ({rays / 1e6:.2f} M camera rays), "
        f"{run['threads']} threads. Bare `rtcIntersect1` loop on the same camera rays: "
        f"{fmt(run['bare_embree_camera_mrays_per_second'])} Mrays/s.",
        "",
        "| backend | build s | bytes | camera Mrays/s | occlusion Mrays/s | camera s | "
        "build / embree | camera / embree | occlusion / embree | camera hits | nodes | leaves | "
        "empty leaves | max depth | prims/leaf | SAH cost |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    backends = run["backends"]
    ref = backends.get("embree")
    for backend, b in backends.items():
        camera_seconds = rays / (b["camera_mrays_per_second"] * 1e6) if b["camera_mrays_per_second"] else 0
        lines.append(
            f"| {backend} | {b['build_seconds']:.3f} | {b['bytes']:,} | "
            f"{fmt(b['camera_mrays_per_second'])} | {fmt(b['occlusion_mrays_per_second'])} | "
            f"{camera_seconds:.2f} | "
            + (
                f"{ratio(b['build_seconds'], ref['build_seconds'])} | "
                f"{ratio(b['camera_mrays_per_second'], ref['camera_mrays_per_second'])} | "
                f"{ratio(b['occlusion_mrays_per_second'], ref['occlusion_mrays_per_second'])} | "
                if ref
                else "— | — | — | "
            )
            + f"{b['camera_hits']:,} | {b['nodes']:,} | {b['leaves']:,} | {b['empty_leaves']:,} | "
            f"{b['max_depth']} | {b['mean_prims_per_leaf']:.2f} | {b['sah_cost']:.2f} |"
        )
    return lines


def targets(whole):
    """The issue's targets, as ratios measured in one run per mesh."""
    lines = [
        "## Targets",
        "",
        "Ratios within one run. SAH kd-tree camera rays >= 0.5x Embree and occlusion rays >= 0.4x "
        "(bunny, dragon); SAH build of the 202k dragon <= 5x Embree's high-quality BVH build "
        "(`RTC_BUILD_QUALITY_HIGH`, timed in the same run); median clearly slower than SAH.",
        "",
        "| mesh | SAH camera / embree | SAH occlusion / embree | SAH build / embree high-quality build | median camera: SAH faster by | median occlusion: SAH faster by |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for name in sorted(whole, key=mesh_key):
        b = whole[name]["backends"]
        e, k, m = b.get("embree"), b.get("kdtree"), b.get("kdtree-median")
        if not (e and k):
            continue
        verdict = lambda x, lo: f"{x:.2f} ({'met' if x >= lo else 'missed'})"
        hq = e.get("high_quality_build_seconds")
        build = f"{k['build_seconds'] / hq:.2f} ({'met' if k['build_seconds'] <= 5 * hq else 'missed'})" if hq else "—"
        cam = k["camera_mrays_per_second"] / e["camera_mrays_per_second"]
        occ = k["occlusion_mrays_per_second"] / e["occlusion_mrays_per_second"]
        mc = f"{k['camera_mrays_per_second'] / m['camera_mrays_per_second']:.2f}x" if m else "—"
        mo = f"{k['occlusion_mrays_per_second'] / m['occlusion_mrays_per_second']:.2f}x" if m else "—"
        lines.append(f"| {name} | {verdict(cam, 0.5)} | {verdict(occ, 0.4)} | {build} | {mc} | {mo} |")
    lines.append("")
    return lines


def scaling_points(whole, cut):
    """{backend: [(n, build s, source)]} over the subsamples and the whole meshes, by n."""
    points = {}
    for name, run in whole.items():
        for backend, b in run["backends"].items():
            points.setdefault(backend, []).append((run["triangles"], b["build_seconds"], name))
    for name, n, run in cut:
        for backend, b in run["backends"].items():
            points.setdefault(backend, []).append((run["triangles"], b["build_seconds"], f"{name} cut to {n:,}"))
    for p in points.values():
        p.sort()
    return points


def markdown(whole, cut):
    any_run = next(iter(whole.values()), None) or (cut[0][2] if cut else None)
    lines = [
        "# Acceleration structures: glint's backends compared",
        "",
        "Generated by `benchmarks/run_accel_benchmarks.sh` (`glint bench-accel`, then "
        "`benchmarks/accel_report.py`) on "
        f"{datetime.date.today().isoformat()}, {cpu_model()}"
        + (f", {any_run['threads']} threads" if any_run else "")
        + ". Do not edit: rerun the script.",
        "",
        "Protocol (benchmarks/README.md): camera on +Z of the bounding-box centre at r / tan(22.5°) "
        "(r = half the box diagonal), 45° vertical field of view, jittered samples from the "
        "Owen-scrambled Sobol sampler (seed 0); every backend traces the same stored camera rays "
        "one at a time (`closestHit`), then the same occlusion rays (`anyHit`): one per Embree "
        "camera hit, cosine-distributed about the geometric normal, tMax infinite. `camera s` is "
        "the time the camera rays take at that rate. Bytes and tree statistics are 0 where a "
        "backend does not expose them (Embree).",
        "",
        "## Per mesh",
        "",
    ]
    if not whole:
        lines += ["(no whole-mesh runs)", ""]
    for name in sorted(whole, key=mesh_key):
        lines += mesh_table(name, whole[name]) + [""]

    lines += targets(whole)
    lines += [
        "## Build-time scaling",
        "",
        "Build seconds over N log2 N (in nanoseconds): flat across N means an O(N log N) build.",
        "",
    ]
    points = scaling_points(whole, cut)
    if not points:
        lines += ["(no runs)", ""]
    for backend, pts in points.items():
        lines += [
            f"### {backend}",
            "",
            "| triangles N | from | build s | build / (N log2 N), ns |",
            "|---:|---|---:|---:|",
        ]
        for n, seconds, source in pts:
            lines.append(f"| {n:,} | {source} | {seconds:.3f} | {seconds / nlogn(n) * 1e9:.2f} |")
        lines.append("")

    lines += [
        "## 2008",
        "",
        "The competition's numbers from 2008, for scale only (another machine and another ray "
        "set): 800×600, 16 rays per pixel, in seconds.",
        "",
        "| structure | mesh | build s | render s |",
        "|---|---|---:|---:|",
    ]
    for structure, mesh, build, render in REFERENCE_2008:
        lines.append(f"| {structure} | {mesh} | {build} | {render} |")
    lines.append("")
    return "\n".join(lines)


def plot(whole, cut, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = sorted(whole, key=mesh_key)
    backends = []
    for name in names:
        for b in whole[name]["backends"]:
            if b not in backends:
                backends.append(b)
    fig, axes = plt.subplots(1, 4, figsize=(20, 4.8))
    width = 0.8 / max(1, len(backends))
    panels = [
        ("camera_mrays_per_second", "camera rays, Mrays/s", False),
        ("occlusion_mrays_per_second", "occlusion rays, Mrays/s", False),
        ("build_seconds", "build time, s", True),
    ]
    for ax, (key, title, log) in zip(axes, panels):
        for i, backend in enumerate(backends):
            xs = [j + (i - (len(backends) - 1) / 2) * width for j in range(len(names))]
            ys = [whole[n]["backends"].get(backend, {}).get(key, 0) for n in names]
            ax.bar(xs, ys, width, label=backend)
        if key == "camera_mrays_per_second" and names:
            bare = [whole[n]["bare_embree_camera_mrays_per_second"] for n in names]
            ax.scatter(range(len(names)), bare, marker="_", s=600, color="black", zorder=3,
                       label="bare rtcIntersect1")
        ax.set_xticks(range(len(names)))
        ax.set_xticklabels([f"{n}\n{whole[n]['triangles']:,} tri" for n in names], fontsize=8)
        ax.set_title(title)
        if log:
            ax.set_yscale("log")
        ax.legend(fontsize=8)
    ax = axes[3]
    for backend, pts in scaling_points(whole, cut).items():
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", label=backend)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("triangles")
    ax.set_title("build time, s, against mesh size")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path + ".tmp.png", dpi=100)
    os.replace(path + ".tmp.png", path)


def write_atomically(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results_dir")
    parser.add_argument("--markdown", required=True)
    parser.add_argument("--plot", required=True)
    args = parser.parse_args()
    whole, cut = load(args.results_dir)
    if not whole and not cut:
        sys.exit(f"accel_report: no JSON results in {args.results_dir}")
    write_atomically(args.markdown, markdown(whole, cut))
    print(f"accel_report: wrote {args.markdown}", file=sys.stderr)
    try:
        plot(whole, cut, args.plot)
    except ImportError:
        sys.exit("accel_report: matplotlib is missing (Debian: python3-matplotlib); no plot written")
    print(f"accel_report: wrote {args.plot}", file=sys.stderr)


if __name__ == "__main__":
    main()
