// glint — light samplers: which light a shading point asks for light, with what probability.
//
// Next-event estimation takes one light per shading point; the sampler picks it in proportion
// to an estimate of what it contributes there. Every sampler is unbiased as long as a light
// that can contribute has a non-zero probability; they differ in variance and cost:
//   uniform — every light alike (for tests and as a baseline);
//   power   — in proportion to emitted power, ignoring where the point is;
//   bvh     — a hierarchy over the lights' bounds, judged from the point (for many lights).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "renderer/light.h"

namespace glint {

struct SampledLight {
  uint32_t index = 0;  // into the scene's lights
  float p = 0;         // the probability it was picked with
};

class LightSampler {
 public:
  virtual ~LightSampler() = default;
  // Picks a light for the receiving point with a uniform number `u`; nullopt when no light
  // can contribute there.
  virtual std::optional<SampledLight> sample(const LightSampleContext& ctx, float u) const = 0;
  // The probability that sample(ctx, ·) picks light `index` (for MIS when a ray finds it).
  virtual float pmf(const LightSampleContext& ctx, uint32_t index) const = 0;
};

// A discrete distribution over weights (a CDF searched by bisection).
class DiscreteDistribution {
 public:
  DiscreteDistribution() = default;
  // Weights must be finite and >= 0; if they are all 0, every entry gets the same weight.
  explicit DiscreteDistribution(const std::vector<float>& weights);
  size_t size() const { return pmf_.size(); }
  // The entry for u in [0, 1), with its probability.
  uint32_t sample(float u, float* p) const;
  // The same, also returning u rescaled to [0, 1) within the entry (to reuse it).
  uint32_t sample(float u, float* p, float* uRemapped) const;
  float pmf(uint32_t i) const { return i < pmf_.size() ? pmf_[i] : 0; }

 private:
  std::vector<double> cdf_;  // cdf_[i] = sum of pmf_[0 .. i-1]; size n + 1
  std::vector<float> pmf_;
};

class UniformLightSampler final : public LightSampler {
 public:
  explicit UniformLightSampler(size_t lightCount) : count_(uint32_t(lightCount)) {}
  std::optional<SampledLight> sample(const LightSampleContext& ctx, float u) const override;
  float pmf(const LightSampleContext& ctx, uint32_t index) const override;

 private:
  uint32_t count_;
};

class PowerLightSampler final : public LightSampler {
 public:
  // Lights must have been preprocessed (infinite lights report power for the scene's size).
  explicit PowerLightSampler(const std::vector<std::unique_ptr<Light>>& lights);
  std::optional<SampledLight> sample(const LightSampleContext& ctx, float u) const override;
  float pmf(const LightSampleContext& ctx, uint32_t index) const override;

 private:
  DiscreteDistribution distribution_;
};

// The sampler called `name` ("uniform", "power"); throws InputError otherwise.
std::unique_ptr<LightSampler> makeLightSampler(const std::string& name,
                                               const std::vector<std::unique_ptr<Light>>& lights);
// The names makeLightSampler accepts.
const std::vector<std::string>& lightSamplerNames();

}  // namespace glint
