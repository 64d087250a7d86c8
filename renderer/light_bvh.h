// glint — the light BVH sampler ("bvh"): a hierarchy over the lights' bounds, descended from
// the receiving point by an importance estimated from each node's bounds (pbrt-v4's
// BVHLightSampler idea: power, distance, the cone of emission and the receiver's normal).
// Lights without bounds (directional, environment) are sampled beside the tree, together with
// as many times the whole tree's probability as there are of them, and DistantLightPicker
// chooses among them. A descent that ends at a light which cannot reach the
// point (a one-sided emitter facing away) returns no light, so the pmf over all lights sums
// to at most 1: the rest is the probability of sampling nothing, which is unbiased.
#pragma once

#include <vector>

#include "renderer/light_sampler.h"

namespace glint {

class BvhLightSampler final : public LightSampler {
 public:
  // Lights must have been preprocessed.
  explicit BvhLightSampler(const std::vector<std::unique_ptr<Light>>& lights);
  std::optional<SampledLight> sample(const LightSampleContext& ctx, float u) const override;
  float pmf(const LightSampleContext& ctx, uint32_t index) const override;

 private:
  struct Node {
    LightBounds bounds;
    uint32_t child1 = 0;  // interior: the second child (the first follows the node)
    uint32_t light = 0;   // leaf: the light's index
    bool leaf = false;
  };
  uint32_t build(std::vector<std::pair<uint32_t, LightBounds>>& items, size_t begin, size_t end,
                 uint64_t trail, int depth);
  // The probability of descending into the first child, or -1 when neither child matters.
  float firstChildProbability(const Node& node, const LightSampleContext& ctx) const;

  std::vector<Node> nodes_;
  std::vector<uint32_t> infinite_;  // lights sampled beside the tree
  DistantLightPicker distant_;      // picks among them
  // Per light: its path from the root (bit d = took the second child at depth d), or
  // kInfinite for lights beside the tree.
  std::vector<uint64_t> trails_;
  std::vector<uint8_t> depths_;
  static constexpr uint64_t kInfinite = ~0ull;
};

// The importance of lights bounded by `b` for a receiving point (0: they cannot light it).
float lightBoundsImportance(const LightBounds& b, const LightSampleContext& ctx);
// The smallest bounds holding a and b.
LightBounds unionOf(const LightBounds& a, const LightBounds& b);

}  // namespace glint
