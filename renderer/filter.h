// glint — pixel reconstruction filters, importance-sampled.
//
// A sample's offset from the pixel centre is drawn from the filter itself, so every sample has
// weight 1 and belongs to one pixel (pbrt-v4's approach). The box, tent and truncated Gaussian
// are non-negative and separable; sampling each axis independently is exact.
#pragma once

#include <string>
#include <vector>

#include "geometry/math.h"
#include "renderer/settings.h"

namespace glint {

class PixelFilter {
 public:
  // Throws std::invalid_argument for an unknown type or a radius that is not > 0.
  explicit PixelFilter(const FilterSettings& settings);
  // Offset from the pixel centre, in pixels, for a uniform sample u in [0,1)^2.
  Vec2f sampleOffset(Vec2f u) const { return {sample1D(u.x), sample1D(u.y)}; }
  float radius() const { return radius_; }

 private:
  float sample1D(float u) const;
  enum class Kind { Box, Tent, Gaussian } kind_;
  float radius_;
  std::vector<float> inverseCdf_;  // Gaussian: x(u) in [-radius, radius] at uniform u steps
};

}  // namespace glint
