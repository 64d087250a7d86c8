// glint — filter importance sampling.
#include "renderer/filter.h"

#include <algorithm>
#include <cmath>

#include "geometry/error.h"

namespace glint {

PixelFilter::PixelFilter(const FilterSettings& s) : radius_(s.radius) {
  if (!(s.radius > 0) || !std::isfinite(s.radius)) throw InputError("filter radius must be > 0");
  if (s.type == "box") {
    kind_ = Kind::Box;
  } else if (s.type == "tent") {
    kind_ = Kind::Tent;
  } else if (s.type == "gaussian") {
    kind_ = Kind::Gaussian;
    // Gaussian with sigma = radius / 3, minus its value at the radius so it reaches zero there
    // (as pbrt does).
    double sigma = radius_ / 3.0;
    auto g = [&](double x) { return std::exp(-x * x / (2 * sigma * sigma)); };
    double edge = g(radius_);
    std::vector<double> cdf(kCdfSize + 1, 0.0);
    for (int i = 0; i < kCdfSize; ++i) {
      double x = -radius_ + (i + 0.5) * 2.0 * radius_ / kCdfSize;
      cdf[size_t(i) + 1] = cdf[size_t(i)] + std::max(0.0, g(x) - edge);
    }
    for (double& c : cdf) c /= cdf.back();
    inverseCdf_.resize(kInverseSize + 1);
    size_t k = 0;
    for (int i = 0; i <= kInverseSize; ++i) {
      double u = double(i) / kInverseSize;
      while (k + 1 < size_t(kCdfSize) && cdf[k + 1] < u) ++k;
      double c0 = cdf[k], c1 = cdf[k + 1];
      double t = c1 > c0 ? std::clamp((u - c0) / (c1 - c0), 0.0, 1.0) : 0.5;
      inverseCdf_[size_t(i)] = float((2 * (double(k) + t) / kCdfSize - 1) * radius_);
    }
  } else {
    throw InputError("unknown filter '" + s.type + "' (box, tent, gaussian)");
  }
}

}  // namespace glint
