// glint — warping uniform samples in [0,1)^2 to directions and points.
#pragma once

#include "geometry/math.h"

namespace glint {

// Shirley–Chiu concentric mapping of the square onto the unit disk (area-preserving,
// low distortion; stratification survives).
inline Vec2f sampleConcentricDisk(Vec2f u) {
  float ox = 2 * u.x - 1, oy = 2 * u.y - 1;
  if (ox == 0 && oy == 0) return {0, 0};
  float r, theta;
  if (std::abs(ox) > std::abs(oy)) {
    r = ox;
    theta = (kPi / 4) * (oy / ox);
  } else {
    r = oy;
    theta = kPi / 2 - (kPi / 4) * (ox / oy);
  }
  return {r * std::cos(theta), r * std::sin(theta)};
}

// Cosine-weighted direction around +Z (Malley's method); pdf = cos(theta) / pi.
inline Vec3f sampleCosineHemisphere(Vec2f u) {
  Vec2f d = sampleConcentricDisk(u);
  float z = std::sqrt(std::max(0.0f, 1 - d.x * d.x - d.y * d.y));
  return {d.x, d.y, z};
}
inline float cosineHemispherePdf(float cosTheta) { return cosTheta > 0 ? cosTheta * kInvPi : 0; }

// Mirror reflection of w about n (both unit, pointing away from the surface).
inline Vec3f reflect(Vec3f w, Vec3f n) { return 2 * dot(w, n) * n - w; }

}  // namespace glint
