// Tests for renderer/tonemap: exposure and Ward's (1994) contrast-based scale factor.
#include "renderer/tonemap.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "renderer/color.h"

namespace glint {
namespace {

std::vector<Rgb> constantImage(size_t n, Rgb c) { return std::vector<Rgb>(n, c); }

double closedFormWard(double lwa, double displayMax) {
  return std::pow((1.219 + std::pow(displayMax / 2, 0.4)) / (1.219 + std::pow(lwa, 0.4)), 2.5);
}

TEST(ToneMap, NoneIsExposureOnly) {
  ToneMapSettings s;
  std::vector<Rgb> img = constantImage(4, {0.25f, 1.0f, 8.0f});
  toneMap(img, s);
  EXPECT_EQ(img[0], (Rgb{0.25f, 1.0f, 8.0f}));  // no clamping: the display transform clips
  s.exposure = 1;
  toneMap(img, s);
  EXPECT_EQ(img[3], (Rgb{0.5f, 2.0f, 16.0f}));
  s.exposure = -2;
  toneMap(img, s);
  EXPECT_EQ(img[1], (Rgb{0.125f, 0.5f, 4.0f}));
}

TEST(ToneMap, WardFactorEqualsClosedFormForConstantImage) {
  ToneMapSettings s;
  s.op = "ward";
  s.wardDisplayMax = 80;
  s.wardSceneLuminance = 250;
  const Rgb c{0.3f, 0.6f, 0.1f};
  std::vector<Rgb> img = constantImage(64, c);
  LogLuminanceStats stats;
  stats.add(img, s);
  // log(δ + Lw) averaged over equal values is log(δ + Lw).
  const double lw = double(luminance(c)) * 250.0;
  EXPECT_NEAR(stats.logAverage(), lw + kWardLogDelta, 1e-9 * lw);
  const double m = closedFormWard(lw + kWardLogDelta, 80);
  EXPECT_NEAR(wardScaleFactor(stats.logAverage(), 80), m, 1e-12);
  EXPECT_NEAR(toneMapScale(s, stats.logAverage()), 250.0 * m / 80.0, 1e-9);

  toneMap(img, s);
  EXPECT_NEAR(img[17].x, 0.3 * 250.0 * m / 80.0, 1e-5);
  EXPECT_NEAR(img[17].y, 0.6 * 250.0 * m / 80.0, 1e-5);
}

TEST(ToneMap, WardIsInvariantToImageSize) {
  ToneMapSettings s;
  s.op = "ward";
  std::vector<Rgb> small = constantImage(4, {0.7f, 0.2f, 0.05f});
  std::vector<Rgb> large = constantImage(512 * 384, {0.7f, 0.2f, 0.05f});
  toneMap(small, s);
  toneMap(large, s);
  EXPECT_NEAR(small[0].x, large[1000].x, 1e-6);
  EXPECT_NEAR(small[3].z, large.back().z, 1e-6);

  // A 2×2 tiling of an image has the same statistics as the image.
  std::vector<Rgb> tile = {{0.1f, 0.1f, 0.1f}, {2, 2, 2}, {0, 0, 0}, {0.5f, 0.3f, 0.9f}};
  std::vector<Rgb> tiled;
  for (int i = 0; i < 4; ++i) tiled.insert(tiled.end(), tile.begin(), tile.end());
  LogLuminanceStats a, b;
  a.add(tile, s);
  b.add(tiled, s);
  EXPECT_NEAR(a.logAverage(), b.logAverage(), 1e-9 * a.logAverage());
}

TEST(ToneMap, StatisticsMergeAcrossFrames) {
  ToneMapSettings s;
  s.op = "ward";
  std::vector<Rgb> f0 = constantImage(10, {0.1f, 0.1f, 0.1f});
  std::vector<Rgb> f1 = constantImage(30, {3.0f, 3.0f, 3.0f});
  LogLuminanceStats s0, s1, all;
  s0.add(f0, s);
  s1.add(f1, s);
  s0.merge(s1);
  std::vector<Rgb> both = f0;
  both.insert(both.end(), f1.begin(), f1.end());
  all.add(both, s);
  EXPECT_EQ(s0.count, 40u);
  EXPECT_NEAR(s0.logAverage(), all.logAverage(), 1e-9 * all.logAverage());
  // Lwa = exp((10 log(10 + δ) + 30 log(300 + δ)) / 40).
  double expected =
      std::exp((10 * std::log(10 + kWardLogDelta) + 30 * std::log(300 + kWardLogDelta)) / 40);
  EXPECT_NEAR(all.logAverage(), expected, 1e-5 * expected);

  // One sequence-wide factor applied to a frame differs from the frame's own.
  std::vector<Rgb> own = f0, shared = f0;
  toneMap(own, s);
  applyToneMap(shared, s, all.logAverage());
  EXPECT_GT(own[0].x, shared[0].x);
}

TEST(ToneMap, BlackPixelsUseDeltaAndBadSamplesDoNotPoison) {
  ToneMapSettings s;
  s.op = "ward";
  LogLuminanceStats black;
  black.add(constantImage(16, {0, 0, 0}), s);
  EXPECT_NEAR(black.logAverage(), kWardLogDelta, 1e-15);
  EXPECT_EQ(LogLuminanceStats{}.logAverage(), kWardLogDelta);

  LogLuminanceStats bad;
  bad.add(std::vector<Rgb>{{NAN, 0, 0}, {-1, -1, -1}}, s);
  EXPECT_TRUE(std::isfinite(bad.logAverage()));
}

TEST(ToneMap, ExposureShiftsWorldLuminance) {
  ToneMapSettings s;
  s.op = "ward";
  LogLuminanceStats a, b;
  a.add(constantImage(4, {0.5f, 0.5f, 0.5f}), s);
  s.exposure = 1;
  b.add(constantImage(4, {0.25f, 0.25f, 0.25f}), s);
  EXPECT_NEAR(a.logAverage(), b.logAverage(), 1e-9);
}

TEST(ToneMap, UnknownOperatorThrows) {
  ToneMapSettings s;
  s.op = "reinhard";
  EXPECT_FALSE(isKnownToneMapOperator("reinhard"));
  EXPECT_TRUE(isKnownToneMapOperator("ward"));
  std::vector<Rgb> img = constantImage(1, {1, 1, 1});
  EXPECT_THROW(toneMap(img, s), ColorError);
}

}  // namespace
}  // namespace glint
