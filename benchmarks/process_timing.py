"""Timing whole glint processes for the benchmark scripts: wall time and peak resident memory
through /usr/bin/time, and min / median / max summaries."""
import statistics
import subprocess


def timed(cmd):
    """Wall seconds and peak resident MB of one run of cmd (a list); exits on failure."""
    out = subprocess.run(["/usr/bin/time", "-f", "%e %M"] + cmd, capture_output=True, text=True)
    if out.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{out.stderr}")
    wall, kb = out.stderr.strip().splitlines()[-1].split()
    return float(wall), int(kb) / 1024


def spread(values, unit, digits=2):
    """'min / median / max unit', or 'n/a' for no values."""
    if not values:
        return "n/a"
    f = f"{{:.{digits}f}}"
    return (f"{f.format(min(values))} / {f.format(statistics.median(values))} / "
            f"{f.format(max(values))} {unit}")
