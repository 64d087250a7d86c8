#!/usr/bin/env python3
"""Where a render's time goes, from a `perf record` profile, by stage of a sample.

Groups the self time of every symbol `perf report` lists into the stages of a path-traced
sample: tracing (Embree and glint's intersection code), texture lookups (glint's MIP pyramids or
OpenImageIO's TextureSystem), BSDF (building and evaluating the per-hit BSDF), lights (choosing a
light and sampling it), film, loading (decoding images, building MIP levels and BVHs, the
dynamic loader, page faults) and the rest of the path loop. Usage:

    perf record -e cpu-clock -F 2000 -g -o render.data -- glint render scene.gltf ...
    benchmarks/profile_breakdown.py render.data [more.data ...]

The rules are the symbol patterns below, first match wins; `--unmatched N` lists the N largest
symbols that fell into "other" so the rules can be kept honest.
"""
import argparse
import re
import subprocess
import sys

RULES = [
    ("texture lookups", r"MipMap::(lookup|bilinear|trilinear|fetch)|TextureSystem|ImageCache|"
                        r"OpenImageIO.*(sample_|texture|find_tile|vfloat4|wrap_|ellipse|miplevels)|"
                        r"__vdso_clock_gettime|hypot|ImageTexture::evaluate|TextureLookups|"
                        r"TextureImages::lookup|TextureMapping::map2D|__log2f"),
    ("loading", r"libjpeg|libpng|inflate|libz|MipMap::buildLevels|downsample|decode|do_lookup_x|"
                r"_dl_|ld-linux|clear_page|exc_page_fault|page_fault|unmap_page|"
                r"rtcCommit|BVHBuilder|build|Draco|gltf|Gltf|json|tinygltf|__memmove|__memset|"
                r"parallel_sort|radix"),
    ("tracing", r"libembree|embree|rtcIntersect|rtcOccluded|Accelerator|intersect|occluded|"
                r"cullBackFaces|alphaTest|shadowRay|spawnRay|offsetRayOrigin"),
    ("hit setup", r"computeSurfaceInteraction|triangleTangents|shadingPoint|tangentFrame|"
                  r"setPixelFootprint|NormalMap::apply|reflectionSafeNormal|Frame::"),
    ("BSDF", r"Bsdf|Bxdf|bsdf|bxdf|ggx|Ggx|Fresnel|fresnel|multipleScattering|microfacet|"
             r"Material::|makeBsdf|lobe|albedo"),
    ("lights", r"Light|light|powerHeuristic|Distribution|sampleLi|pdfLi"),
    ("film", r"Film|film|addSample|Filter|splat"),
    ("path loop", r"PathIntegrator|tracePath|VertexSamples|Sampler|sampler|Sobol|sobol|"
                  r"renderTile|ProgressiveRender|Integrator|SampleEvaluator|shutterTimes|"
                  r"PixelSums|ContrastStop|AdaptiveStop"),
]


def breakdown(data, unmatched, hz):
    out = subprocess.run(["perf", "report", "-i", data, "--no-children", "--sort", "dso,symbol",
                          "-g", "none", "--stdio", "-n"], capture_output=True, text=True,
                         check=True)
    totals, rest, samples = {}, [], 0
    for line in out.stdout.splitlines():
        m = re.match(r"\s*([0-9.]+)%\s+(\d+)\s+(\S+)\s+\[.\]\s+(.*)", line)
        if not m:
            continue
        pct, dso, sym = float(m.group(1)), m.group(3), m.group(4).strip()
        samples += int(m.group(2))
        key = "other"
        for name, pattern in RULES:
            if re.search(pattern, dso + " " + sym):
                key = name
                break
        totals[key] = totals.get(key, 0.0) + pct
        if key == "other":
            rest.append((pct, dso, sym))
    cpu = samples / hz
    print(f"## {data}: {samples} samples, {cpu:.2f} CPU s at {hz:g} Hz")
    for name in [r[0] for r in RULES] + ["other"]:
        share = totals.get(name, 0.0)
        print(f"  {name:16s} {share:5.1f}%  {share / 100 * cpu:6.2f} CPU s")
    for pct, dso, sym in sorted(rest, reverse=True)[:unmatched]:
        print(f"    other: {pct:5.2f}% {dso} {sym[:90]}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("data", nargs="+")
    ap.add_argument("--unmatched", type=int, default=0)
    ap.add_argument("--hz", type=float, default=2000, help="the -F given to perf record")
    args = ap.parse_args()
    for d in args.data:
        breakdown(d, args.unmatched, args.hz)


if __name__ == "__main__":
    sys.exit(main())
