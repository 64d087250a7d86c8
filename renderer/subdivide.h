// glint — anti-aliasing by recursive subdivision (POV-Ray's sampling method 2).
//
// A scene without noise (Whitted: point lights, mirrors, glass) is exact everywhere but at its
// edges, so samples are wasted wherever the image is smooth. Whole-pixel anti-aliasing by
// contrast (AdaptiveSettings::contrast alone) puts its extra samples on whole pixels; this one
// puts them where inside the pixel the contrast is:
//
//  - every pixel corner gets one look (a camera path through that point of the film), shared by
//    the four pixels that meet there, so a smooth region costs one look per pixel;
//  - a square whose four corner looks differ by more than `contrast` (any channel, on x/(1+x),
//    as the whole-pixel rule compares) is cut into four, which takes five new looks (its edges'
//    midpoints, shared with the square beside it, and its centre), down to `subdivide` levels;
//  - a square that is not cut is the mean of its corners (the trapezoid rule: exact for a linear
//    gradient, like a centre look), and a pixel is the area-weighted sum of its squares: an
//    estimate of the pixel's box integral. render.filter is not used.
//
// Looks lie on a lattice of 2^subdivide points per pixel side, each keyed by its place in the
// whole image (its jitter, lens point, time and integrator numbers come from that key), so a
// look is the same whichever tile, thread, crop or pixel asks for it: the image does not depend
// on the thread count, and a crop's pixels are the whole frame's. With `jitter` (default 1) a
// look moves off its lattice point by up to half the finest lattice step, as POV-Ray's +J
// does; the squares and their weights stay the lattice's.
//
// The film holds each pixel's estimate; `samples` = the distinct looks in it (4 + 5 per cut),
// `variance` = their area-weighted spread divided by that count (a spread, not a variance: the
// estimate is a quadrature, not a mean of random samples), alpha and the AOVs area-weighted like
// the colour. RenderStats::meanSpp = the looks traced per pixel (shared corners count once).
// The render is one pass: it cannot be continued, budgeted or previewed pass by pass.
#pragma once

#include "renderer/render.h"

namespace glint {

// Renders `scene` as described above with settings.adaptive.subdivide levels (1 to
// kMaxSubdivision) and settings.adaptive.contrast (0: every square is cut to the deepest
// level, full supersampling on the lattice). `cancel` (may be null) stops it between rows and
// tiles; it then returns false and leaves `film` alone. `onPixels` (may be empty) is called
// from worker threads as pixels finish (each pixel counts twice: its corner, then its squares).
// Throws InputError for a crop outside the image, a depth out of range, or an adaptive
// threshold (the noise rule has no samples to judge here).
// The most looks a pixel can hold with `levels` of subdivision, (2^levels + 1)²: what a
// subdivided render reports as its spp.
inline uint32_t subdivisionMaxLooks(int levels) {
  const uint32_t side = (1u << levels) + 1;
  return side * side;
}

bool renderSubdivided(const RenderScene& scene, const Integrator& integrator,
                      const RenderSettings& settings, const RenderOptions& options, Film* film,
                      RenderStats* stats, const std::atomic<bool>* cancel = nullptr,
                      const std::function<void(uint64_t)>& onPixels = {});

}  // namespace glint
