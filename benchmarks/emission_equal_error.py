#!/usr/bin/env python3
"""Two glint builds on one scene at equal error: MSE against a reference times CPU seconds.

For an estimator change (the track-length emission estimator of issue 52 was measured with it):
each build renders the scene at each spp level with two seeds, the builds alternated; the MSE
of each image against a converged reference EXR (e.g. cycles_vdb.py's 4,096-spp glint image),
the process's CPU seconds, the image mean against the reference's, and delta tracking's
tentative collisions (--stats). Prints each row and, per level, MSE x CPU for both builds.

  /usr/bin/python3 benchmarks/emission_equal_error.py --before OLD/glint --after NEW/glint \\
      --scene /tmp/cyc/fire.json --reference /tmp/cyc/fire_glint_ref.exr --python NEW/python
"""
import argparse
import json
import resource
import subprocess
import sys

import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--before", required=True)
    ap.add_argument("--after", required=True)
    ap.add_argument("--scene", required=True)
    ap.add_argument("--reference", required=True)
    ap.add_argument("--python", required=True, help="a build's python/ folder (glint.read)")
    ap.add_argument("--spp", type=int, nargs="+", default=[16, 64])
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--work", default="/tmp")
    args = ap.parse_args()
    sys.path.insert(0, args.python)
    import glint  # noqa: E402 (from the build named on the command line)

    ref = np.asarray(glint.read(args.reference).beauty, dtype=np.float64)
    builds = {"before": args.before, "after": args.after}
    rows = []
    for rnd in range(args.rounds):
        for spp in args.spp:
            order = ("before", "after") if rnd % 2 == 0 else ("after", "before")
            for name in order:
                out = f"{args.work}/eee_{name}_{spp}_{rnd}.exr"
                stats = out + ".stats.json"
                r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
                subprocess.run([builds[name], "render", args.scene, "-q", "--spp", str(spp),
                                "--seed", str(100 + rnd), "--threads", str(args.threads),
                                "-o", out, "--stats", stats], check=True)
                r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
                cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
                img = np.asarray(glint.read(out).beauty, dtype=np.float64)
                with open(stats) as f:
                    s = json.load(f)
                row = {"build": name, "spp": spp, "round": rnd,
                       "mse": float(((img - ref) ** 2).mean()), "cpu_seconds": cpu,
                       "render_seconds": s["render_seconds"],
                       "mean_vs_reference": float(img.mean() / ref.mean() - 1),
                       "tentative": s.get("tracking_collisions", {}).get("delta_tentative")}
                rows.append(row)
                print(json.dumps(row), flush=True)
    for spp in args.spp:
        for name in builds:
            rs = [r for r in rows if r["build"] == name and r["spp"] == spp]
            mse = np.mean([r["mse"] for r in rs])
            cpu = np.mean([r["cpu_seconds"] for r in rs])
            print(f"{name} {spp} spp: MSE {mse:.3g}, CPU {cpu:.3g} s, MSE x CPU {mse * cpu:.3g}")


if __name__ == "__main__":
    main()
