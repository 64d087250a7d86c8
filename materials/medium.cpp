// glint — density fields.
#include "materials/medium.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace glint {

// ---------------------------------------------------------------------------------------------
// Density fields
// ---------------------------------------------------------------------------------------------

GridDensity::GridDensity(int nx, int ny, int nz, std::vector<float> values, const Bounds3f& bounds)
    : nx_(nx), ny_(ny), nz_(nz), values_(std::move(values)), bounds_(bounds) {
  if (nx < 1 || ny < 1 || nz < 1 || values_.size() != size_t(nx) * size_t(ny) * size_t(nz))
    throw std::logic_error("GridDensity: the value count does not match the resolution");
  for (float& v : values_) {
    if (!std::isfinite(v) || v < 0) v = 0;
    max_ = std::max(max_, v);
  }
}

float GridDensity::density(Vec3f p) const {
  const Vec3f extent = bounds_.diagonal();
  float c[3];
  int i0[3], i1[3];
  float f[3];
  const int res[3] = {nx_, ny_, nz_};
  for (int a = 0; a < 3; ++a) {
    c[a] = extent[a] > 0 ? (p[a] - bounds_.lower[a]) / extent[a] * float(res[a] - 1) : 0;
    c[a] = std::clamp(c[a], 0.0f, float(res[a] - 1));
    i0[a] = std::min(int(c[a]), res[a] - 1);
    i1[a] = std::min(i0[a] + 1, res[a] - 1);
    f[a] = c[a] - float(i0[a]);
  }
  auto lerp1 = [](float t, float a, float b) { return a + t * (b - a); };
  float x00 = lerp1(f[0], at(i0[0], i0[1], i0[2]), at(i1[0], i0[1], i0[2]));
  float x10 = lerp1(f[0], at(i0[0], i1[1], i0[2]), at(i1[0], i1[1], i0[2]));
  float x01 = lerp1(f[0], at(i0[0], i0[1], i1[2]), at(i1[0], i0[1], i1[2]));
  float x11 = lerp1(f[0], at(i0[0], i1[1], i1[2]), at(i1[0], i1[1], i1[2]));
  return lerp1(f[2], lerp1(f[1], x00, x10), lerp1(f[1], x01, x11));
}

NoiseDensity::NoiseDensity(float scale, int octaves, float threshold, uint64_t seed, Vec3f offset)
    : noise_(seed),
      scale_(scale),
      offset_(offset),
      octaves_(octaves),
      threshold_(threshold),
      amplitudeSum_(octaveAmplitudeSum(octaves, 0.5f)) {}

float NoiseDensity::density(Vec3f p) const {
  const float n = std::clamp(
      0.5f + 0.5f * noise_.fbm((p - offset_) * scale_, octaves_) / amplitudeSum_, 0.0f, 1.0f);
  return std::max(0.0f, n - threshold_) / (1 - threshold_);
}

ExponentialDensity::ExponentialDensity(Vec3f up, float falloff, float h0)
    : up_(normalize(up)), falloff_(falloff), h0_(h0) {}

float ExponentialDensity::density(Vec3f p) const {
  return std::exp(std::min(60.0f, -falloff_ * (dot(p, up_) - h0_)));
}

float ExponentialDensity::maxDensity(const Bounds3f& region) const {
  // The exponent is linear in p, so its maximum over a box is at a corner.
  float best = 0;
  for (int i = 0; i < 8; ++i) {
    Vec3f corner{(i & 1) ? region.upper.x : region.lower.x,
                 (i & 2) ? region.upper.y : region.lower.y,
                 (i & 4) ? region.upper.z : region.lower.z};
    best = std::max(best, density(corner));
  }
  return best;
}

}  // namespace glint
