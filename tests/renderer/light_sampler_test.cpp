// Light samplers: probabilities sum to 1, sampling frequencies match them, and the power
// sampler weighs area lights by their power.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "renderer/area_lights.h"
#include "renderer/light_sampler.h"

namespace glint {
namespace {

TEST(DiscreteDistribution, FrequenciesMatchThePmf) {
  const std::vector<float> w = {3, 0, 1, 6, 0.5f, 0};
  DiscreteDistribution d(w);
  double sum = 0;
  for (uint32_t i = 0; i < d.size(); ++i) sum += d.pmf(i);
  EXPECT_NEAR(sum, 1.0, 1e-6);
  EXPECT_EQ(d.pmf(1), 0);
  std::vector<int> counts(w.size(), 0);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> uni(0.0f, 0.999999f);
  constexpr int kN = 200'000;
  double remappedMean = 0;
  for (int i = 0; i < kN; ++i) {
    float p = 0, r = 0;
    const uint32_t k = d.sample(uni(rng), &p, &r);
    ASSERT_GT(p, 0);
    EXPECT_EQ(p, d.pmf(k));
    ASSERT_GE(r, 0);
    ASSERT_LT(r, 1);
    remappedMean += r;
    ++counts[k];
  }
  for (size_t i = 0; i < w.size(); ++i) {
    const double p = d.pmf(uint32_t(i));
    EXPECT_NEAR(counts[i] / double(kN), p, 5 * std::sqrt(p * (1 - p) / kN) + 1e-9) << i;
  }
  // The remapped number is uniform again: mean 1/2.
  EXPECT_NEAR(remappedMean / kN, 0.5, 0.005);
}

TEST(PowerLightSampler, PicksAreaLightsByPower) {
  std::vector<std::unique_ptr<Light>> lights;
  AreaEmission dim, bright;
  dim.radiance = {1, 1, 1};
  bright.radiance = {3, 3, 3};
  lights.push_back(std::make_unique<QuadLight>(Vec3f{0, 1, 0}, Vec3f{1, 0, 0}, Vec3f{0, 0, 1}, dim));
  lights.push_back(std::make_unique<QuadLight>(Vec3f{0, 1, 0}, Vec3f{2, 0, 0}, Vec3f{0, 0, 1}, bright));
  lights.push_back(std::make_unique<SphereLight>(Vec3f{0, 3, 0}, 0.5f, dim));
  auto sampler = makeLightSampler("power", lights);
  LightSampleContext ctx;
  // Powers: pi * 1 * 1, pi * 3 * 2, pi * 1 * 4 pi 0.25 = pi^2.
  const double p0 = kPi, p1 = 6 * kPi, p2 = kPi * kPi, total = p0 + p1 + p2;
  EXPECT_NEAR(sampler->pmf(ctx, 0), p0 / total, 1e-4);
  EXPECT_NEAR(sampler->pmf(ctx, 1), p1 / total, 1e-4);
  EXPECT_NEAR(sampler->pmf(ctx, 2), p2 / total, 1e-4);
  std::vector<int> counts(3, 0);
  constexpr int kN = 100'000;
  for (int i = 0; i < kN; ++i) {
    auto s = sampler->sample(ctx, (float(i) + 0.5f) / kN);
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(s->p, sampler->pmf(ctx, s->index));
    ++counts[s->index];
  }
  for (uint32_t i = 0; i < 3; ++i) EXPECT_NEAR(counts[i] / double(kN), sampler->pmf(ctx, i), 1e-3);
}

}  // namespace
}  // namespace glint
