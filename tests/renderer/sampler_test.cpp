// Tests for addressed sampling: determinism, ranges, stratification.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "renderer/sampler.h"

namespace glint {
namespace {

TEST(Sampler, SameAddressGivesSameValues) {
  Sampler a(1234, 7, 16, 99), b(1234, 7, 16, 99);
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ(a.get1D(), b.get1D());
    Vec2f pa = a.get2D(), pb = b.get2D();
    EXPECT_EQ(pa.x, pb.x);
    EXPECT_EQ(pa.y, pb.y);
  }
}

TEST(Sampler, SeedPixelAndSampleChangeTheValues) {
  auto first = [](uint64_t px, uint32_t s, uint64_t seed) {
    Sampler smp(px, s, 16, seed);
    return smp.get2D();
  };
  Vec2f base = first(10, 3, 0);
  EXPECT_NE(base.x, first(11, 3, 0).x);
  EXPECT_NE(base.x, first(10, 4, 0).x);
  EXPECT_NE(base.x, first(10, 3, 1).x);
}

TEST(Sampler, PermuteIndexIsAPermutation) {
  for (uint32_t n : {1u, 2u, 3u, 7u, 16u, 100u, 1000u}) {
    for (uint32_t pattern : {0u, 1u, 0xdeadbeefu}) {
      std::set<uint32_t> seen;
      for (uint32_t i = 0; i < n; ++i) {
        uint32_t p = permuteIndex(i, n, pattern);
        ASSERT_LT(p, n);
        seen.insert(p);
      }
      EXPECT_EQ(seen.size(), n);
    }
  }
}

// Correlated multi-jittered samples are stratified in y (each of the n intervals
// [k/n, (k+1)/n) holds exactly one sample) and in x over the m*k >= n columns of its grid
// (at most one sample each; exactly one when n is m*k, e.g. a square), for any n.
TEST(Sampler, TwoDimensionalSamplesAreStratifiedForAnyCount) {
  for (uint32_t n : {1u, 2u, 5u, 16u, 17u, 64u, 100u}) {
    for (uint64_t pixel : {0ull, 77ull, 123456ull}) {
      uint32_t m = uint32_t(std::sqrt(double(n))), cols = m * ((n + m - 1) / m);
      std::vector<int> xs(cols, 0), ys(n, 0);
      for (uint32_t s = 0; s < n; ++s) {
        Sampler smp(pixel, s, n, 5);
        smp.get1D();  // a 1D dimension first, to exercise the dimension counter
        Vec2f p = smp.get2D();
        ASSERT_GE(p.x, 0.0f);
        ASSERT_LT(p.x, 1.0f);
        ASSERT_GE(p.y, 0.0f);
        ASSERT_LT(p.y, 1.0f);
        xs[std::min(cols - 1, uint32_t(p.x * float(cols)))]++;
        ys[std::min(n - 1, uint32_t(p.y * float(n)))]++;
      }
      for (uint32_t k = 0; k < cols; ++k) {
        if (cols == n)
          EXPECT_EQ(xs[k], 1) << "n=" << n << " x column " << k;
        else
          EXPECT_LE(xs[k], 1) << "n=" << n << " x column " << k;
      }
      for (uint32_t k = 0; k < n; ++k) EXPECT_EQ(ys[k], 1) << "n=" << n << " y stratum " << k;
    }
  }
}

TEST(Sampler, OneDimensionalSamplesAreStratified) {
  const uint32_t n = 37;
  std::vector<int> strata(n, 0);
  for (uint32_t s = 0; s < n; ++s) {
    Sampler smp(9, s, n, 0);
    float v = smp.get1D();
    ASSERT_GE(v, 0.0f);
    ASSERT_LT(v, 1.0f);
    strata[uint32_t(v * n)]++;
  }
  for (uint32_t k = 0; k < n; ++k) EXPECT_EQ(strata[k], 1);
}

TEST(Sampler, ValuesAreUniformAcrossPixels) {
  // Mean and variance of many independent pixels' first sample match U(0,1).
  double sum = 0, sum2 = 0;
  const int count = 100000;
  for (int i = 0; i < count; ++i) {
    Sampler smp(uint64_t(i), 0, 1, 3);
    double v = smp.get1D();
    sum += v, sum2 += v * v;
  }
  double mean = sum / count, var = sum2 / count - mean * mean;
  EXPECT_NEAR(mean, 0.5, 0.005);
  EXPECT_NEAR(var, 1.0 / 12.0, 0.002);
}

}  // namespace
}  // namespace glint
