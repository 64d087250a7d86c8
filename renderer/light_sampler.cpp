// glint — uniform and power light samplers (the BVH sampler is in light_bvh.cpp).
#include "renderer/light_sampler.h"

#include <algorithm>
#include <cmath>

#include "geometry/error.h"
#include "materials/phase.h"
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

DistantLightPicker::DistantLightPicker(const std::vector<std::unique_ptr<Light>>& lights,
                                       const std::vector<uint32_t>& indices) {
  for (uint32_t i : indices) entries_.push_back({i, lights[i]->distantImportance()});
}

float DistantLightPicker::weight(const Entry& e, const LightSampleContext& ctx) const {
  const Vec3f w = e.importance.towards;
  if (w.x == 0 && w.y == 0 && w.z == 0) return e.importance.irradiance;
  if (!ctx.onSurface()) {
    if (ctx.wo.x == 0 && ctx.wo.y == 0 && ctx.wo.z == 0) return e.importance.irradiance;
    // The phase function towards the light, relative to an isotropic one's 1 / (4 pi).
    return e.importance.irradiance * (4 * kPi) * henyeyGreenstein(dot(ctx.wo, w), ctx.g);
  }
  const float cosine = std::max(std::abs(dot(ctx.n, w)), std::abs(dot(ctx.ns, w)));
  return e.importance.irradiance * cosine;
}

std::optional<SampledLight> DistantLightPicker::sample(const LightSampleContext& ctx,
                                                       float u) const {
  if (entries_.size() == 1) return SampledLight{entries_[0].light, 1};
  // Few lights (a sun and a sky): the weights are summed afresh rather than kept in a table.
  float total = 0;
  for (const Entry& e : entries_) total += weight(e, ctx);
  if (!(total > 0)) return std::nullopt;
  float target = u * total;
  const Entry* last = nullptr;  // the last with weight: it takes what rounding leaves over
  float lastWeight = 0;
  for (const Entry& e : entries_) {
    const float w = weight(e, ctx);
    if (!(w > 0)) continue;
    if (target < w) return SampledLight{e.light, w / total};
    target -= w;
    last = &e, lastWeight = w;
  }
  return SampledLight{last->light, lastWeight / total};
}

float DistantLightPicker::pmf(const LightSampleContext& ctx, uint32_t index) const {
  if (entries_.size() == 1) return entries_[0].light == index ? 1.0f : 0.0f;
  float total = 0, mine = 0;
  for (const Entry& e : entries_) {
    const float w = weight(e, ctx);
    total += w;
    if (e.light == index) mine = w;
  }
  return total > 0 ? mine / total : 0.0f;
}

PowerLightSampler::PowerLightSampler(const std::vector<std::unique_ptr<Light>>& lights) {
  std::vector<float> weights;
  std::vector<uint32_t> distant;
  float distantPower = 0;
  entryOf_.resize(lights.size());
  for (uint32_t i = 0; i < lights.size(); ++i) {
    const float power = luminance(lights[i]->phi());
    const LightKind kind = lights[i]->kind();
    if (kind == LightKind::Infinite || kind == LightKind::DeltaDirection) {
      if (distantEntry_ == ~0u) {
        distantEntry_ = uint32_t(weights.size());
        weights.push_back(0);
        lightOf_.push_back(~0u);
      }
      entryOf_[i] = distantEntry_;
      distant.push_back(i);
      if (std::isfinite(power) && power > 0) distantPower += power;
      continue;
    }
    entryOf_[i] = uint32_t(weights.size());
    weights.push_back(power);
    lightOf_.push_back(i);
  }
  if (distantEntry_ != ~0u) {
    weights[distantEntry_] = distantPower;
    // One light at infinity is its entry's light, and nothing is left to pick.
    if (distant.size() == 1) lightOf_[distantEntry_] = distant[0], distantEntry_ = ~0u;
  }
  distribution_ = DiscreteDistribution(weights);
  distant_ = DistantLightPicker(lights, distant);
}

std::optional<SampledLight> PowerLightSampler::sample(const LightSampleContext& ctx,
                                                      float u) const {
  if (distribution_.size() == 0) return std::nullopt;
  float p = 0, v = 0;
  const uint32_t entry =
      distantEntry_ == ~0u ? distribution_.sample(u, &p) : distribution_.sample(u, &p, &v);
  if (!(p > 0)) return std::nullopt;
  if (entry != distantEntry_) return SampledLight{lightOf_[entry], p};
  std::optional<SampledLight> picked = distant_.sample(ctx, v);
  if (picked) picked->p *= p;
  return picked;
}

float PowerLightSampler::pmf(const LightSampleContext& ctx, uint32_t index) const {
  if (index >= entryOf_.size()) return 0;
  const float p = distribution_.pmf(entryOf_[index]);
  return entryOf_[index] == distantEntry_ ? p * distant_.pmf(ctx, index) : p;
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
