// Tests for Russian roulette (renderer/roulette.h), the one rule the path tracer and instant
// radiosity's light paths end their paths by.
#include "renderer/roulette.h"

#include <gtest/gtest.h>

#include <cmath>

namespace glint {
namespace {

TEST(RussianRoulette, PathsShorterThanRrDepthAlwaysGoOnUnchanged) {
  for (int bounce = 0; bounce < 3; ++bounce) {
    Rgb beta{1e-3f, 2e-3f, 0};
    EXPECT_TRUE(survivesRoulette(bounce, 3, 1, 0.999f, &beta)) << bounce;
    EXPECT_EQ(beta, (Rgb{1e-3f, 2e-3f, 0}));
  }
  Rgb beta{1e-3f, 2e-3f, 0};
  EXPECT_FALSE(survivesRoulette(3, 3, 1, 0.999f, &beta));
}

TEST(RussianRoulette, BrightPathsAreNeverCut) {
  for (float u : {0.0f, 0.5f, 0.999f}) {
    Rgb beta{0.1f, 1.0f, 0.3f};
    EXPECT_TRUE(survivesRoulette(10, 1, 1, u, &beta)) << u;
    EXPECT_EQ(beta, (Rgb{0.1f, 1.0f, 0.3f}));
  }
}

// The expectation over u is the throughput itself: the survivors carry 1 / survival.
TEST(RussianRoulette, KeepsTheExpectation) {
  const Rgb beta0{0.2f, 0.1f, 0.05f};
  constexpr int kN = 10000;
  Rgb sum;
  int survivors = 0;
  for (int i = 0; i < kN; ++i) {
    Rgb beta = beta0;
    if (!survivesRoulette(1, 1, 1, (float(i) + 0.5f) / kN, &beta)) continue;
    ++survivors;
    sum += beta;
  }
  // survival = the square root of the largest component, 0.2
  EXPECT_NEAR(survivors, kN * std::sqrt(0.2f), 1);
  // Up to one stratum of u: the chance is not a multiple of 1 / kN.
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(sum[c] / kN, beta0[c], beta0[c] / (kN * std::sqrt(0.2f))) << c;
}

TEST(RussianRoulette, BoostsDimPathsAtMostTwentyTimes) {
  Rgb beta{1e-4f, 0, 0};
  EXPECT_TRUE(survivesRoulette(5, 1, 1, 0.01f, &beta));
  EXPECT_FLOAT_EQ(beta.x, 2e-3f);
  Rgb cut{1e-4f, 0, 0};
  EXPECT_FALSE(survivesRoulette(5, 1, 1, 0.05f, &cut));
}

// Refraction divides radiance by eta^2, which says nothing about how much the path will carry
// on: the chance is taken on beta times etaScale.
TEST(RussianRoulette, UndoesTheRefractionScaleForTheChance) {
  Rgb inGlass{0.4f, 0.4f, 0.4f};  // 0.9 before the 1/1.5^2 of entering glass
  EXPECT_TRUE(survivesRoulette(5, 1, 2.25f, 0.7f, &inGlass));  // chance sqrt(0.9) = 0.95
  EXPECT_FLOAT_EQ(inGlass.x, 0.4f / std::sqrt(0.9f));
  Rgb plain{0.4f, 0.4f, 0.4f};
  EXPECT_FALSE(survivesRoulette(5, 1, 1, 0.7f, &plain));  // chance sqrt(0.4) = 0.63
}

}  // namespace
}  // namespace glint
