// glint — uniform and power light samplers (the BVH sampler is in light_bvh.cpp).
#include "renderer/light_sampler.h"

#include <algorithm>
#include <cmath>

#include "geometry/error.h"
#include "renderer/light_bvh.h"

namespace glint {

DiscreteDistribution::DiscreteDistribution(const std::vector<float>& weights) {
  const size_t n = weights.size();
  double total = 0;
  for (float w : weights) total += (std::isfinite(w) && w > 0) ? double(w) : 0.0;
  pmf_.resize(n);
  cdf_.resize(n + 1);
  cdf_[0] = 0;
  for (size_t i = 0; i < n; ++i) {
    const double w =
        total > 0 ? ((std::isfinite(weights[i]) && weights[i] > 0) ? weights[i] : 0.0) : 1.0;
    const double p = w / (total > 0 ? total : double(n));
    pmf_[i] = float(p);
    cdf_[i + 1] = cdf_[i] + p;
  }
  if (n > 0) cdf_[n] = 1;
}

uint32_t DiscreteDistribution::sample(float u, float* p) const {
  // The last entry whose cdf is <= u, skipping entries of probability zero.
  const auto it = std::upper_bound(cdf_.begin() + 1, cdf_.end(), double(u));
  size_t i = size_t(it - cdf_.begin()) - 1;
  i = std::min(i, pmf_.size() - 1);
  while (pmf_[i] == 0 && i > 0) --i;  // u landed exactly on a boundary before a zero entry
  *p = pmf_[i];
  return uint32_t(i);
}

uint32_t DiscreteDistribution::sample(float u, float* p, float* uRemapped) const {
  const uint32_t i = sample(u, p);
  const double within = *p > 0 ? (double(u) - cdf_[i]) / double(*p) : 0.0;
  *uRemapped = float(std::clamp(within, 0.0, double(0x1.fffffep-1)));
  return i;
}

std::optional<SampledLight> UniformLightSampler::sample(const LightSampleContext&, float u) const {
  if (count_ == 0) return std::nullopt;
  const uint32_t i = std::min(uint32_t(u * float(count_)), count_ - 1);
  return SampledLight{i, 1.0f / float(count_)};
}

float UniformLightSampler::pmf(const LightSampleContext&, uint32_t index) const {
  return index < count_ ? 1.0f / float(count_) : 0.0f;
}

PowerLightSampler::PowerLightSampler(const std::vector<std::unique_ptr<Light>>& lights) {
  std::vector<float> weights;
  weights.reserve(lights.size());
  for (const auto& l : lights) weights.push_back(luminance(l->phi()));
  distribution_ = DiscreteDistribution(weights);
}

std::optional<SampledLight> PowerLightSampler::sample(const LightSampleContext&, float u) const {
  if (distribution_.size() == 0) return std::nullopt;
  float p = 0;
  const uint32_t i = distribution_.sample(u, &p);
  if (!(p > 0)) return std::nullopt;
  return SampledLight{i, p};
}

float PowerLightSampler::pmf(const LightSampleContext&, uint32_t index) const {
  return distribution_.pmf(index);
}

const std::vector<std::string>& lightSamplerNames() {
  static const std::vector<std::string> names = {"uniform", "power", "bvh"};
  return names;
}

std::unique_ptr<LightSampler> makeLightSampler(const std::string& name,
                                               const std::vector<std::unique_ptr<Light>>& lights) {
  if (name == "uniform") return std::make_unique<UniformLightSampler>(lights.size());
  if (name == "power") return std::make_unique<PowerLightSampler>(lights);
  if (name == "bvh") return std::make_unique<BvhLightSampler>(lights);
  throw InputError("unknown light sampler '" + name + "' (uniform, power, bvh)");
}

}  // namespace glint
