// glint — Russian roulette on a path's throughput: the one rule the path tracer (camera paths,
// surface and medium vertices alike) and instant radiosity's light paths end their paths by.
#pragma once

#include <algorithm>
#include <cmath>

#include "geometry/math.h"

namespace glint {

// Whether a path goes on after the vertex that gives it its `bounce`-th bounce (1: the first
// surface's bounce), and if so its throughput `*beta` divided by the chance it had. Paths of
// fewer than `rrDepth` bounces always go on; the others survive with the square root of the
// throughput's largest component (as Cycles does), clamped to [0.05, 1], so bright paths are
// never cut and dim ones not boosted more than 20x. `etaScale` undoes the 1/eta^2 that
// refractions put into a radiance throughput (1 for flux); `u` is the vertex's roulette number
// in [0, 1). The expectation is unchanged.
//
// Why the square root: the throughput alone (pbrt-v4's chance) cuts too many paths that still
// carry light. At a throughput of 0.125 (three bounces off albedo 0.5) it keeps one path in
// eight and weighs it 8x, and the variance that adds outweighs the time saved. Measured
// (benchmarks/README, "Russian roulette": 1 / (variance x time)), the root from bounce 5 was
// 1.11x as efficient as the throughput from bounce 3 on a Cornell box, 1.30x with a glass
// ball and a mirror box in it, 1.33x on the CSG scene, 1.12x on the VDB fire, and level on
// the VDB cloud.
inline bool survivesRoulette(int bounce, int rrDepth, float etaScale, float u, Rgb* beta) {
  if (bounce < rrDepth) return true;
  const float survive = std::clamp(std::sqrt(maxComponent(*beta * etaScale)), 0.05f, 1.0f);
  if (survive >= 1) return true;
  if (u >= survive) return false;
  *beta *= 1 / survive;
  return true;
}

}  // namespace glint
