#!/usr/bin/env python3
"""glint through Slurm on this machine: how frames scale over concurrent tasks, and what each
task pays before it renders (process start, scene load, BVH build).

Brings up a one-node cluster (scripts/slurm/local-cluster; needs root and the packages
scripts/setup.sh installs), then renders the same frames with scripts/slurm/glint-submit in
four layouts, each into a folder of its own:

  serial       1 task at a time, 1 CPU (thread) each       --max-parallel 1 --cpus-per-task 1
  concurrent   2 tasks at a time, 1 CPU each               --cpus-per-task 1
  threaded     1 task at a time, 2 CPUs (threads) each     --cpus-per-task 2
  tiles        each frame as 2 tiles, 2 tasks at a time     --tiles 2 --cpus-per-task 1

For each: the wall clock from submission until the last job ended (tone mapping left out;
tiles include their assembly), and per task glint's own --stats (scene build, of which the
accelerator, and render seconds) and the task's wall clock in the job script (process start
and everything else included). Writes scaling.json and prints a table.

  benchmarks/slurm/scaling.py [--glint build/glint] [--scene scenes/snowy/snowy.json]
      [--frames 368-375] [--width 400] [--height 300] [--spp 4] [--out benchmarks/results/slurm]
"""
import argparse
import atexit
import glob
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
LAYOUTS = [
    ("serial", "1 task at a time, 1 thread", ["--max-parallel", "1", "--cpus-per-task", "1"]),
    ("concurrent", "2 tasks at a time, 1 thread each", ["--cpus-per-task", "1"]),
    ("threaded", "1 task at a time, 2 threads", ["--cpus-per-task", "2"]),
    ("tiles", "2 tiles a frame, 2 tasks at a time, 1 thread each",
     ["--tiles", "2", "--cpus-per-task", "1"]),
]


def wait_for(job_ids, env, timeout=3600):
    ids = ",".join(job_ids)
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        out = subprocess.run(["squeue", "-h", "-j", ids], env=env, capture_output=True,
                             text=True).stdout
        if not out.strip():
            return
        time.sleep(0.2)
    sys.exit(f"scaling: jobs {ids} did not finish within {timeout} s")


def job_states(job_id, env):
    out = subprocess.run(["scontrol", "-o", "show", "job", job_id], env=env,
                         capture_output=True, text=True).stdout
    return [w.split("=", 1)[1] for w in out.split() if w.startswith("JobState=")]


def task_records(out_dir):
    """Per task: glint's stats and the job script's wall clock."""
    records = []
    for stats_path in sorted(glob.glob(os.path.join(out_dir, "stats", "*.json"))):
        with open(stats_path) as f:
            stats = json.load(f)
        frame = stats["frames"][0]
        with open(stats_path[:-len(".json")] + ".wall") as f:
            start, end = (float(v) for v in f.read().split())
        records.append({
            "task": os.path.basename(stats_path)[:-len(".json")],
            "wall_seconds": end - start,
            "build_seconds": frame["build_seconds"],
            "accel_build_seconds": frame["accel_build_seconds"],
            "render_seconds": frame["render_seconds"],
            "start": start,
            "end": end,
        })
    return records


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--glint", default=os.path.join(ROOT, "build", "glint"))
    parser.add_argument("--scene", default=os.path.join(ROOT, "scenes", "snowy", "snowy.json"))
    parser.add_argument("--frames", default="368-375")
    parser.add_argument("--width", type=int, default=400)
    parser.add_argument("--height", type=int, default=300)
    parser.add_argument("--spp", type=int, default=4)
    parser.add_argument("--out", default=os.path.join(ROOT, "benchmarks", "results", "slurm"))
    parser.add_argument("--port", type=int, default=18817)
    args = parser.parse_args()

    work = tempfile.mkdtemp(prefix="glint-slurm-bench.")
    os.chmod(work, 0o755)  # munged runs as the munge user
    cluster = os.path.join(work, "cluster")
    local_cluster = os.path.join(ROOT, "scripts", "slurm", "local-cluster")
    subprocess.run([local_cluster, "start", cluster, "--port", str(args.port)], check=True,
                   stdout=subprocess.DEVNULL)

    def cleanup():
        subprocess.run([local_cluster, "stop", cluster])
        subprocess.run(["rm", "-rf", work])

    atexit.register(cleanup)
    env = dict(os.environ, SLURM_CONF=os.path.join(cluster, "slurm.conf"))

    render = ["--width", str(args.width), "--height", str(args.height), "--spp", str(args.spp)]
    results = {
        "scene": os.path.relpath(args.scene, ROOT),
        "frames": args.frames,
        "width": args.width,
        "height": args.height,
        "spp": args.spp,
        "cores": os.cpu_count(),
        "date": time.strftime("%Y-%m-%d"),
        "layouts": [],
    }
    for name, description, options in LAYOUTS:
        out_dir = os.path.join(work, name)
        start = time.monotonic()
        submitted = subprocess.run(
            [os.path.join(ROOT, "scripts", "slurm", "glint-submit"), args.scene,
             "--frames", args.frames, "--output", out_dir, "--mem", "2G", "--no-tonemap",
             "--glint", args.glint] + options + ["--"] + render,
            env=env, capture_output=True, text=True)
        if submitted.returncode != 0:
            sys.exit(f"scaling: glint-submit failed:\n{submitted.stderr}")
        jobs = [line.split()[1] for line in submitted.stdout.splitlines()]
        wait_for(jobs, env)
        wall = time.monotonic() - start
        for job in jobs:
            states = set(job_states(job, env))
            if states != {"COMPLETED"}:
                sys.exit(f"scaling: {name}: job {job} ended {states}; logs in {out_dir}/logs")
        tasks = task_records(out_dir)
        frames = len({t["task"].split(".")[0] for t in tasks})
        mean = lambda key: statistics.mean(t[key] for t in tasks)
        layout = {
            "layout": name,
            "description": description,
            "options": options,
            "tasks": len(tasks),
            "frames": frames,
            "wall_seconds": wall,
            "seconds_per_frame": wall / frames,
            # From the first task's start to the last task's end: the array itself, without
            # submission and scheduling before it or the assembly after it.
            "array_seconds": max(t["end"] for t in tasks) - min(t["start"] for t in tasks),
            "task_wall_seconds": mean("wall_seconds"),
            "task_build_seconds": mean("build_seconds"),
            "task_accel_build_seconds": mean("accel_build_seconds"),
            "task_render_seconds": mean("render_seconds"),
            # Everything a task spends outside the render: process start, scene load and build.
            "task_overhead_seconds": mean("wall_seconds") - mean("render_seconds"),
            "task_records": tasks,
        }
        results["layouts"].append(layout)
        print(f"{name:<11} {wall:7.1f} s wall, {wall / frames:6.2f} s/frame; per task "
              f"{layout['task_wall_seconds']:.2f} s: render {layout['task_render_seconds']:.2f} s, "
              f"build {layout['task_build_seconds']:.2f} s (BVH "
              f"{layout['task_accel_build_seconds']:.3f} s), overhead "
              f"{layout['task_overhead_seconds']:.2f} s", flush=True)

    serial = results["layouts"][0]["wall_seconds"]
    for layout in results["layouts"]:
        layout["speedup_over_serial"] = serial / layout["wall_seconds"]
    os.makedirs(args.out, exist_ok=True)
    path = os.path.join(args.out, "scaling.json")
    with open(path, "w") as f:
        json.dump(results, f, indent=2)
        f.write("\n")
    print(f"\n| layout | wall s | s/frame | speedup | task s | render s | build s | overhead s |")
    print("|---|---|---|---|---|---|---|---|")
    for l in results["layouts"]:
        print(f"| {l['description']} | {l['wall_seconds']:.1f} | {l['seconds_per_frame']:.2f} | "
              f"{l['speedup_over_serial']:.2f} | {l['task_wall_seconds']:.2f} | "
              f"{l['task_render_seconds']:.2f} | {l['task_build_seconds']:.2f} | "
              f"{l['task_overhead_seconds']:.2f} |")
    print(f"\nwrote {os.path.relpath(path)}")


if __name__ == "__main__":
    main()
