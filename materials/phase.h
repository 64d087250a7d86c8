// glint — the Henyey–Greenstein phase function (Henyey & Greenstein 1941), for participating
// media (materials/medium.h).
//
// Convention: cosTheta is the cosine between the direction light travelled before scattering
// and the direction it travels after. g > 0 scatters forwards (cosTheta near 1), g < 0
// backwards, g = 0 is isotropic. For a camera-side direction d (pointing into the scene) and a
// direction wi towards a light, light travels along -wi and then along -d, so
// cosTheta = dot(wi, d). The density is normalised over the sphere of directions:
//   p(cosTheta) = (1 - g^2) / (4 pi (1 + g^2 - 2 g cosTheta)^(3/2)).
#pragma once

#include <algorithm>
#include <cmath>

#include "geometry/math.h"

namespace glint {

// The phase function for |g| < 1 (solid-angle density).
inline float henyeyGreenstein(float cosTheta, float g) {
  // 1 + g^2 - 2 g cosTheta written without cancellation for g near 1 and cosTheta near 1;
  // it is >= (1 - |g|)^2 > 0 for |g| < 1, the max only guards rounding.
  const float denom = (1 - g) * (1 - g) + 2 * g * (1 - cosTheta);
  const float d = std::max(denom, 1e-12f);
  return (1 - g * g) / (4 * kPi * d * std::sqrt(d));
}

// The cosine of a direction drawn from the HG density (inverse CDF), for u in [0, 1).
inline float sampleHenyeyGreensteinCos(float g, float u) {
  // Near g = 0 the inverse CDF divides 0 by 0; the isotropic law is its limit there.
  if (std::abs(g) < 1e-3f) return std::clamp(2 * u - 1, -1.0f, 1.0f);
  const float s = (1 - g * g) / (1 - g + 2 * g * u);
  return std::clamp((1 + g * g - s * s) / (2 * g), -1.0f, 1.0f);
}

// A unit direction drawn around `forward` (the unit direction light travels before
// scattering) with density henyeyGreenstein(dot(forward, w), g), which goes into `pdf`.
inline Vec3f sampleHenyeyGreenstein(Vec3f forward, float g, Vec2f u, float* pdf) {
  const float cosTheta = sampleHenyeyGreensteinCos(g, u.x);
  const float sinTheta = std::sqrt(std::max(0.0f, 1 - cosTheta * cosTheta));
  const float phi = 2 * kPi * u.y;
  const Frame frame = Frame::fromZ(forward);
  if (pdf) *pdf = henyeyGreenstein(cosTheta, g);
  return normalize(frame.fromLocal({sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta}));
}

}  // namespace glint
