// glint — warping uniform samples in [0,1)^2 to directions and points.
#pragma once

#include <algorithm>
#include <cmath>

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

// The density of sampleConcentricDisk over the unit disk: uniform.
inline float concentricDiskPdf() { return kInvPi; }

// The concentric map in polar form, radius >= 0 and angle in [-pi/4, 7pi/4]: r^2 and the angle
// are uniform and independent for uniform u.
inline void sampleConcentricPolar(Vec2f u, float* r, float* theta) {
  float ox = 2 * u.x - 1, oy = 2 * u.y - 1;
  if (ox == 0 && oy == 0) {
    *r = 0, *theta = 0;
    return;
  }
  if (std::abs(ox) > std::abs(oy)) {
    *r = std::abs(ox);
    *theta = (kPi / 4) * (oy / ox) + (ox < 0 ? kPi : 0);
  } else {
    *r = std::abs(oy);
    *theta = kPi / 2 - (kPi / 4) * (ox / oy) + (oy < 0 ? kPi : 0);
  }
}

// A uniform point in the regular polygon with `n` >= 3 vertices on the unit circle, the first
// at angle `angle0` from +X. The concentric map's radius scales the polygon and its angle runs
// along the edges at a constant rate per sector: each sector is a triangle with its apex at the
// centre, whose area grows linearly along the edge and quadratically with the scale, so the
// map stays uniform; it is continuous, sends the square's centre to the polygon's centre and
// keeps the concentric map's low distortion (stratified samples stay stratified).
inline Vec2f sampleRegularPolygon(Vec2f u, int n, float angle0) {
  float r, theta;
  sampleConcentricPolar(u, &r, &theta);
  const float sector = 2 * kPi / float(n);
  float a = (theta - angle0) / sector;
  a -= float(n) * std::floor(a / float(n));  // in [0, n)
  int k = std::min(int(a), n - 1);
  float t = std::min(a - float(k), 1.0f);
  float a0 = angle0 + float(k) * sector, a1 = a0 + sector;
  return {r * ((1 - t) * std::cos(a0) + t * std::cos(a1)),
          r * ((1 - t) * std::sin(a0) + t * std::sin(a1))};
}
// The density of sampleRegularPolygon: one over the area (n/2) sin(2 pi / n).
inline float regularPolygonPdf(int n) { return 2 / (float(n) * std::sin(2 * kPi / float(n))); }

// Cosine-weighted direction around +Z (Malley's method); pdf = cos(theta) / pi.
inline Vec3f sampleCosineHemisphere(Vec2f u) {
  Vec2f d = sampleConcentricDisk(u);
  float z = std::sqrt(std::max(0.0f, 1 - d.x * d.x - d.y * d.y));
  return {d.x, d.y, z};
}
inline float cosineHemispherePdf(float cosTheta) { return cosTheta > 0 ? cosTheta * kInvPi : 0; }

// Uniform direction on the hemisphere around +Z; pdf = 1 / (2 pi).
inline Vec3f sampleUniformHemisphere(Vec2f u) {
  const float z = u.x;
  const float r = std::sqrt(std::max(0.0f, 1 - z * z));
  const float phi = 2 * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float uniformHemispherePdf(float cosTheta) { return cosTheta > 0 ? 0.5f * kInvPi : 0; }

// Uniform direction on the unit sphere; pdf = 1 / (4 pi).
inline Vec3f sampleUniformSphere(Vec2f u) {
  const float z = 1 - 2 * u.x;
  const float r = std::sqrt(std::max(0.0f, 1 - z * z));
  const float phi = 2 * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}
inline constexpr float kUniformSpherePdf = 1 / (4 * kPi);

// Uniform direction in the cone of half-angle acos(cosThetaMax) around +Z;
// pdf = 1 / (2 pi (1 - cosThetaMax)).
inline Vec3f sampleUniformCone(Vec2f u, float cosThetaMax) {
  const float cosTheta = (1 - u.x) + u.x * cosThetaMax;
  const float sinTheta = std::sqrt(std::max(0.0f, 1 - cosTheta * cosTheta));
  const float phi = 2 * kPi * u.y;
  return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}
inline float uniformConePdf(float cosThetaMax) { return 1 / (2 * kPi * (1 - cosThetaMax)); }

// Mirror reflection of w about n (both unit, pointing away from the surface).
inline Vec3f reflect(Vec3f w, Vec3f n) { return 2 * dot(w, n) * n - w; }

}  // namespace glint
