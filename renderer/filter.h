// glint — pixel reconstruction filters, importance-sampled.
//
// A sample's offset from the pixel centre is drawn from the filter itself, so every sample has
// weight 1 and belongs to one pixel (pbrt-v4's approach). The box, tent and truncated Gaussian
// are non-negative and separable; sampling each axis independently is exact.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "geometry/math.h"
#include "renderer/sampler.h"
#include "renderer/settings.h"

namespace glint {

class PixelFilter {
 public:
  // Throws InputError for an unknown type or a radius that is not > 0.
  explicit PixelFilter(const FilterSettings& settings);
  // Offset from the pixel centre, in pixels, for a uniform sample u in [0,1)^2.
  Vec2f sampleOffset(Vec2f u) const { return {sample1D(u.x), sample1D(u.y)}; }
  // The same for u given as 32-bit fractions: equal to sampleOffset(u.toFloat()), bit for
  // bit, but the Gaussian table index comes from the integer bits (no float-int round trip).
  Vec2f sampleOffsetFraction(Fraction2 u) const {
    if (kind_ != Kind::Gaussian) return sampleOffset(u.toFloat());
    return {gaussian1D(u.x), gaussian1D(u.y)};
  }
  float radius() const { return radius_; }

 private:
  // Inline: runs twice per camera sample.
  float sample1D(float u) const {
    switch (kind_) {
      case Kind::Box:
        return (2 * u - 1) * radius_;
      case Kind::Tent:
        return u < 0.5f ? radius_ * (std::sqrt(2 * u) - 1) : radius_ * (1 - std::sqrt(2 - 2 * u));
      case Kind::Gaussian:
      default: {
        float x = u * kInverseSize;
        int i = std::min(int(x), kInverseSize - 1);
        float t = x - float(i);
        const float* table = inverseCdf_.data();
        return table[i] + t * (table[i + 1] - table[i]);
      }
    }
  }
  // sample1D for the Gaussian at u = fractionToFloat(v): u has 24 bits, so x = u * 2^10 splits
  // exactly into the top 10 bits (the index) and the low 14 (the lerp weight).
  float gaussian1D(uint32_t v) const {
    static_assert(kInverseSize == 1 << 10);
    uint32_t bits = v >> 8;
    uint32_t i = bits >> 14;
    float t = float(bits & 0x3fffu) * 0x1p-14f;
    const float* table = inverseCdf_.data();
    return table[i] + t * (table[i + 1] - table[i]);
  }

  // The Gaussian's CDF is tabulated finely, then inverted onto a table indexed by u, so a
  // sample costs one lookup and a lerp (no search).
  static constexpr int kCdfSize = 4096;
  static constexpr int kInverseSize = 1024;
  enum class Kind { Box, Tent, Gaussian } kind_;
  float radius_;
  std::vector<float> inverseCdf_;  // Gaussian: x(u) in [-radius, radius] at uniform u steps
};

}  // namespace glint
