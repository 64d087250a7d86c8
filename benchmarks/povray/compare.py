#!/usr/bin/env python3
"""glint against POV-Ray 3.7 on one scene: time to equal error (issue 27).

Usage: compare.py [--glint PATH] [--povray PATH] [--repeats 3] [--threads 2]
                  [--glint-spp 1,2,4,...] [--glint-ref-spp 1024] [--glint-filters LIST]
                  [--glint-antialias C,C,...] [--glint-antialias-spp 16]
                  [--glint-antialias-high C,C,...] [--glint-antialias-high-spp 32]
                  [--glint-subdivide D:C,D:C,...]
                  [--pov-configs LIST] [--pov-ref CONFIG] [--fresh-references]
                  [--work DIR] [--out-json FILE] [--out-svg FILE] [--out-png FILE]
                  [--quick] [--report] [--keep-images] [--no-install]

Run from anywhere. The scene is csg_compare.pov (POV-Ray) and csg_compare.json (its glint
translation), beside this script. glint renders it twice over, once per pixel filter
(--glint-filters): "gaussian", the scene as written (glint's default filter, a Gaussian of
radius 1.5 pixels), and "box", the same scene with a box filter of radius 0.5 (the pixel's
square: the integral POV-Ray's anti-aliasing estimates). For each renderer (and glint filter)
the script

  1. renders a converged reference once and caches it under --work (default
     build/povray_compare), keyed by a hash of the scene file, the settings and the renderer's
     binary: glint at --glint-ref-spp (default 1024) with a seed no sweep point uses;
     POV-Ray with --pov-ref (default am2:0.0:6:j, i.e. +AM2 +A0.0 +R6 +J: a 33x33 jittered
     grid per pixel, about 1,100 samples);
  2. renders its quality sweep --repeats times (default 3), every point once per round,
     the two renderers' points interleaved (the order reversed every other round), all with
     --threads (default 2: glint --threads 2, POV-Ray +WT2): glint at --glint-spp samples per
     pixel (seed = round) and with anti-aliasing by contrast (`--antialias C --spp CAP`, POV-
     Ray's rule: a pixel stops after 1, 2, 4, 8 or 16 samples unless its mean differs from a
     neighbour's by more than C) at each C of --glint-antialias (cap --glint-antialias-spp,
     default 16) and of --glint-antialias-high (cap --glint-antialias-high-spp, default 32),
     and with anti-aliasing by subdivision (`--subdivide D --antialias C`, POV-Ray's method
     2: shared corner looks, squares cut where their corners differ; box filter only, the
     integral it estimates) at each D:C of --glint-subdivide, POV-Ray at each of --pov-configs;
  3. for every render records the wall time of the process, the renderer's own time (glint:
     `--stats` render_seconds, plus load and BVH build; POV-Ray: its printed Parse, Bounding
     and Trace times), the CPU seconds of the child process and the load average, and the
     error of the image against its own renderer's reference: RMSE over the pixels and the
     linear R, G, B channels (and relMSE as a second opinion);
  4. takes each point's median time (and the min-max spread) and median error, and reports
     time to equal error: for each POV-Ray point, glint's time at that error, interpolated
     log-log along glint's curve (the lower-left front of its points), and the ratio
     POV-Ray time / glint time (> 1: glint is faster). With the renderers' own tracing
     times (glint render_seconds, POV-Ray Trace Time), the processes' CPU seconds and their
     wall times; for each glint series on its own: a filter's spp ladder, or its sweep over
     the contrast C at one cap (the contrast is the series' parameter, the mean spp glint
     reports is recorded with each point); and the best series per filter, plain or
     anti-aliased.

It writes --out-json (default benchmarks/results/povray_csg.json: every render, the medians,
the ratios, the machine, the versions, the commit and the command line), --out-svg (default
benchmarks/results/povray_csg.svg: error against time, log-log, both renderers; drawn by hand,
no matplotlib) and --out-png (default benchmarks/results/povray_csg_refs.png: the references
side by side at half size, sRGB: glint's, one per filter, then POV-Ray's), each through a
temporary file and a rename, and prints the tables. --report redraws the tables and the plot
from an existing --out-json without rendering. --quick is a smoke test: 160x120, few points,
low references, one round, outputs under --work.

Images are read by a small OpenEXR reader in this file (scanline, NONE/ZIPS/ZIP compression,
HALF/FLOAT channels: what both renderers write), with numpy when the interpreter has it
(Debian's python3-numpy; /usr/bin/python3 here), else in pure Python (slower, same numbers).
POV-Ray's OpenEXR output is linear (assumed_gamma 1.0 in the scene) and half-float.

POV-Ray is Debian's `povray` package (3.7.0.10); when it is not on PATH and --povray is not
given, the script installs it with apt-get (it says so first; --no-install stops instead).
"""
import argparse
import array
import datetime
import hashlib
import json
import math
import os
import platform
import re
import resource
import shutil
import statistics
import struct
import subprocess
import sys
import tempfile
import time
import zlib
from itertools import accumulate

try:
    import numpy as np
except ImportError:  # the pure-Python paths below do the same arithmetic
    np = None

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
POV_SCENE = os.path.join(HERE, "csg_compare.pov")
GLINT_SCENE = os.path.join(HERE, "csg_compare.json")
RESULTS = os.path.join(ROOT, "benchmarks", "results")

DEFAULT_GLINT_SPP = [1, 2, 4, 8, 16, 32, 64]
# glint's pixel filters: "gaussian" is the scene as written (glint's default filter, a Gaussian
# of radius 1.5 pixels); "box" is the same scene with render.filter = box of radius 0.5, the
# pixel's own square: the integral POV-Ray's anti-aliasing estimates.
GLINT_FILTERS = {"gaussian": None, "box": {"type": "box", "radius": 0.5}}
GLINT_COLOURS = {"gaussian": "#1f77b4", "box": "#2ca02c"}
# glint's anti-aliasing by contrast (--antialias C, POV-Ray's rule: after 1, 2, 4, 8 and 16
# samples a pixel stops unless its mean differs from a neighbour's by more than C; --spp caps
# it): a sweep over C per filter and per cap, each (filter, cap) its own series. A pixel's first
# look goes through its centre, so C = 1 (no pixel ever differs by more) is POV-Ray's one ray
# per pixel without anti-aliasing. The second cap lets the thresholds reach the errors of
# POV-Ray's deepest settings; its larger C fill the gap between the two caps (where POV-Ray's
# depth-4 settings are). Cap 32 rather than 64 (until 2026-11-27): at POV-Ray's depth-4 errors
# (0.0021-0.0025) it was 1.3-1.7x faster than cap 64, and C = 0.02 still reaches 0.0017.
DEFAULT_GLINT_ANTIALIAS = [1, 0.3, 0.1, 0.05, 0.02, 0.01, 0.005]
DEFAULT_GLINT_ANTIALIAS_SPP = 16
DEFAULT_GLINT_ANTIALIAS_HIGH = [0.3, 0.1, 0.05, 0.02, 0.01, 0.005]
DEFAULT_GLINT_ANTIALIAS_HIGH_SPP = 32
# (filter, cap) -> colour of an anti-aliased series; plain ladders use GLINT_COLOURS.
GLINT_AA_COLOURS = {("gaussian", 16): "#9467bd", ("gaussian", 32): "#17becf",
                    ("gaussian", 64): "#17becf", ("box", 16): "#bcbd22",
                    ("box", 32): "#8c564b", ("box", 64): "#8c564b"}
# glint's anti-aliasing by recursive subdivision (--subdivide D --antialias C, POV-Ray's method
# 2 with jittered looks, glint's --jitter default): (depth, contrast) points, one series per
# depth. It estimates the pixel's box integral, so it is judged against the box reference only.
# Depth D is POV-Ray's +R(D+1).
DEFAULT_GLINT_SUBDIVIDE = ["2:0.3", "2:0.1", "2:0.05", "2:0.02", "3:0.3", "3:0.1", "3:0.05",
                           "3:0.03", "3:0.02", "3:0.01", "4:0.1", "4:0.05", "4:0.03", "4:0.02"]
GLINT_SUB_COLOURS = {2: "#98df8a", 3: "#d62fd6", 4: "#393b79", 5: "#637939"}
GLINT_REF_SEED = 1000  # the sweep uses seeds 1..repeats: the reference shares no samples
# POV-Ray configurations: "none" (no anti-aliasing: one ray through each pixel centre) or
# "amM:THRESHOLD:DEPTH[:j]": +AM<M> +A<THRESHOLD> +R<DEPTH> [+J]. Method 1 supersamples a pixel
# whose colour differs from a neighbour's by more than the threshold with a DEPTH x DEPTH grid
# (POV-Ray's default method, depth 3); method 2 subdivides adaptively, up to a
# (2^(DEPTH-1)+1)^2 grid of pixel-corner samples shared with the neighbours.
DEFAULT_POV_CONFIGS = (
    ["none"]
    + [f"am1:{a}:3" for a in ("0.3", "0.1", "0.03", "0.0")]
    + [f"am1:0.0:{r}" for r in (2, 4, 5)]
    + [f"am2:{a}:{r}" for r in (2, 3, 4) for a in ("0.3", "0.1", "0.03", "0.0")]
    + ["am1:0.0:3:j", "am2:0.0:3:j"]
    # POV-Ray's own defaults jitter (+J1.0 unless -J): its jittered method 2 at depths 3 and 4
    # reaches a lower error than the same setting unjittered, at the same time.
    + ["am1:0.3:3:j", "am2:0.3:3:j", "am2:0.1:3:j", "am2:0.3:4:j", "am2:0.1:4:j",
       "am2:0.03:4:j"]
)
DEFAULT_POV_REF = "am2:0.0:6:j"

QUICK = {
    "width": 160, "height": 120,
    "glint_spp": [1, 4, 16], "glint_ref_spp": 256,
    "glint_antialias": [0.05, 0.01], "glint_antialias_high": [0.01],
    "glint_subdivide": ["2:0.1", "3:0.05"],
    "pov_configs": ["none", "am1:0.3:3", "am1:0.0:3", "am2:0.0:3"],
    "pov_ref": "am2:0.0:5:j",
    "repeats": 1,
}


def log(msg):
    print(msg, file=sys.stderr, flush=True)


# ---------------------------------------------------------------------------------------------
# OpenEXR reading (scanline images, NONE / ZIPS / ZIP, HALF / FLOAT)
# ---------------------------------------------------------------------------------------------

_COMPRESSION = {0: ("none", 1), 2: ("zips", 1), 3: ("zip", 16)}
_PIXEL_SIZE = {1: 2, 2: 4}  # HALF, FLOAT (UINT, 0, is not read)
_PREDICTOR = bytes((b - 128) & 255 for b in range(256))


def _undo_zip(raw):
    """OpenEXR's ZIP/ZIPS filter after inflating: undo the byte predictor, then interleave."""
    n = len(raw)
    if n == 0:
        return b""
    if np is not None:
        t = np.frombuffer(raw, dtype=np.uint8).copy()
        t[1:] -= 128  # wraps modulo 256, as the format's predictor does
        t = np.cumsum(t, dtype=np.uint8)
        out = np.empty(n, dtype=np.uint8)
        half = (n + 1) // 2
        out[0::2] = t[:half]
        out[1::2] = t[half:]
        return out.tobytes()
    t = bytearray(raw[:1]) + raw[1:].translate(_PREDICTOR)
    t = bytes(map((255).__and__, accumulate(t)))
    out = bytearray(n)
    half = (n + 1) // 2
    out[0::2] = t[:half]
    out[1::2] = t[half:]
    return bytes(out)


def read_exr(path, wanted=("R", "G", "B")):
    """Returns (width, height, [channel arrays]) for the wanted channels, row-major floats
    (numpy float64 arrays, or array('d') without numpy)."""
    with open(path, "rb") as f:
        data = f.read()
    if struct.unpack_from("<I", data, 0)[0] != 20000630:
        raise ValueError(f"{path}: not an OpenEXR file")
    version = struct.unpack_from("<I", data, 4)[0]
    if version & 0x1A00:  # tiled, deep or multi-part
        raise ValueError(f"{path}: only single-part scanline OpenEXR files are read here")
    pos = 8
    channels, compression, window = [], None, None
    while data[pos] != 0:
        end = data.index(b"\0", pos)
        name = data[pos:end].decode()
        end2 = data.index(b"\0", end + 1)
        kind = data[end + 1:end2].decode()
        size = struct.unpack_from("<i", data, end2 + 1)[0]
        value = data[end2 + 5:end2 + 5 + size]
        pos = end2 + 5 + size
        if name == "channels" and kind == "chlist":
            p = 0
            while value[p] != 0:
                e = value.index(b"\0", p)
                cname = value[p:e].decode()
                ptype, _linear, xs, ys = struct.unpack_from("<iB3xii", value, e + 1)
                if xs != 1 or ys != 1:
                    raise ValueError(f"{path}: subsampled channel {cname}")
                channels.append((cname, ptype))
                p = e + 1 + 16
        elif name == "compression":
            compression = value[0]
        elif name == "dataWindow":
            window = struct.unpack("<iiii", value)
    pos += 1
    if compression not in _COMPRESSION:
        raise ValueError(f"{path}: compression {compression} is not read here "
                         "(NONE, ZIPS and ZIP are)")
    if any(t not in _PIXEL_SIZE for _, t in channels):
        raise ValueError(f"{path}: UINT channels are not read here")
    xmin, ymin, xmax, ymax = window
    width, height = xmax - xmin + 1, ymax - ymin + 1
    lines = _COMPRESSION[compression][1]
    chunks = (height + lines - 1) // lines
    offsets = struct.unpack_from(f"<{chunks}Q", data, pos)
    index = {name: i for i, (name, _) in enumerate(channels)}
    missing = [c for c in wanted if c not in index]
    if missing:
        raise ValueError(f"{path}: no channel {missing[0]}")
    line_bytes = sum(width * _PIXEL_SIZE[t] for _, t in channels)
    parts = {c: [None] * height for c in wanted}
    for off in offsets:
        y, size = struct.unpack_from("<ii", data, off)
        block = data[off + 8:off + 8 + size]
        n_lines = min(lines, ymax + 1 - y)
        if compression != 0 and size < n_lines * line_bytes:
            block = _undo_zip(zlib.decompress(block))
        p = 0
        for row in range(y - ymin, y - ymin + n_lines):
            for name, ptype in channels:
                nbytes = width * _PIXEL_SIZE[ptype]
                if name in parts:
                    parts[name][row] = (ptype, block[p:p + nbytes])
                p += nbytes
    result = []
    for c in wanted:
        ptype = parts[c][0][0]
        buf = b"".join(b for _, b in parts[c])
        if np is not None:
            result.append(np.frombuffer(buf, dtype="<f2" if ptype == 1 else "<f4")
                          .astype(np.float64))
        elif ptype == 1:
            result.append(array.array("d", struct.unpack(f"<{len(buf) // 2}e", buf)))
        else:
            a = array.array("f")
            a.frombytes(buf)
            if sys.byteorder != "little":
                a.byteswap()
            result.append(array.array("d", a))
    return width, height, result


def image_errors(img, ref):
    """RMSE over pixels and the R, G, B channels, relMSE = mean (a-b)^2 / (b^2 + 0.01), and the
    mean of each image (a bias check)."""
    (wa, ha, a), (wb, hb, b) = img, ref
    if (wa, ha) != (wb, hb):
        raise ValueError(f"image sizes differ: {wa}x{ha} against {wb}x{hb}")
    n = 3 * wa * ha
    if np is not None:
        A, B = np.stack(a), np.stack(b)
        d2 = (A - B) ** 2
        return {"rmse": float(math.sqrt(d2.sum() / n)),
                "relmse": float((d2 / (B * B + 0.01)).sum() / n),
                "mean": float(A.sum() / n), "ref_mean": float(B.sum() / n)}
    se = rel = sa = sb = 0.0
    for ca, cb in zip(a, b):
        for x, y in zip(ca, cb):
            d = (x - y) * (x - y)
            se += d
            rel += d / (y * y + 0.01)
            sa += x
            sb += y
    return {"rmse": math.sqrt(se / n), "relmse": rel / n, "mean": sa / n, "ref_mean": sb / n}


# ---------------------------------------------------------------------------------------------
# PNG writing (the references side by side)
# ---------------------------------------------------------------------------------------------

def _srgb8(v):
    v = min(max(v, 0.0), 1.0)
    v = 12.92 * v if v <= 0.0031308 else 1.055 * v ** (1 / 2.4) - 0.055
    return int(v * 255 + 0.5)


def side_by_side_png(images, path, gap=8):
    """images: [(w, h, [R, G, B])], all the same size; each is halved (2x2 box), encoded to
    sRGB (clamped to [0, 1]) and placed left to right on a white strip."""
    w, h = images[0][0], images[0][1]
    hw, hh = w // 2, h // 2
    table = [_srgb8(i / 4095) for i in range(4096)]
    halves = []
    for _, _, chans in images:
        planes = []
        for c in chans:
            if np is not None:
                m = np.asarray(c).reshape(h, w)[:2 * hh, :2 * hw]
                m = 0.25 * (m[0::2, 0::2] + m[1::2, 0::2] + m[0::2, 1::2] + m[1::2, 1::2])
                q = np.clip(np.rint(m * 4095), 0, 4095).astype(np.int64)
                planes.append(np.asarray(table, dtype=np.uint8)[q])
            else:
                rows = []
                for y in range(hh):
                    r0, r1 = (2 * y) * w, (2 * y + 1) * w
                    rows.append([table[min(max(int(0.25 * (c[r0 + 2 * x] + c[r0 + 2 * x + 1]
                                                              + c[r1 + 2 * x] + c[r1 + 2 * x + 1])
                                                       * 4095 + 0.5), 0), 4095)]
                                 for x in range(hw)])
                planes.append(rows)
        halves.append(planes)
    total_w = len(images) * hw + (len(images) - 1) * gap
    raw = bytearray()
    for y in range(hh):
        raw.append(0)
        for k, planes in enumerate(halves):
            if k:
                raw += b"\xff" * (3 * gap)
            if np is not None:
                raw += np.stack([p[y] for p in planes], axis=1).astype(np.uint8).tobytes()
            else:
                raw += bytes(v for x in range(hw) for v in (planes[0][y][x], planes[1][y][x],
                                                            planes[2][y][x]))

    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body
                + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF))

    header = struct.pack(">IIBBBBB", total_w, hh, 8, 2, 0, 0, 0)  # 8-bit RGB
    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
           + chunk(b"IDAT", zlib.compress(bytes(raw), 9)) + chunk(b"IEND", b""))
    write_atomic(path, png)


# ---------------------------------------------------------------------------------------------
# Files, machine, versions
# ---------------------------------------------------------------------------------------------

def write_atomic(path, content):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(os.path.abspath(path)),
                               prefix="." + os.path.basename(path), suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(content.encode() if isinstance(content, str) else content)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes 0600; give the file a plain file's mode
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def sha256_file(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def cpu_model():
    """The CPU's model name: accel_report.py's (one reader of /proc/cpuinfo for the benchmarks),
    else what Python's platform module says."""
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    try:
        from accel_report import cpu_model as read_cpu_model
    finally:
        sys.path.pop(0)
    name = read_cpu_model()
    return name if name != "unknown CPU" else (platform.processor() or name)


def git_commit():
    try:
        rev = subprocess.run(["git", "-C", ROOT, "rev-parse", "HEAD"], capture_output=True,
                             text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", ROOT, "status", "--porcelain"], capture_output=True,
                               text=True, check=True).stdout.strip()
        return rev + ("+dirty" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return None


def machine():
    return {"cpu": cpu_model(), "logical_cpus": os.cpu_count(), "kernel": platform.release(),
            "python": platform.python_version(), "numpy": np.__version__ if np else None,
            "hostname": platform.node()}


def ensure_povray(args):
    if args.povray:
        return args.povray
    found = shutil.which("povray")
    if found:
        return found
    if args.no_install:
        sys.exit("povray is not on PATH (Debian: apt-get install povray); --no-install given")
    log("povray is not on PATH: installing Debian's povray package with apt-get "
        "(the benchmark's own dependency; CI does not install it)")
    apt = ["apt-get", "install", "-y", "povray"]
    if os.geteuid() != 0:
        if not shutil.which("sudo"):
            sys.exit("povray is missing and this is not root: run `apt-get install povray`")
        apt = ["sudo"] + apt
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    if subprocess.run(apt, env=env).returncode != 0:
        log("apt-get install failed; trying apt-get update first")
        subprocess.run(apt[:-3] + ["update"], env=env, check=True)
        subprocess.run(apt, env=env, check=True)
    found = shutil.which("povray")
    if not found:
        sys.exit("povray is still not on PATH after apt-get install")
    return found


def povray_version(povray):
    r = subprocess.run([povray, "--version"], capture_output=True, text=True)
    for line in (r.stdout + r.stderr).splitlines():
        if line.startswith("POV-Ray "):
            return line.strip()
    return "unknown"


def glint_version(glint):
    return subprocess.run([glint, "--version"], capture_output=True, text=True).stdout.strip()


# ---------------------------------------------------------------------------------------------
# Rendering
# ---------------------------------------------------------------------------------------------

def parse_pov_config(text):
    """'none' or 'amM:A:R[:j]' -> dict with the command-line options."""
    if text == "none":
        return {"name": "none", "label": "no AA", "options": ["-A"], "method": 0}
    parts = text.split(":")
    if len(parts) not in (3, 4) or not re.fullmatch(r"am[12]", parts[0]) or \
            (len(parts) == 4 and parts[3] != "j"):
        raise ValueError(f"POV-Ray config '{text}': expected none or amM:THRESHOLD:DEPTH[:j]")
    method, threshold, depth = int(parts[0][2]), float(parts[1]), int(parts[2])
    jitter = len(parts) == 4
    opts = [f"+AM{method}", f"+A{parts[1]}", f"+R{depth}"] + (["+J1.0"] if jitter else ["-J"])
    label = f"AM{method} A{parts[1]} R{depth}" + (" J" if jitter else "")
    return {"name": text, "label": label, "options": opts, "method": method,
            "threshold": threshold, "depth": depth, "jitter": jitter}


def _child_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def _pov_seconds(text, label):
    m = re.search(label + r" Time:.*?\(([\d.]+) seconds\)", text)
    return float(m.group(1)) if m else None


def render_povray(ctx, config, out_path):
    """One POV-Ray render; returns the record (times, statistics)."""
    out_dir = os.path.dirname(out_path)
    cmd = [ctx["povray"], "-D", "-P", f"+I{POV_SCENE}", f"+O{os.path.basename(out_path)}",
           "+FE", f"+W{ctx['width']}", f"+H{ctx['height']}", f"+WT{ctx['threads']}"] + \
        config["options"]
    load = os.getloadavg()
    cpu0, t0 = _child_cpu(), time.perf_counter()
    # POV-Ray's I/O restrictions let it write only below its working directory.
    r = subprocess.run(cmd, cwd=out_dir, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    cpu = _child_cpu() - cpu0
    text = r.stdout + r.stderr
    if r.returncode != 0 or not os.path.exists(out_path):
        raise RuntimeError(f"povray failed ({r.returncode}): {' '.join(cmd)}\n{text[-3000:]}")
    trace = _pov_seconds(text, "Trace")
    parse = _pov_seconds(text, "Parse") or 0.0
    bounding = _pov_seconds(text, "Bounding") or 0.0
    if trace is None:
        raise RuntimeError(f"no 'Trace Time' in POV-Ray's output:\n{text[-3000:]}")
    stats = {}
    for key, pattern in (("samples", r"Samples:\s+(\d+)"), ("samples_per_pixel",
                                                           r"Smpls/Pxl:\s+([\d.]+)"),
                         ("rays", r"Rays:\s+(\d+)"), ("shadow_rays", r"Shadow Ray Tests:\s+(\d+)"),
                         ("reflected_rays", r"Reflected Rays:\s+(\d+)"),
                         ("refracted_rays", r"Refracted Rays:\s+(\d+)")):
        m = re.search(pattern, text)
        if m:
            stats[key] = float(m.group(1)) if "." in m.group(1) else int(m.group(1))
    m = re.search(r"Trace Time:.*?\n\s*using (\d+) thread\(s\) with ([\d.]+) CPU-seconds", text)
    if m:
        stats["trace_threads"], stats["trace_cpu_seconds"] = int(m.group(1)), float(m.group(2))
    rays = stats.get("rays", 0) + stats.get("shadow_rays", 0)
    return {"wall_seconds": wall, "trace_seconds": trace, "parse_seconds": parse,
            "bounding_seconds": bounding, "own_seconds": parse + bounding + trace,
            "cpu_seconds": cpu, "load_average": load,
            "mrays_per_second": rays / trace / 1e6 if trace > 0 else None, "stats": stats}


def glint_scene(ctx, filt):
    """The glint scene for a pixel filter: the file itself, or a copy with render.filter set
    (written under --work; the scene names no other files)."""
    if GLINT_FILTERS[filt] is None:
        return GLINT_SCENE
    with open(GLINT_SCENE) as f:
        scene = json.load(f)
    scene["render"]["filter"] = GLINT_FILTERS[filt]
    path = os.path.join(ctx["work"], "scenes", f"csg_compare_{filt}.json")
    text = json.dumps(scene, indent=1) + "\n"
    if not os.path.exists(path) or open(path).read() != text:
        write_atomic(path, text)
    return path


def render_glint(ctx, scene, spp, seed, out_path, antialias=0.0, subdivide=0):
    """One glint render: spp samples in every pixel, or with antialias > 0 anti-aliasing by
    contrast (--antialias) with spp the most a pixel takes, or with subdivide > 0 anti-aliasing
    by subdivision (--subdivide) at contrast antialias."""
    stats_path = out_path[:-4] + ".stats.json"
    cmd = [ctx["glint"], "render", scene, "-q", "-o", out_path, "--stats", stats_path,
           "--spp", str(spp), "--seed", str(seed), "--threads", str(ctx["threads"]),
           "--width", str(ctx["width"]), "--height", str(ctx["height"]),
           "--integrator", "whitted"]
    if antialias or subdivide:
        cmd += ["--antialias", f"{antialias:g}"]
    if subdivide:
        cmd += ["--subdivide", str(subdivide)]
    load = os.getloadavg()
    cpu0, t0 = _child_cpu(), time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    cpu = _child_cpu() - cpu0
    if r.returncode != 0:
        raise RuntimeError(f"glint failed ({r.returncode}): {' '.join(cmd)}\n"
                           f"{(r.stdout + r.stderr)[-3000:]}")
    with open(stats_path) as f:
        st = json.load(f)
    os.unlink(stats_path)
    return {"wall_seconds": wall, "trace_seconds": st["render_seconds"],
            "load_seconds": st.get("load_seconds"), "build_seconds": st.get("build_seconds"),
            "own_seconds": (st.get("load_seconds") or 0) + (st.get("build_seconds") or 0)
            + st["render_seconds"],
            "cpu_seconds": cpu, "load_average": load,
            "mrays_per_second": st.get("mrays_per_second"),
            "stats": {"rays": st.get("rays"), "spp_reached": st.get("spp_reached"),
                      "mean_spp": st.get("mean_spp"), "antialias": antialias or None,
                      "subdivide": subdivide or None,
                      "integrator": st.get("integrator"), "threads": st.get("threads")}}


def reference(ctx, renderer, args, filt=None):
    """Renders (or finds in the cache) one renderer's converged reference; returns its record."""
    if renderer == "glint":
        settings = {"spp": ctx["glint_ref_spp"], "seed": GLINT_REF_SEED, "filter": filt}
        scene, binary = glint_scene(ctx, filt), ctx["glint"]
    else:
        settings = {"config": ctx["pov_ref"]}
        scene, binary = POV_SCENE, ctx["povray"]
    key_src = json.dumps({"renderer": renderer, "scene": sha256_file(scene),
                          "binary": sha256_file(binary), "width": ctx["width"],
                          "height": ctx["height"], **settings}, sort_keys=True)
    key = hashlib.sha256(key_src.encode()).hexdigest()[:16]
    ref_dir = os.path.join(ctx["work"], "references")
    os.makedirs(ref_dir, exist_ok=True)
    name = renderer if filt is None else f"{renderer}_{filt}"
    path = os.path.join(ref_dir, f"{name}_{key}.exr")
    meta_path = path[:-4] + ".json"
    if not args.fresh_references and os.path.exists(path) and os.path.exists(meta_path):
        with open(meta_path) as f:
            meta = json.load(f)
        log(f"{name} reference: cached {os.path.relpath(path, ROOT)}")
        meta["cached"] = True
        return meta
    log(f"{name} reference: rendering ({settings}); this takes minutes, once")
    tmp = os.path.join(ref_dir, f".{name}_{key}.exr")
    if renderer == "glint":
        rec = render_glint(ctx, scene, settings["spp"], settings["seed"], tmp)
    else:
        rec = render_povray(ctx, parse_pov_config(settings["config"]), tmp)
    os.replace(tmp, path)
    meta = {"renderer": renderer, "path": os.path.relpath(path, ROOT), "key": key,
            "settings": settings, "render": rec,
            "date": datetime.datetime.now().isoformat(timespec="seconds"), "cached": False}
    write_atomic(meta_path, json.dumps(meta, indent=2) + "\n")
    log(f"{name} reference: {rec['trace_seconds']:.1f} s tracing, "
        f"{rec['wall_seconds']:.1f} s wall")
    return meta


# ---------------------------------------------------------------------------------------------
# Curves, interpolation, ratios
# ---------------------------------------------------------------------------------------------

def front(points, time_key):
    """The lower-left front of points (each a dict with the median time and error): sorted by
    time, each point kept only when its error is below every faster point's."""
    best, out = math.inf, []
    for p in sorted(points, key=lambda p: p[time_key]):
        if p["rmse"] < best:
            out.append(p)
            best = p["rmse"]
    return out


def time_at_error(curve, time_key, error):
    """Time along a front at this error, log-log interpolated between the neighbouring points.
    Returns (seconds, how): how is 'interpolated', or 'faster' when even the curve's cheapest
    point has less error (the time is then an upper bound), or 'beyond' when the curve never
    gets this low (the time is its last point's: a lower bound)."""
    if error >= curve[0]["rmse"]:
        return curve[0][time_key], "faster" if error > curve[0]["rmse"] else "interpolated"
    for a, b in zip(curve, curve[1:]):
        if a["rmse"] >= error >= b["rmse"]:
            f = math.log(a["rmse"] / error) / math.log(a["rmse"] / b["rmse"])
            return math.exp(math.log(a[time_key]) + f * math.log(b[time_key] / a[time_key])), \
                "interpolated"
    return curve[-1][time_key], "beyond"


def summarize(records):
    """Median (and min, max) of each time and of the error over the repeats."""
    out = {}
    for key in ("wall_seconds", "trace_seconds", "own_seconds", "cpu_seconds"):
        vals = [r[key] for r in records if r.get(key) is not None]
        if vals:
            out[key] = statistics.median(vals)
            out[key + "_min"], out[key + "_max"] = min(vals), max(vals)
    for key in ("rmse", "relmse", "mean"):
        vals = [r["error"][key] for r in records]
        out[key] = statistics.median(vals)
        out[key + "_min"], out[key + "_max"] = min(vals), max(vals)
    rates = [r["mrays_per_second"] for r in records if r.get("mrays_per_second")]
    out["mrays_per_second"] = statistics.median(rates) if rates else None
    return out


def glint_label(f, spp, contrast, subdivide=0):
    if subdivide:
        return f"{f} sub{subdivide} {contrast:g}"
    return f"{f} {spp} spp" if not contrast else f"{f} AA {contrast:g} ≤{spp}"


def glint_filters(glint_points):
    return list(dict.fromkeys(p["filter"] for p in glint_points))


def series_of(p):
    """A glint point's series: its filter for the plain spp ladder (as in JSON written before
    the anti-aliased series existed), "FILTER aaCAP" for anti-aliasing by contrast with the
    cap CAP (the point's spp)."""
    if p.get("series"):
        return p["series"]
    return p["filter"] if not p.get("antialias") else f"{p['filter']} aa{p['spp']}"


def glint_series(glint_points):
    """The series in order: per filter, the plain ladder, then the anti-aliased ones by cap."""
    seen = {}
    for p in glint_points:
        seen.setdefault(series_of(p), p)
    order = {f: i for i, f in enumerate(glint_filters(glint_points))}
    return sorted(seen, key=lambda s: (order[seen[s]["filter"]], bool(seen[s].get("subdivide")),
                                       seen[s].get("subdivide") or
                                       (seen[s]["spp"] if seen[s].get("antialias") else 0)))


def series_info(glint_points, s):
    """kind: plain (the spp ladder), antialias (contrast at cap `cap`) or subdivide (contrast
    at depth `depth`)."""
    p = next(q for q in glint_points if series_of(q) == s)
    depth = p.get("subdivide") or None
    cap = p["spp"] if p.get("antialias") and not depth else None
    if depth:
        return {"filter": p["filter"], "cap": None, "depth": depth, "kind": "subdivide",
                "label": f"{p['filter']} sub{depth}",
                "colour": GLINT_SUB_COLOURS.get(depth, "#e377c2")}
    return {"filter": p["filter"], "cap": cap, "depth": None,
            "kind": "plain" if cap is None else "antialias",
            "label": p["filter"] if cap is None else f"{p['filter']} AA≤{cap}",
            "colour": (GLINT_COLOURS.get(p["filter"], "#17becf") if cap is None else
                       GLINT_AA_COLOURS.get((p["filter"], cap), "#e377c2"))}


# The three times compared: the renderer's own tracing time, the CPU seconds of the process
# (user + system of both threads: less sensitive than the clocks to a machine shared with other
# work, which takes CPU from one renderer more than from the other), and the process's wall time.
TIME_KINDS = (("trace_seconds", "trace"), ("cpu_seconds", "cpu"), ("wall_seconds", "wall"))


def equal_error(glint_points, pov_points):
    """For each POV-Ray point and each glint series (a filter's plain spp ladder, or its sweep
    over anti-aliasing contrasts at one cap): glint's time at the POV-Ray point's error and the
    ratio, with each kind of time. row["best"]["FILTER plain" / "FILTER antialias"]: for each
    kind of time, the series with the highest ratio (interpolated within a series, never
    between two)."""
    rows = []
    series = glint_series(glint_points)
    fronts = {(s, k): front([p for p in glint_points if series_of(p) == s], k)
              for s in series for k, _ in TIME_KINDS}
    pov_front = {p["config"] for p in front(pov_points, "trace_seconds")}
    for p in pov_points:
        row = {"config": p["config"], "label": p["label"], "rmse": p["rmse"],
               "pov_on_front": p["config"] in pov_front, "glint": {}}
        for k, short in TIME_KINDS:
            row[f"pov_{short}_seconds"] = p[k]
        for f in series:
            g = row["glint"][f] = {}
            for k, short in TIME_KINDS:
                t, how = time_at_error(fronts[(f, k)], k, p["rmse"])
                g[f"{short}_seconds"] = t
                g[f"ratio_{short}"] = p[k] / t
                # 'faster': glint's cheapest point already beats this error, so the ratio is a
                # lower bound; 'beyond': glint's dearest point does not reach it: an upper bound.
                g[f"ratio_{short}_bound"] = {"interpolated": "=", "faster": ">=",
                                             "beyond": "<="}[how]
        row["best"] = {}
        for f in series:
            info = series_info(glint_points, f)
            group = f"{info['filter']} {info['kind']}"
            b = row["best"].setdefault(group, {})
            for _, short in TIME_KINDS:
                r = row["glint"][f][f"ratio_{short}"]
                bound = row["glint"][f][f"ratio_{short}_bound"]
                # An upper bound (the series never reaches the error) loses to any value or
                # lower bound, whatever its number.
                if short not in b or (bound != "<=", r) > (b[short]["bound"] != "<=",
                                                           b[short]["ratio"]):
                    b[short] = {"series": f, "ratio": r, "bound": bound,
                                "glint_seconds": row["glint"][f][f"{short}_seconds"]}
        rows.append(row)
    return rows


# ---------------------------------------------------------------------------------------------
# Reporting: tables and the SVG plot
# ---------------------------------------------------------------------------------------------

def fmt_ratio(x, bound):
    return ("" if bound == "=" else ("≥" if bound == ">=" else "≤")) + f"{x:.2f}"


def tables(res):
    lines = []
    ctx = res["settings"]
    filters = glint_filters(res["glint"])
    refs = res["references"]
    lines.append(f"glint: {res['versions']['glint']}, POV-Ray: {res['versions']['povray']}; "
                 f"{ctx['width']}x{ctx['height']}, {ctx['threads']} threads, "
                 f"{ctx['repeats']} round(s); times are medians [min-max]; "
                 f"1-min load {res['load_average_range'][0]:.1f}-"
                 f"{res['load_average_range'][1]:.1f}")
    lines.append("references: " + ", ".join(
        f"glint {f} {refs['glint:' + f]['settings']['spp']} spp "
        f"({refs['glint:' + f]['render']['trace_seconds']:.1f} s tracing)" for f in filters)
        + ", POV-Ray {} ({:.1f} s tracing)".format(
            parse_pov_config(refs["povray"]["settings"]["config"])["label"],
            refs["povray"]["render"]["trace_seconds"]))
    series = glint_series(res["glint"])
    infos = {sr: series_info(res["glint"], sr) for sr in series}
    lines.append("")
    lines.append(f"{'glint':<24} {'trace s':>20} {'cpu s':>7} {'wall s':>20} {'RMSE':>9} "
                 f"{'mean spp':>8} {'Mrays/s':>8}")
    for sr in series:
        pts = [p for p in res["glint"] if series_of(p) == sr]
        pts.sort(key=lambda p: (p["spp"], -(p.get("antialias") or 0)))
        for p in pts:
            lines.append(f"{p['label']:<24} {_span(p, 'trace_seconds'):>20} "
                         f"{p['cpu_seconds']:7.2f} {_span(p, 'wall_seconds'):>20} "
                         f"{p['rmse']:9.5f} {p.get('mean_spp') or p['spp']:8.2f} "
                         f"{(p['mrays_per_second'] or 0):8.2f}")
    lines.append("")
    head = (f"{'POV-Ray':<16} {'trace s':>20} {'cpu s':>7} {'wall s':>20} {'RMSE':>9} "
            f"{'Mrays/s':>8} |")
    for sr in series:
        head += f" {infos[sr]['label']:>13}"
    lines.append(head)
    lines.insert(len(lines) - 1, "POV-Ray's points; right of |: the ratio by trace time for "
                 "each glint series")
    by_config = {r["config"]: r for r in res["equal_error"]}
    for p in res["povray"]:
        r = by_config[p["config"]]
        mark = "*" if r["pov_on_front"] else " "
        line = (f"{p['label']:<15}{mark} {_span(p, 'trace_seconds'):>20} "
                f"{p['cpu_seconds']:7.2f} {_span(p, 'wall_seconds'):>20} {p['rmse']:9.5f} "
                f"{(p['mrays_per_second'] or 0):8.2f} |")
        for sr in series:
            g = r["glint"][sr]
            line += f" {fmt_ratio(g['ratio_trace'], g['ratio_trace_bound']):>13}"
        lines.append(line)
    lines.append("")
    groups = list(dict.fromkeys(g for r in res["equal_error"] for g in r.get("best", {})))
    if groups:
        lines.append("best glint series at each POV-Ray point: ratio by trace / CPU / wall "
                     "time [series of each: the cap of the anti-aliased one, the depth of the "
                 "subdivided one]")
        lines.append(f"{'POV-Ray':<16} {'RMSE':>9} " + " ".join(f"| {g:<29}" for g in groups))
        for r in res["equal_error"]:
            mark = "*" if r["pov_on_front"] else " "
            line = f"{r['label']:<15}{mark} {r['rmse']:9.5f} "
            for g in groups:
                b = r["best"][g]
                cell = " ".join(fmt_ratio(b[k]["ratio"], b[k]["bound"]) for k in
                                ("trace", "cpu", "wall"))
                if g.endswith("antialias") or g.endswith("subdivide"):
                    what = "cap" if g.endswith("antialias") else "depth"
                    cell += " [" + ",".join(str(infos[b[k]["series"]][what]) for k in
                                            ("trace", "cpu", "wall")) + "]"
                line += f"| {cell:<29} "
            lines.append(line)
    lines.append("")
    lines.append("ratio = POV-Ray trace time / glint's trace time at the same RMSE, interpolated "
                 "along one glint series; cpu, wall = the same with the processes' CPU seconds "
                 "and wall times (> 1: glint faster); AA≤N: --antialias C --spp N, C swept; "
                 "subD: --subdivide D --antialias C, C swept;")
    lines.append("* = on POV-Ray's time-error front (its best settings); ≥ / ≤: the error is "
                 "outside glint's measured range, so the ratio is a bound")
    lines.append("cross-renderer RMSE between the references (translation fidelity; "
                 "the pixel filters differ): " + ", ".join(
                     f"glint {f} - POV-Ray {res['references_cross_rmse'][f]:.4f}"
                     for f in filters)
                 + "; image means: " + ", ".join(
                     f"glint {f} {refs['glint:' + f]['mean']:.4f}" for f in filters)
                 + f", POV-Ray {refs['povray']['mean']:.4f}")
    return "\n".join(lines)


def _span(p, key):
    if key + "_min" not in p:
        return f"{p[key]:.3f}"
    return f"{p[key]:.3f} [{p[key + '_min']:.2f}-{p[key + '_max']:.2f}]"


def _esc(s):
    return str(s).replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


POV_STYLE = {  # (method, depth) -> colour; marker by method
    (0, 0): "#7f7f7f", (1, 2): "#fdae6b", (1, 3): "#e6550d", (1, 4): "#a63603",
    (1, 5): "#7f2704", (2, 2): "#fdd0a2", (2, 3): "#f16913", (2, 4): "#8c2d04",
    (2, 5): "#4d1a02", (2, 6): "#2d0f01",
}


def _pov_series(points):
    series = {}
    for p in points:
        c = parse_pov_config(p["config"])
        key = (c["method"], c.get("depth", 0), c.get("jitter", False))
        series.setdefault(key, []).append((c, p))
    return series


def _glint_aa_marker(x, y, cap, colour):
    """An anti-aliased glint point: a ring for the lower cap (16), a filled inverted triangle
    for a higher one."""
    if cap <= 16:
        return (f'<circle cx="{x:.1f}" cy="{y:.1f}" r="4" fill="white" stroke="{colour}" '
                f'stroke-width="2"/>')
    return (f'<polygon points="{x - 5:.1f},{y - 4:.1f} {x + 5:.1f},{y - 4:.1f} '
            f'{x:.1f},{y + 5:.1f}" fill="{colour}"/>')


def svg_plot(res):
    panels = [("trace_seconds", "tracing time (s): glint render_seconds, POV-Ray Trace Time"),
              ("cpu_seconds", "CPU seconds of the process (user + system, both threads)"),
              ("wall_seconds", "wall time of the whole process (s)")]
    pw, ph, top, gap = 380, 380, 70, 100
    W, H = 80 + len(panels) * pw + (len(panels) - 1) * gap + 30, 560
    pts = res["glint"] + res["povray"]
    ymin = min(p["rmse"] for p in pts) / 1.3
    ymax = max(p["rmse"] for p in pts) * 1.3
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" '
           f'viewBox="0 0 {W} {H}" font-family="sans-serif" font-size="12">',
           f'<rect width="{W}" height="{H}" fill="white"/>',
           f'<text x="{W / 2}" y="22" text-anchor="middle" font-size="15">'
           f'{_esc(res["title"])}</text>',
           f'<text x="{W / 2}" y="40" text-anchor="middle" font-size="11" fill="#555">'
           f'{_esc(res["subtitle"])}</text>']
    for k, (key, xlabel) in enumerate(panels):
        left = 80 + k * (pw + gap)
        tmin = min(p[key + "_min"] if key + "_min" in p else p[key] for p in pts) / 1.3
        tmax = max(p[key + "_max"] if key + "_max" in p else p[key] for p in pts) * 1.3

        def X(t, left=left, tmin=tmin, tmax=tmax):
            return left + pw * math.log(t / tmin) / math.log(tmax / tmin)

        def Y(e):
            return top + ph * (1 - math.log(e / ymin) / math.log(ymax / ymin))

        out.append(f'<rect x="{left}" y="{top}" width="{pw}" height="{ph}" fill="none" '
                   f'stroke="#333"/>')
        for lo, hi, axis in ((tmin, tmax, "x"), (ymin, ymax, "y")):
            for d in range(math.floor(math.log10(lo)), math.ceil(math.log10(hi)) + 1):
                for m in range(1, 10):
                    v = m * 10.0 ** d
                    if not lo <= v <= hi:
                        continue
                    major = m == 1
                    labelled = major or m in ((2, 5) if hi / lo > 100 else (2, 3, 5))
                    if axis == "x":
                        x = X(v)
                        out.append(f'<line x1="{x:.1f}" y1="{top}" x2="{x:.1f}" y2="{top + ph}" '
                                   f'stroke="{"#ccc" if major else "#eee"}"/>')
                        if labelled:
                            out.append(f'<text x="{x:.1f}" y="{top + ph + 16}" '
                                       f'text-anchor="middle" font-size="11">{v:g}</text>')
                    else:
                        y = Y(v)
                        out.append(f'<line x1="{left}" y1="{y:.1f}" x2="{left + pw}" '
                                   f'y2="{y:.1f}" stroke="{"#ccc" if major else "#eee"}"/>')
                        if labelled:
                            out.append(f'<text x="{left - 6}" y="{y + 4:.1f}" text-anchor="end" '
                                       f'font-size="11">{v:g}</text>')
        out.append(f'<text x="{left + pw / 2}" y="{top + ph + 36}" text-anchor="middle" '
                   f'font-size="11">{_esc(xlabel)}</text>')
        out.append(f'<text transform="translate({left - 52},{top + ph / 2}) rotate(-90)" '
                   f'text-anchor="middle">RMSE against its own reference (linear RGB)</text>')

        def errbar(p, colour):
            if key + "_min" in p and p[key + "_max"] > p[key + "_min"]:
                y = Y(p["rmse"])
                out.append(f'<line x1="{X(p[key + "_min"]):.1f}" y1="{y:.1f}" '
                           f'x2="{X(p[key + "_max"]):.1f}" y2="{y:.1f}" stroke="{colour}" '
                           f'stroke-width="1"/>')

        # POV-Ray: one series per method and depth (thresholds 0.3 -> 0.0 along it).
        for (method, depth, jitter), items in sorted(_pov_series(res["povray"]).items()):
            colour = POV_STYLE.get((method, depth), "#d62728")
            items.sort(key=lambda cp: -cp[0].get("threshold", 1))
            if len(items) > 1:
                path = " ".join(f"{X(p[key]):.1f},{Y(p['rmse']):.1f}" for _, p in items)
                out.append(f'<polyline points="{path}" fill="none" stroke="{colour}" '
                           f'stroke-width="1.2"/>')
            for c, p in items:
                errbar(p, colour)
                x, y = X(p[key]), Y(p["rmse"])
                fill = "white" if jitter else colour
                if method == 0:
                    out.append(f'<rect x="{x - 4:.1f}" y="{y - 4:.1f}" width="8" height="8" '
                               f'fill="{fill}" stroke="{colour}" stroke-width="1.5"/>')
                elif method == 1:
                    out.append(f'<polygon points="{x:.1f},{y - 5:.1f} {x + 5:.1f},{y + 4:.1f} '
                               f'{x - 5:.1f},{y + 4:.1f}" fill="{fill}" stroke="{colour}" '
                               f'stroke-width="1.5"/>')
                else:
                    out.append(f'<polygon points="{x:.1f},{y - 5:.1f} {x + 5:.1f},{y:.1f} '
                               f'{x:.1f},{y + 5:.1f} {x - 5:.1f},{y:.1f}" fill="{fill}" '
                               f'stroke="{colour}" stroke-width="1.5"/>')
        # POV-Ray's front (its best settings), dashed.
        pf = front(res["povray"], key)
        if len(pf) > 1:
            path = " ".join(f"{X(p[key]):.1f},{Y(p['rmse']):.1f}" for p in pf)
            out.append(f'<polyline points="{path}" fill="none" stroke="#d62728" '
                       f'stroke-width="1" stroke-dasharray="5,4"/>')
        # glint: one spp ladder per pixel filter, the spp written beside each point; one
        # series of contrast thresholds per filter and cap (--antialias), the contrast written
        # beside each point (".02" for 0.02).
        for sr in glint_series(res["glint"]):
            info = series_info(res["glint"], sr)
            colour, aa = info["colour"], info["kind"] != "plain"
            sub = info["kind"] == "subdivide"
            g = [p for p in res["glint"] if series_of(p) == sr]
            g.sort(key=(lambda p: -p["antialias"]) if aa else (lambda p: p["spp"]))
            path = " ".join(f"{X(p[key]):.1f},{Y(p['rmse']):.1f}" for p in g)
            dash = ' stroke-dasharray="6,2"' if aa and not sub and info["cap"] > 16 else ""
            out.append(f'<polyline points="{path}" fill="none" stroke="{colour}" '
                       f'stroke-width="{1.5 if aa else 2}"{dash}/>')
            for p in g:
                errbar(p, colour)
                x, y = X(p[key]), Y(p["rmse"])
                if not aa:
                    out.append(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="4" fill="{colour}"/>')
                    dx, anchor = (-7, "end") if info["filter"] == "gaussian" else (7, "start")
                    text, dy = str(p["spp"]), -7
                elif sub:
                    out.append(f'<rect x="{x - 3.5:.1f}" y="{y - 3.5:.1f}" width="7" height="7" '
                               f'fill="{colour}" transform="rotate(45 {x:.1f} {y:.1f})"/>')
                    dx, anchor = 7, "start"
                    text, dy = f"{p['antialias']:g}".replace("0.", ".", 1), -6
                else:
                    out.append(_glint_aa_marker(x, y, info["cap"], colour))
                    dx, anchor = (7, "start") if info["filter"] == "gaussian" else (-7, "end")
                    text, dy = f"{p['antialias']:g}".replace("0.", ".", 1), 12
                out.append(f'<text x="{x + dx:.1f}" y="{y + dy:.1f}" text-anchor="{anchor}" '
                           f'font-size="9" fill="{colour}">{text}</text>')
    # Legend, under the panels.
    ly = top + ph + 58
    legend = []
    for sr in glint_series(res["glint"]):
        info = series_info(res["glint"], sr)
        f = info["filter"]
        if info["kind"] == "subdivide":
            legend.append((f"glint --subdivide {info['depth']} --antialias C, C as labelled",
                           info["colour"], "sub", False))
        elif info["cap"] is None:
            legend.append((f"glint, Whitted, {f} filter{' (default)' if f == 'gaussian' else ''}"
                           ", spp as labelled", info["colour"], "circle", False))
        else:
            legend.append((f"glint {f}, --antialias C --spp {info['cap']}, C as labelled",
                           info["colour"], f"aa{info['cap']}", False))
    for (method, depth, jitter), items in sorted(_pov_series(res["povray"]).items()):
        thresholds = sorted({c.get("threshold", 0) for c, _ in items}, reverse=True)
        a = (f"{thresholds[0]:g}" if len(thresholds) == 1 else
             " → ".join(f"{t:g}" for t in thresholds))
        name = ("POV-Ray no anti-aliasing" if method == 0 else
                f"POV-Ray +AM{method} +R{depth}{' +J' if jitter else ''}, +A {a}")
        legend.append((name, POV_STYLE.get((method, depth), "#d62728"),
                       ["square", "triangle", "diamond"][method], jitter))
    legend.append(("POV-Ray's front (its best settings at each time)", "#d62728", "dash", False))
    cols = 3
    for i, (name, colour, shape, hollow) in enumerate(legend):
        x = 90 + (i % cols) * (W - 120) // cols
        y = ly + (i // cols) * 17
        fill = "white" if hollow else colour
        if shape == "circle":
            out.append(f'<circle cx="{x}" cy="{y - 4}" r="4" fill="{colour}"/>')
        elif shape.startswith("aa"):
            out.append(_glint_aa_marker(x, y - 4, int(shape[2:]), colour))
        elif shape == "sub":
            out.append(f'<rect x="{x - 3.5}" y="{y - 7.5}" width="7" height="7" fill="{colour}" '
                       f'transform="rotate(45 {x} {y - 4})"/>')
        elif shape == "square":
            out.append(f'<rect x="{x - 4}" y="{y - 8}" width="8" height="8" fill="{fill}" '
                       f'stroke="{colour}" stroke-width="1.5"/>')
        elif shape == "triangle":
            out.append(f'<polygon points="{x},{y - 9} {x + 5},{y} {x - 5},{y}" fill="{fill}" '
                       f'stroke="{colour}" stroke-width="1.5"/>')
        elif shape == "diamond":
            out.append(f'<polygon points="{x},{y - 9} {x + 5},{y - 4} {x},{y + 1} {x - 5},{y - 4}" '
                       f'fill="{fill}" stroke="{colour}" stroke-width="1.5"/>')
        else:
            out.append(f'<line x1="{x - 8}" y1="{y - 4}" x2="{x + 8}" y2="{y - 4}" '
                       f'stroke="{colour}" stroke-dasharray="5,4"/>')
        out.append(f'<text x="{x + 12}" y="{y}" font-size="11">{_esc(name)}</text>')
    rows = (len(legend) + cols - 1) // cols
    height = ly + rows * 17 + 10
    out[0] = out[0].replace(f'height="{H}" viewBox="0 0 {W} {H}"',
                            f'height="{height}" viewBox="0 0 {W} {height}"')
    out[1] = f'<rect width="{W}" height="{height}" fill="white"/>'
    out.append("</svg>")
    return "\n".join(out) + "\n"


def report(res, args):
    res["equal_error"] = equal_error(res["glint"], res["povray"])
    text = tables(res)
    print(text)
    write_atomic(args.out_json, json.dumps(res, indent=1) + "\n")
    write_atomic(args.out_svg, svg_plot(res))
    log(f"wrote {os.path.relpath(args.out_json)}, {os.path.relpath(args.out_svg)}")


# ---------------------------------------------------------------------------------------------
# Main
# ---------------------------------------------------------------------------------------------

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--glint", default=os.environ.get("GLINT", os.path.join(ROOT, "build",
                                                                               "glint")),
                    help="glint binary (default: $GLINT, else build/glint)")
    ap.add_argument("--povray", help="povray binary (default: povray on PATH, installed with "
                                     "apt-get when missing)")
    ap.add_argument("--no-install", action="store_true", help="never run apt-get")
    ap.add_argument("--repeats", type=int, default=3, help="rounds over every point (default 3)")
    ap.add_argument("--threads", type=int, default=2, help="threads for both (default 2)")
    ap.add_argument("--glint-spp", default=",".join(map(str, DEFAULT_GLINT_SPP)))
    ap.add_argument("--glint-ref-spp", type=int, default=1024)
    ap.add_argument("--glint-filters", default=",".join(GLINT_FILTERS),
                    help="pixel filters, each its own spp ladder and reference: gaussian (the "
                         "scene as written, glint's default), box (radius 0.5)")
    ap.add_argument("--glint-antialias", default=",".join(map(str, DEFAULT_GLINT_ANTIALIAS)),
                    help="contrast thresholds C for glint's anti-aliasing by contrast "
                         "(--antialias C), one series per filter; empty: none")
    ap.add_argument("--glint-antialias-spp", type=int, default=DEFAULT_GLINT_ANTIALIAS_SPP,
                    help="their cap, --spp (default %(default)s)")
    ap.add_argument("--glint-antialias-high",
                    default=",".join(map(str, DEFAULT_GLINT_ANTIALIAS_HIGH)),
                    help="thresholds of a second series per filter at a higher cap (default "
                         "the smallest: reaching the errors of POV-Ray's deepest settings); "
                         "empty: none")
    ap.add_argument("--glint-antialias-high-spp", type=int,
                    default=DEFAULT_GLINT_ANTIALIAS_HIGH_SPP,
                    help="their cap (default %(default)s)")
    ap.add_argument("--glint-subdivide", default=",".join(DEFAULT_GLINT_SUBDIVIDE),
                    help="anti-aliasing by subdivision points DEPTH:CONTRAST (--subdivide "
                         "DEPTH --antialias CONTRAST), box filter only; empty: none")
    ap.add_argument("--pov-configs", default=",".join(DEFAULT_POV_CONFIGS),
                    help="comma-separated: none, or amM:THRESHOLD:DEPTH[:j]")
    ap.add_argument("--pov-ref", default=DEFAULT_POV_REF)
    ap.add_argument("--width", type=int, default=800)
    ap.add_argument("--height", type=int, default=600)
    ap.add_argument("--work", default=os.path.join(ROOT, "build", "povray_compare"),
                    help="references (cached) and scratch images")
    ap.add_argument("--out-json", default=os.path.join(RESULTS, "povray_csg.json"))
    ap.add_argument("--out-svg", default=os.path.join(RESULTS, "povray_csg.svg"))
    ap.add_argument("--out-png", default=os.path.join(RESULTS, "povray_csg_refs.png"))
    ap.add_argument("--fresh-references", action="store_true",
                    help="render the references again even when cached")
    ap.add_argument("--keep-images", action="store_true", help="keep the sweep's EXRs in --work")
    ap.add_argument("--quick", action="store_true", help="smoke test (outputs under --work)")
    ap.add_argument("--report", action="store_true",
                    help="tables and plot again from --out-json, no rendering")
    args = ap.parse_args()

    if args.quick:
        for k, v in QUICK.items():
            if k in ("glint_spp", "pov_configs", "glint_antialias", "glint_antialias_high",
                     "glint_subdivide"):
                v = ",".join(map(str, v))
            setattr(args, k, v)
        for k, name in (("out_json", "quick.json"), ("out_svg", "quick.svg"),
                        ("out_png", "quick.png")):
            setattr(args, k, os.path.join(args.work, name))
    if args.report:
        with open(args.out_json) as f:
            report(json.load(f), args)
        return

    glint = os.path.abspath(args.glint)
    if not os.access(glint, os.X_OK):
        sys.exit(f"no glint binary at {glint} (build it, or pass --glint PATH / set GLINT)")
    povray = ensure_povray(args)
    if np is None:
        log("numpy not found in this interpreter: reading the images in pure Python "
            "(slower, same numbers; Debian's /usr/bin/python3 with python3-numpy is faster)")
    glint_spp = [int(s) for s in args.glint_spp.split(",")]
    # (spp, contrast, depth): the plain ladder (contrast 0), then the anti-aliased points, then
    # the subdivided ones (depth > 0; box filter only).
    glint_settings = [(n, 0.0, 0) for n in glint_spp]
    for cs, cap in ((args.glint_antialias, args.glint_antialias_spp),
                    (args.glint_antialias_high, args.glint_antialias_high_spp)):
        for c in (float(x) for x in cs.split(",") if x.strip()):
            if not 0 < c <= 1:
                sys.exit(f"anti-aliasing contrast {c}: must be in (0, 1]")
            glint_settings.append((cap, c, 0))
    for dc in (x for x in args.glint_subdivide.split(",") if x.strip()):
        try:
            d, c = dc.split(":")
            d, c = int(d), float(c)
        except ValueError:
            sys.exit(f"--glint-subdivide: '{dc}': expected DEPTH:CONTRAST")
        if not (1 <= d <= 6 and 0 <= c <= 1):
            sys.exit(f"--glint-subdivide: '{dc}': depth 1-6, contrast 0-1")
        glint_settings.append((1, c, d))
    filters = args.glint_filters.split(",")
    for f in filters:
        if f not in GLINT_FILTERS:
            sys.exit(f"--glint-filters: unknown filter '{f}' (known: {', '.join(GLINT_FILTERS)})")
    pov_configs = [parse_pov_config(c) for c in args.pov_configs.split(",")]
    ctx = {"glint": glint, "povray": povray, "threads": args.threads, "width": args.width,
           "height": args.height, "work": os.path.abspath(args.work),
           "glint_ref_spp": args.glint_ref_spp, "pov_ref": args.pov_ref,
           "repeats": args.repeats}
    scratch = os.path.join(ctx["work"], "scratch")
    os.makedirs(scratch, exist_ok=True)
    started = datetime.datetime.now()
    versions = {"glint": glint_version(glint), "glint_sha256": sha256_file(glint),
                "povray": povray_version(povray), "povray_path": povray}
    log(f"{versions['glint']} ({glint}); {versions['povray']} ({povray})")

    refs = {f"glint:{f}": reference(ctx, "glint", args, f) for f in filters}
    refs["povray"] = reference(ctx, "povray", args)
    ref_images = {r: read_exr(os.path.join(ROOT, refs[r]["path"])) for r in refs}
    for r in refs:
        refs[r]["mean"] = image_errors(ref_images[r], ref_images[r])["mean"]
    cross = {f: image_errors(ref_images[f"glint:{f}"], ref_images["povray"])["rmse"]
             for f in filters}
    side_by_side_png([ref_images[f"glint:{f}"] for f in filters] + [ref_images["povray"]],
                     args.out_png)

    # The sweep: every round renders every point once, glint's and POV-Ray's alternating (the
    # order reversed every other round, so a drift in the machine's load hits both alike).
    def wanted(f, d):  # subdivision estimates the box integral: judged against box only
        return not d or f == "box"
    jobs = [("glint", (f, s, c, d)) for s, c, d in glint_settings for f in filters
            if wanted(f, d)]
    pov_jobs = [("povray", c) for c in pov_configs]
    order = []
    for i in range(max(len(jobs), len(pov_jobs))):
        order += jobs[i:i + 1] + pov_jobs[i:i + 1]
    records = {("glint", f, s, c, d): [] for f in filters for s, c, d in glint_settings
               if wanted(f, d)}
    records.update({("povray", c["name"]): [] for c in pov_configs})
    scenes = {f: glint_scene(ctx, f) for f in filters}
    total = len(order) * args.repeats
    done = 0
    for rnd in range(args.repeats):
        for renderer, what in (order if rnd % 2 == 0 else order[::-1]):
            done += 1
            if renderer == "glint":
                f, s, c, d = what
                out = os.path.join(scratch, f"glint_{f}_{s}spp_aa{c:g}_sub{d}_r{rnd}.exr")
                rec = render_glint(ctx, scenes[f], s, rnd + 1, out, antialias=c, subdivide=d)
                rec["seed"] = rnd + 1
                key, ref, label = ("glint", f, s, c, d), f"glint:{f}", glint_label(f, s, c, d)
            else:
                out = os.path.join(scratch, f"pov_{what['name'].replace(':', '_')}_r{rnd}.exr")
                rec = render_povray(ctx, what, out)
                key, ref, label = ("povray", what["name"]), "povray", what["label"]
            rec["round"] = rnd
            rec["error"] = image_errors(read_exr(out), ref_images[ref])
            if not args.keep_images:
                os.unlink(out)
            records[key].append(rec)
            log(f"[{done}/{total}] {renderer:6} {label:<18} trace {rec['trace_seconds']:7.3f} s"
                f"  wall {rec['wall_seconds']:7.3f} s  RMSE {rec['error']['rmse']:.5f}"
                f"  load {rec['load_average'][0]:.2f}")

    glint_points = []
    for f in filters:
        for s, c, d in glint_settings:
            if not wanted(f, d):
                continue
            rs = records[("glint", f, s, c, d)]
            mean_spp = [r["stats"]["mean_spp"] for r in rs if r["stats"].get("mean_spp")]
            p = {"renderer": "glint", "filter": f, "spp": s, "antialias": c,
                 "subdivide": d or None,
                 "series": f"{f} sub{d}" if d else (f if not c else f"{f} aa{s}"),
                 "label": glint_label(f, s, c, d),
                 "mean_spp": statistics.median(mean_spp) if mean_spp else None,
                 **summarize(rs), "runs": rs}
            glint_points.append(p)
    pov_points = []
    for c in pov_configs:
        p = {"renderer": "povray", "config": c["name"], "label": c["label"],
             "options": c["options"], **summarize(records[("povray", c["name"])]),
             "runs": records[("povray", c["name"])]}
        pov_points.append(p)

    loads = [r["load_average"][0] for rs in records.values() for r in rs]
    res = {
        "benchmark": "glint against POV-Ray: time to equal error (issue 27)",
        "title": "glint (Whitted) against POV-Ray 3.7: RMSE against each renderer's own "
                 "reference",
        "subtitle": (f"benchmarks/povray/csg_compare, {args.width}x{args.height}, "
                     f"{args.threads} threads, median of {args.repeats}; {cpu_model()}, "
                     f"{started:%Y-%m-%d}, 1-min load {min(loads):.1f}-{max(loads):.1f}"),
        "date": started.isoformat(timespec="seconds"),
        "finished": datetime.datetime.now().isoformat(timespec="seconds"),
        "command": [sys.executable] + sys.argv,
        "commit": git_commit(),
        "machine": machine(),
        "versions": versions,
        "settings": {"width": args.width, "height": args.height, "threads": args.threads,
                     "repeats": args.repeats, "glint_spp": glint_spp,
                     "glint_antialias": {"contrasts": args.glint_antialias,
                                         "spp": args.glint_antialias_spp,
                                         "high_contrasts": args.glint_antialias_high,
                                         "high_spp": args.glint_antialias_high_spp,
                                         "options": "--antialias C --spp CAP"},
                     "glint_subdivide": {"points": args.glint_subdivide,
                                         "options": "--subdivide D --antialias C (box filter "
                                                    "scene; glint's default --jitter 1)"},
                     "glint_filters": {f: GLINT_FILTERS[f] or "the scene's (glint's default: "
                                       "gaussian, radius 1.5 pixels)" for f in filters},
                     "glint_ref_spp": args.glint_ref_spp, "glint_ref_seed": GLINT_REF_SEED,
                     "glint_sweep_seeds": list(range(1, args.repeats + 1)),
                     "pov_configs": [c["name"] for c in pov_configs], "pov_ref": args.pov_ref,
                     "scenes": {"glint": os.path.relpath(GLINT_SCENE, ROOT),
                                "povray": os.path.relpath(POV_SCENE, ROOT)},
                     "error": "RMSE over all pixels and the linear R, G, B channels against "
                              "the renderer's own reference; relMSE = mean (a-b)^2/(b^2+0.01)",
                     "times": "trace_seconds: glint render_seconds, POV-Ray Trace Time; "
                              "own_seconds: + glint load and build, + POV-Ray parse and "
                              "bounding; wall_seconds: the whole process; cpu_seconds: the "
                              "child's user + system time"},
        "load_average_range": [min(loads), max(loads)],
        "references": refs,
        "references_cross_rmse": cross,
        "glint": glint_points,
        "povray": pov_points,
    }
    report(res, args)


if __name__ == "__main__":
    main()
