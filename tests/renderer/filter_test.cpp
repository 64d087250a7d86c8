// Tests for importance-sampled pixel filters: support and moments.
#include "renderer/filter.h"

#include <gtest/gtest.h>

#include "geometry/error.h"

namespace glint {
namespace {

// Mean and variance of the offsets over a stratified set of samples.
void moments(const PixelFilter& f, double* mean, double* var, float* maxAbs) {
  const uint32_t n = 4096;
  double s = 0, s2 = 0;
  *maxAbs = 0;
  for (uint32_t i = 0; i < n; ++i) {
    float u = (float(i) + 0.5f) / float(n);  // stratified: exact moments up to O(1/n^2)
    Vec2f o = f.sampleOffset({u, u});
    s += o.x, s2 += double(o.x) * o.x;
    *maxAbs = std::max(*maxAbs, std::max(std::abs(o.x), std::abs(o.y)));
  }
  *mean = s / n;
  *var = s2 / n - *mean * *mean;
}

TEST(PixelFilter, BoxIsUniformOverItsRadius) {
  PixelFilter f({"box", 0.5f});
  double mean, var;
  float maxAbs;
  moments(f, &mean, &var, &maxAbs);
  EXPECT_NEAR(mean, 0, 1e-3);
  EXPECT_NEAR(var, 0.25 / 3, 1e-3);  // (2r)^2 / 12
  EXPECT_LE(maxAbs, 0.5f);
}

TEST(PixelFilter, TentHasTheTriangleVariance) {
  PixelFilter f({"tent", 1.0f});
  double mean, var;
  float maxAbs;
  moments(f, &mean, &var, &maxAbs);
  EXPECT_NEAR(mean, 0, 1e-3);
  EXPECT_NEAR(var, 1.0 / 6, 2e-3);  // r^2 / 6
  EXPECT_LE(maxAbs, 1.0f);
}

TEST(PixelFilter, GaussianStaysWithinRadiusWithSigmaNearRadiusOverThree) {
  PixelFilter f({"gaussian", 1.5f});
  double mean, var;
  float maxAbs;
  moments(f, &mean, &var, &maxAbs);
  EXPECT_NEAR(mean, 0, 2e-3);
  EXPECT_LE(maxAbs, 1.5f);
  // The truncated, shifted Gaussian is a little narrower than sigma = 0.5.
  EXPECT_GT(std::sqrt(var), 0.40);
  EXPECT_LT(std::sqrt(var), 0.50);
}

TEST(PixelFilter, RejectsUnknownTypesAndBadRadii) {
  EXPECT_THROW(PixelFilter({"mitchel", 1.0f}), InputError);
  EXPECT_THROW(PixelFilter({"box", 0.0f}), InputError);
  EXPECT_THROW(PixelFilter({"box", -1.0f}), InputError);
}

TEST(PixelFilter, FractionAndFloatSamplesAgreeBitForBit) {
  for (const char* type : {"box", "tent", "gaussian"}) {
    PixelFilter f({type, 1.5f});
    for (uint32_t i = 0; i < 100000; ++i) {
      // Spread over all 32-bit fractions, including the ends of the table.
      Fraction2 u{i * 42949u, 0xffffffffu - i * 7919u};
      Vec2f a = f.sampleOffsetFraction(u), b = f.sampleOffset(u.toFloat());
      ASSERT_EQ(a.x, b.x) << type << " " << u.x;
      ASSERT_EQ(a.y, b.y) << type << " " << u.y;
    }
  }
}

}  // namespace
}  // namespace glint
