// glint — filter importance sampling.
#include "renderer/filter.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace glint {

namespace {
constexpr int kGaussianTableSize = 256;
}

PixelFilter::PixelFilter(const FilterSettings& s) : radius_(s.radius) {
  if (!(s.radius > 0) || !std::isfinite(s.radius))
    throw std::invalid_argument("filter radius must be > 0");
  if (s.type == "box") {
    kind_ = Kind::Box;
  } else if (s.type == "tent") {
    kind_ = Kind::Tent;
  } else if (s.type == "gaussian") {
    kind_ = Kind::Gaussian;
    // Gaussian with sigma = radius / 3, minus its value at the radius so it reaches zero there
    // (as pbrt does); tabulated CDF, inverted by linear interpolation.
    double sigma = radius_ / 3.0;
    auto g = [&](double x) { return std::exp(-x * x / (2 * sigma * sigma)); };
    double edge = g(radius_);
    cdf_.resize(kGaussianTableSize + 1);
    cdf_[0] = 0;
    double sum = 0;
    for (int i = 0; i < kGaussianTableSize; ++i) {
      double x = -radius_ + (i + 0.5) * 2.0 * radius_ / kGaussianTableSize;
      sum += std::max(0.0, g(x) - edge);
      cdf_[size_t(i) + 1] = float(sum);
    }
    for (float& c : cdf_) c = float(c / sum);
  } else {
    throw std::invalid_argument("unknown filter '" + s.type + "' (box, tent, gaussian)");
  }
}

float PixelFilter::sample1D(float u) const {
  switch (kind_) {
    case Kind::Box: return (2 * u - 1) * radius_;
    case Kind::Tent:
      return u < 0.5f ? radius_ * (std::sqrt(2 * u) - 1) : radius_ * (1 - std::sqrt(2 - 2 * u));
    case Kind::Gaussian:
    default: {
      auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
      size_t i = size_t(std::clamp<std::ptrdiff_t>(it - cdf_.begin() - 1, 0, kGaussianTableSize - 1));
      float c0 = cdf_[i], c1 = cdf_[i + 1];
      float t = c1 > c0 ? (u - c0) / (c1 - c0) : 0.5f;
      float x = (float(i) + t) / kGaussianTableSize;  // in [0, 1]
      return (2 * x - 1) * radius_;
    }
  }
}

}  // namespace glint
