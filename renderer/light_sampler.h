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

// Picks among the lights at infinity (directional and environment lights) for a receiving
// point, each in proportion to what it gives there unshadowed, as irradiance (Light::
// distantImportance): a directional light's scaled by its cosine with the surface (the larger
// of the geometric and the shading normal's, so a light that can reach the shading normal is
// never left out) or, in a medium, by the phase function towards it over an isotropic one's
// (1 where the context does not say); an environment's by none.
// Why not their power, as for other lights: a light at infinity has no power of its own, only
// one through some disk, and the power sampler's disk weighs an environment by its radiance
// over the whole sphere (4 pi L), four times what a surface under it receives (pi L). A sun and
// a sky picked that way left the sun, which lights most of a cloud, 39% of the samples: the
// cloud of scenes/volumes has 1.56x less variance picked by irradiance, 1.69x with the phase
// function (benchmarks/README, issue 52).
class DistantLightPicker {
 public:
  DistantLightPicker() = default;
  // `indices`: the lights of `lights` to pick among (preprocessed).
  DistantLightPicker(const std::vector<std::unique_ptr<Light>>& lights,
                     const std::vector<uint32_t>& indices);
  size_t size() const { return entries_.size(); }
  // One of them for `ctx` with u in [0, 1), with its probability among them; nullopt when
  // none gives `ctx` any light.
  std::optional<SampledLight> sample(const LightSampleContext& ctx, float u) const;
  // The probability that sample(ctx, ·) picks the light `index` of the scene (0 for lights
  // not among them).
  float pmf(const LightSampleContext& ctx, uint32_t index) const;

 private:
  struct Entry {
    uint32_t light;
    DistantImportance importance;
  };
  float weight(const Entry& e, const LightSampleContext& ctx) const;
  std::vector<Entry> entries_;
};

class UniformLightSampler final : public LightSampler {
 public:
  explicit UniformLightSampler(size_t lightCount) : count_(uint32_t(lightCount)) {}
  std::optional<SampledLight> sample(const LightSampleContext& ctx, float u) const override;
  float pmf(const LightSampleContext& ctx, uint32_t index) const override;

 private:
  uint32_t count_;
};

// Lights in proportion to their power; the lights at infinity together get the share of their
// powers added (through a disk of the scene's size), and DistantLightPicker chooses among them.
class PowerLightSampler final : public LightSampler {
 public:
  // Lights must have been preprocessed (infinite lights report power for the scene's size).
  explicit PowerLightSampler(const std::vector<std::unique_ptr<Light>>& lights);
  std::optional<SampledLight> sample(const LightSampleContext& ctx, float u) const override;
  float pmf(const LightSampleContext& ctx, uint32_t index) const override;

 private:
  // Over the lights, the lights at infinity all standing at the entry `distantEntry_` (none,
  // ~0u, when there are fewer than two: a single one is an entry like any light).
  DiscreteDistribution distribution_;
  std::vector<uint32_t> entryOf_;  // per light: its entry
  std::vector<uint32_t> lightOf_;  // per entry: its light (the distant entry: unused)
  DistantLightPicker distant_;
  uint32_t distantEntry_ = ~0u;
};

// The sampler called `name` ("uniform", "power"); throws InputError otherwise.
std::unique_ptr<LightSampler> makeLightSampler(const std::string& name,
                                               const std::vector<std::unique_ptr<Light>>& lights);
// The names makeLightSampler accepts.
const std::vector<std::string>& lightSamplerNames();

}  // namespace glint
