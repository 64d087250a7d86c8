// Light samplers: probabilities sum to 1, sampling frequencies match them, and the power
// sampler weighs area lights by their power.
#include "renderer/light_sampler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "geometry/shapes/quad.h"
#include "geometry/shapes/sphere.h"
#include "materials/phase.h"
#include "renderer/area_lights.h"
#include "renderer/light.h"

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
  lights.push_back(makeShapeLight(
      std::make_unique<Quad>(Vec3f{0, 1, 0}, Vec3f{1, 0, 0}, Vec3f{0, 0, 1}), {}, dim));
  lights.push_back(makeShapeLight(
      std::make_unique<Quad>(Vec3f{0, 1, 0}, Vec3f{2, 0, 0}, Vec3f{0, 0, 1}), {}, bright));
  lights.push_back(makeShapeLight(std::make_unique<Sphere>(Vec3f{0, 3, 0}, 0.5f), {}, dim));
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

// Frequencies of sample(ctx, ·) over a fine grid of u against pmf(ctx, ·), and the sum of pmf.
void expectFrequenciesMatchPmf(const LightSampler& sampler, const LightSampleContext& ctx,
                               size_t lights) {
  std::vector<int> counts(lights, 0);
  constexpr int kN = 100'000;
  double sum = 0;
  for (uint32_t i = 0; i < lights; ++i) sum += sampler.pmf(ctx, i);
  EXPECT_NEAR(sum, 1.0, 1e-5);
  for (int i = 0; i < kN; ++i) {
    auto s = sampler.sample(ctx, (float(i) + 0.5f) / kN);
    ASSERT_TRUE(s.has_value());
    EXPECT_NEAR(s->p, sampler.pmf(ctx, s->index), 1e-6f);
    ++counts[s->index];
  }
  for (uint32_t i = 0; i < lights; ++i)
    EXPECT_NEAR(counts[i] / double(kN), sampler.pmf(ctx, i), 1e-3) << "light " << i;
}

// A sun and a sky: picked by the irradiance each gives the receiving point (the sun's times its
// cosine with the surface), not by power through the scene's disk, which weighs a sky by its
// radiance over the whole sphere (4 pi L) and left the sun of scenes/volumes' cloud 39% of the
// samples. Local lights keep their share by power.
TEST(PowerLightSampler, PicksASunAndASkyByTheirIrradianceAtThePoint) {
  for (const char* name : {"power", "bvh"}) {
    SCOPED_TRACE(name);
    for (bool withLocal : {false, true}) {
      SCOPED_TRACE(withLocal);
      std::vector<std::unique_ptr<Light>> lights;
      // Irradiance 3 from 60 degrees off the vertical; a sky of radiance 0.5 (pi/2 on a surface).
      const Vec3f towards = normalize(Vec3f{std::sqrt(3.0f), 1, 0});
      lights.push_back(std::make_unique<DirectionalLight>(-towards, Rgb{3, 3, 3}, true));
      lights.push_back(std::make_unique<UniformEnvironmentLight>(Rgb{0.5f, 0.5f, 0.5f}));
      if (withLocal) {
        AreaEmission e;
        e.radiance = {2, 2, 2};
        lights.push_back(makeShapeLight(std::make_unique<Sphere>(Vec3f{0, 3, 0}, 0.5f), {}, e));
      }
      for (auto& l : lights) l->preprocess(Bounds3f{{-6, 0, -6}, {6, 6, 6}});
      auto sampler = makeLightSampler(name, lights);
      LightSampleContext up, medium, facing;
      up.n = up.ns = {0, 1, 0};        // a floor: the sun's cosine is 1/2
      facing.n = facing.ns = towards;  // a wall facing the sun
      medium.p = up.p = facing.p = {0, 1, 0};
      const double sky = kPi * 0.5;
      // The lights at infinity share what they had before among themselves.
      const double share = sampler->pmf(medium, 0) + sampler->pmf(medium, 1);
      EXPECT_NEAR(sampler->pmf(up, 0) / share, 1.5 / (1.5 + sky), 1e-5);
      EXPECT_NEAR(sampler->pmf(facing, 0) / share, 3 / (3 + sky), 1e-5);
      EXPECT_NEAR(sampler->pmf(medium, 0) / share, 3 / (3 + sky), 1e-5);
      EXPECT_NEAR(sampler->pmf(up, 1) / share, sky / (1.5 + sky), 1e-5);
      if (!withLocal) {
        EXPECT_NEAR(share, 1, 1e-6);
      }
      for (const LightSampleContext& ctx : {up, medium, facing})
        expectFrequenciesMatchPmf(*sampler, ctx, lights.size());
      // In a medium, the sun weighed by the phase function towards it when the context gives
      // the path's direction: 10x an isotropic one's for a path heading into the sun, 0.156x for
      // one heading away from it (g = 0.6).
      for (float heading : {1.0f, -1.0f}) {
        const LightSampleContext c =
            LightSampleContext::inMedium({0, 1, 0}, 0, towards * heading, 0.6f);
        const double sun = 3 * 4 * kPi * henyeyGreenstein(heading, 0.6f);
        EXPECT_NEAR(sun / 3, heading > 0 ? 10 : 0.15625, 1e-3);
        EXPECT_NEAR(sampler->pmf(c, 0) / share, sun / (sun + sky), 1e-5);
        expectFrequenciesMatchPmf(*sampler, c, lights.size());
      }
      // A surface that the sun reaches only edge-on still gets the sky.
      LightSampleContext edgeOn;
      edgeOn.n = edgeOn.ns = normalize(Vec3f{-1, std::sqrt(3.0f), 0});
      EXPECT_NEAR(sampler->pmf(edgeOn, 0), 0, 1e-6);
      EXPECT_GT(sampler->pmf(edgeOn, 1), 0);
    }
  }
}

}  // namespace
}  // namespace glint

// --- Light BVH -----------------------------------------------------------------------------------

namespace glint {
namespace {

// Many small lights of different kinds, powers and orientations, plus unbounded lights.
std::vector<std::unique_ptr<Light>> manyLights(bool withInfinite) {
  std::vector<std::unique_ptr<Light>> lights;
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> uni(-5.0f, 5.0f), pos(0.5f, 4.0f);
  for (int i = 0; i < 40; ++i) {
    const Vec3f p{uni(rng), pos(rng) + 1, uni(rng)};
    switch (i % 4) {
      case 0:
        lights.push_back(std::make_unique<PointLight>(p, Rgb{pos(rng), 1, 1}, 0, true));
        break;
      case 1:
        lights.push_back(std::make_unique<SpotLight>(p, Vec3f{uni(rng), -3, uni(rng)}, Rgb{2, 2, 2},
                                                     0.2f, 0.6f, 0, true));
        break;
      case 2: {
        AreaEmission e;
        e.radiance = {pos(rng), pos(rng), 1};
        e.twoSided = i % 8 == 2;
        lights.push_back(makeShapeLight(
            std::make_unique<Quad>(p, Vec3f{0.5f, 0, 0}, Vec3f{0, 0.1f, 0.5f}), {}, e));
        break;
      }
      default: {
        AreaEmission e;
        e.radiance = {1, pos(rng), 1};
        lights.push_back(makeShapeLight(std::make_unique<Sphere>(p, 0.2f), {}, e));
      }
    }
  }
  if (withInfinite) {
    lights.push_back(std::make_unique<DirectionalLight>(Vec3f{0, -1, 0.3f}, Rgb{1, 1, 1}, true));
    lights.push_back(std::make_unique<UniformEnvironmentLight>(Rgb{0.2f, 0.2f, 0.2f}));
  }
  for (auto& l : lights) l->preprocess(Bounds3f{{-6, 0, -6}, {6, 6, 6}});
  return lights;
}

TEST(BvhLightSampler, PmfMatchesFrequencies) {
  for (bool withInfinite : {false, true}) {
    SCOPED_TRACE(withInfinite);
    const auto lights = manyLights(withInfinite);
    auto sampler = makeLightSampler("bvh", lights);
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> uni(-4.0f, 4.0f);
    for (int c = 0; c < 6; ++c) {
      LightSampleContext ctx;
      ctx.p = {uni(rng), c % 2 ? 0.0f : 3.0f, uni(rng)};
      if (c % 3 != 2) ctx.n = ctx.ns = normalize(Vec3f{uni(rng) * 0.2f, 1, uni(rng) * 0.2f});
      double sum = 0;
      for (uint32_t i = 0; i < lights.size(); ++i) sum += sampler->pmf(ctx, i);
      // Below 1 only by the mass of leaves that cannot light the point (a one-sided light
      // facing away): there the sampler returns no light, as often as that mass says.
      EXPECT_LE(sum, 1.0 + 1e-4) << "context " << c;
      EXPECT_GT(sum, 0.5) << "context " << c;
      std::vector<int> counts(lights.size(), 0);
      constexpr int kN = 100'000;
      int found = 0;
      for (int i = 0; i < kN; ++i) {
        auto s = sampler->sample(ctx, (float(i) + 0.5f) / kN);
        if (!s) continue;
        ++found;
        EXPECT_NEAR(s->p, sampler->pmf(ctx, s->index), 1e-5f * s->p);
        ++counts[s->index];
      }
      EXPECT_NEAR(found / double(kN), sum, 1e-3);
      for (uint32_t i = 0; i < lights.size(); ++i)
        EXPECT_NEAR(counts[i] / double(kN), sampler->pmf(ctx, i), 2e-3) << "light " << i;
    }
  }
}

TEST(BvhLightSampler, NeverIgnoresALightThatReachesThePoint) {
  // Unbiasedness needs a non-zero probability for every light that can light the point.
  const auto lights = manyLights(true);
  auto sampler = makeLightSampler("bvh", lights);
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> uni(-4.0f, 4.0f), unit(0.0f, 0.999f);
  for (int c = 0; c < 50; ++c) {
    LightSampleContext ctx;
    ctx.p = {uni(rng), 0, uni(rng)};
    ctx.n = ctx.ns = {0, 1, 0};
    for (uint32_t i = 0; i < lights.size(); ++i) {
      bool reaches = false;
      for (int k = 0; k < 16 && !reaches; ++k)
        if (auto ls = lights[i]->sampleLi(ctx, {unit(rng), unit(rng)}))
          reaches = dot(ls->wi, ctx.n) > 0 && (ls->L.x > 0 || ls->L.y > 0 || ls->L.z > 0);
      if (reaches) {
        EXPECT_GT(sampler->pmf(ctx, i), 0) << "light " << i << " at context " << c;
      }
    }
  }
}

TEST(BvhLightSampler, IsNamed) {
  const auto& names = lightSamplerNames();
  EXPECT_NE(std::find(names.begin(), names.end(), "bvh"), names.end());
}

}  // namespace
}  // namespace glint
