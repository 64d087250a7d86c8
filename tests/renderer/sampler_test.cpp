// Tests for addressed sampling: determinism, ranges, (0,2)-net stratification, uniformity.
#include "renderer/sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

namespace glint {
namespace {

TEST(Sampler, SameAddressGivesSameValues) {
  uint64_t key = pixelSampleKey(99, 1234);
  Sampler a(key, 7), b(key, 7);
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ(a.get1D(), b.get1D());
    Vec2f pa = a.get2D(), pb = b.get2D();
    EXPECT_EQ(pa.x, pb.x);
    EXPECT_EQ(pa.y, pb.y);
  }
}

TEST(Sampler, SeedPixelAndSampleChangeTheValues) {
  auto first = [](uint64_t px, uint32_t s, uint64_t seed) {
    Sampler smp(pixelSampleKey(seed, px), s);
    return smp.get2D();
  };
  Vec2f base = first(10, 3, 0);
  EXPECT_NE(base.x, first(11, 3, 0).x);
  EXPECT_NE(base.x, first(10, 4, 0).x);
  EXPECT_NE(base.x, first(10, 3, 1).x);
}

// The closed form (a superset transform of the index bits) against the generator matrix's
// columns applied bit by bit: every 16-bit index, and high-bit indices from a hash.
TEST(Sampler, SobolSecondDimensionMatchesTheBitLoop) {
  auto bitLoop = [](uint32_t idx) {
    uint32_t r = 0;
    for (uint32_t v = 1u << 31; idx; idx >>= 1, v ^= v >> 1)
      if (idx & 1) r ^= v;
    return r;
  };
  int mismatches = 0;
  for (uint32_t i = 0; i < 65536; ++i) mismatches += sobolSecondDimension(i) != bitLoop(i);
  for (uint32_t k = 0; k < 65536; ++k) {
    const uint32_t i = uint32_t(mixBits(k));
    mismatches += sobolSecondDimension(i) != bitLoop(i);
  }
  EXPECT_EQ(mismatches, 0);
  for (uint32_t i : {0x12345678u, 0x80000000u, 0xffffffffu})
    EXPECT_EQ(sobolSecondDimension(i), bitLoop(i)) << i;
}

TEST(Sampler, OwenScrambleIsABijectionOnLowBits) {
  // Scrambling the top 8 bits of 256 distinct fractions gives 256 distinct results.
  std::set<uint32_t> seen;
  for (uint32_t i = 0; i < 256; ++i) seen.insert(owenScramble(i << 24, 0xabcdef) >> 24);
  EXPECT_EQ(seen.size(), 256u);
}

// For n = 2^b samples, every elementary interval of area 1/n (2^i x 2^(b-i) cells) holds
// exactly one sample, in every dimension pair and every pixel: a (0,2)-net.
TEST(Sampler, PowerOfTwoSampleCountsFormZeroTwoNets) {
  for (uint32_t b : {0u, 2u, 4u, 6u}) {
    const uint32_t n = 1u << b;
    for (uint64_t pixel : {0ull, 77ull, 123456ull}) {
      for (int pair = 0; pair < 3; ++pair) {
        std::vector<Vec2f> pts;
        for (uint32_t s = 0; s < n; ++s) {
          Sampler smp(pixelSampleKey(5, pixel), s);
          Vec2f p;
          for (int k = 0; k <= pair; ++k) p = smp.get2D();
          ASSERT_GE(p.x, 0.0f);
          ASSERT_LT(p.x, 1.0f);
          ASSERT_GE(p.y, 0.0f);
          ASSERT_LT(p.y, 1.0f);
          pts.push_back(p);
        }
        for (uint32_t i = 0; i <= b; ++i) {
          uint32_t cx = 1u << i, cy = 1u << (b - i);
          std::vector<int> cells(n, 0);
          for (Vec2f p : pts) cells[uint32_t(p.y * cy) * cx + uint32_t(p.x * cx)]++;
          for (uint32_t c = 0; c < n; ++c)
            EXPECT_EQ(cells[c], 1) << "n=" << n << " pair " << pair << " shape " << cx << "x" << cy;
        }
      }
    }
  }
}

TEST(Sampler, OneDimensionalSamplesAreStratifiedForPowersOfTwo) {
  const uint32_t n = 32;
  std::vector<int> strata(n, 0);
  for (uint32_t s = 0; s < n; ++s) {
    Sampler smp(pixelSampleKey(0, 9), s);
    float v = smp.get1D();
    ASSERT_GE(v, 0.0f);
    ASSERT_LT(v, 1.0f);
    strata[uint32_t(v * n)]++;
  }
  for (uint32_t k = 0; k < n; ++k) EXPECT_EQ(strata[k], 1);
}

TEST(Sampler, DimensionPairsAreDecorrelated) {
  // Correlation between the x of the first and the x of the second pair over many samples.
  double sa = 0, sb = 0, sab = 0, saa = 0, sbb = 0;
  const int n = 4096;
  for (int s = 0; s < n; ++s) {
    Sampler smp(pixelSampleKey(1, 3), uint32_t(s));
    double a = smp.get2D().x, b = smp.get2D().x;
    sa += a, sb += b, sab += a * b, saa += a * a, sbb += b * b;
  }
  double cov = sab / n - sa / n * sb / n;
  double corr = cov / std::sqrt((saa / n - sa * sa / n / n) * (sbb / n - sb * sb / n / n));
  EXPECT_LT(std::abs(corr), 0.05);
}

TEST(Sampler, ValuesAreUniformAcrossPixels) {
  // Mean and variance of many independent pixels' first sample match U(0,1).
  double sum = 0, sum2 = 0;
  const int count = 100000;
  for (int i = 0; i < count; ++i) {
    Sampler smp(pixelSampleKey(3, uint64_t(i)), 0);
    double v = smp.get1D();
    sum += v, sum2 += v * v;
  }
  double mean = sum / count, var = sum2 / count - mean * mean;
  EXPECT_NEAR(mean, 0.5, 0.005);
  EXPECT_NEAR(var, 1.0 / 12.0, 0.002);
}

// The render loop draws the film pair from per-pixel seeds and starts the sampler after it;
// the numbers must be those of the plain sampler.
TEST(Sampler, PixelSeededFilmPairMatchesTheSampler) {
  for (uint64_t pixel : {0ull, 5ull, 479999ull}) {
    const uint64_t key = pixelSampleKey(42, pixel);
    const DimensionSeeds film(key, 0);
    for (uint32_t s : {0u, 1u, 15u, 1000u}) {
      Sampler plain(key, s);
      Vec2f a = plain.get2D(), b = sample2D(s, film);
      EXPECT_EQ(a.x, b.x);
      EXPECT_EQ(a.y, b.y);
      Sampler after(key, s, 2);
      EXPECT_EQ(after.dimension(), plain.dimension());
      EXPECT_EQ(plain.get1D(), after.get1D());
      Vec2f c = plain.get2D(), d = after.get2D();
      EXPECT_EQ(c.x, d.x);
      EXPECT_EQ(c.y, d.y);
    }
  }
}

// The vectorised batch (whichever clone the CPU selects) equals the scalar sample bit for bit.
TEST(Sampler, BatchEqualsSingleSamples) {
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    DimensionSeeds seeds(rng(), uint32_t(rng() % 8));
    uint32_t first = uint32_t(rng() % 4096), count = 1 + uint32_t(rng() % 16);
    if (trial % 10 == 0) first = 0xfffffff0u;  // indices near the top of the range
    uint32_t xs[16], ys[16];
    sample2DFractionBatch(first, count, seeds, xs, ys);
    for (uint32_t i = 0; i < count; ++i) {
      Fraction2 f = sample2DFraction(first + i, seeds);
      ASSERT_EQ(xs[i], f.x) << "trial " << trial << " sample " << i;
      ASSERT_EQ(ys[i], f.y) << "trial " << trial << " sample " << i;
    }
  }
}

}  // namespace
}  // namespace glint
