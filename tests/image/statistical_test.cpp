// Tests for image/statistical: the z-test model on synthetic renders whose noise is
// known, the multiple-comparison correction, the global bias test, the error cap, and the
// inputs it refuses.
#include "image/statistical.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "test_support.h"

namespace glint {
namespace {

constexpr int kW = 64, kH = 48;

// A reference "rendered" at `spp` samples of per-sample standard deviation `sigma` around a
// smooth image: its mean and the variance of that mean.
struct Reference {
  std::vector<float> mean;  // RGB
  float sigma = 0;
  int spp = 0;
};

float truth(int x, int y, int c) { return 0.2f + 0.5f * float(x) / kW + 0.1f * float(c + y % 3); }

void writeExr(const std::string& path, std::vector<std::string> names, const std::vector<float>& px,
              int spp) {
  OIIO::ImageSpec spec(kW, kH, int(names.size()), OIIO::TypeDesc::FLOAT);
  spec.channelnames = names;
  if (spp > 0) spec.attribute("glint:spp", spp);
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out && out->open(path, spec)) << OIIO::geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data())) << out->geterror();
  ASSERT_TRUE(out->close());
}

// Writes the reference (mean of `spp` samples + variance of the mean) to `path`.
void writeReference(const std::string& path, float sigma, int spp, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0f, sigma / std::sqrt(float(spp)));
  std::vector<float> px;
  const float var = sigma * sigma / float(spp);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      for (int c = 0; c < 3; ++c) px.push_back(truth(x, y, c) + noise(rng));
      px.insert(px.end(), {var, var, var});
    }
  writeExr(path, {"R", "G", "B", "variance.R", "variance.G", "variance.B"}, px, spp);
}

// Writes a test render of `spp` samples; `bias(x, y)` is added to every channel's true value.
template <class Bias>
void writeRender(const std::string& path, float sigma, int spp, uint32_t seed, Bias bias,
                 bool withSpp = true) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0f, sigma / std::sqrt(float(spp)));
  std::vector<float> px;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      for (int c = 0; c < 3; ++c) px.push_back(truth(x, y, c) + bias(x, y) + noise(rng));
  writeExr(path, {"R", "G", "B"}, px, withSpp ? spp : 0);
}

auto noBias = [](int, int) { return 0.0f; };

TEST(StatisticalDiff, TwoSidedQuantileInvertsTheNormalTail) {
  EXPECT_NEAR(normalTwoSidedQuantile(0.05), 1.959964, 1e-5);
  EXPECT_NEAR(normalTwoSidedQuantile(0.01), 2.575829, 1e-5);
  EXPECT_NEAR(normalTwoSidedQuantile(1e-9), 6.109410, 1e-4);
  EXPECT_EQ(normalTwoSidedQuantile(1), 0);
}

// Correct renders pass over many seeds, and the noise model fits (mean z² ≈ 1).
TEST(StatisticalDiff, UnbiasedRendersPass) {
  std::string dir = test::scratchDir("StatisticalDiff.UnbiasedRendersPass");
  writeReference(dir + "/ref.exr", 0.5f, 4096, 1);
  int failures = 0;
  double meanZ2 = 0;
  for (uint32_t seed = 2; seed < 22; ++seed) {
    writeRender(dir + "/a.exr", 0.5f, 32, seed, noBias);
    StatisticalResult r = diffStatistical(dir + "/a.exr", dir + "/ref.exr", {});
    EXPECT_EQ(r.varianceModel, "predicted");
    EXPECT_EQ(r.sppA, 32);
    EXPECT_EQ(r.sppB, 4096);
    failures += r.verdict == DiffVerdict::Fail;
    meanZ2 += r.meanZ2 / 20;
  }
  // α = 0.01 per comparison: 20 comparisons fail none with probability 0.82, at most one
  // with 0.98.
  EXPECT_LE(failures, 1);
  EXPECT_NEAR(meanZ2, 1.0, 0.05);
}

// The Šidák threshold grows with the number of pixels tested.
TEST(StatisticalDiff, PixelThresholdIsSidakCorrected) {
  std::string dir = test::scratchDir("StatisticalDiff.PixelThresholdIsSidakCorrected");
  writeReference(dir + "/ref.exr", 0.5f, 4096, 1);
  writeRender(dir + "/a.exr", 0.5f, 32, 5, noBias);
  StatisticalResult r = diffStatistical(dir + "/a.exr", dir + "/ref.exr", {});
  const double tests = 3.0 * kW * kH;
  EXPECT_NEAR(r.pixelZ, normalTwoSidedQuantile(1 - std::pow(0.99, 1 / tests)), 1e-6);
  EXPECT_NEAR(r.globalZLimit, normalTwoSidedQuantile(1 - std::pow(0.99, 1 / 3.0)), 1e-6);
}

// A localised error: a block of pixels 8σ off fails the per-pixel tests.
TEST(StatisticalDiff, ALocalErrorFailsThePixelTests) {
  std::string dir = test::scratchDir("StatisticalDiff.ALocalErrorFailsThePixelTests");
  writeReference(dir + "/ref.exr", 0.5f, 4096, 1);
  const float sigma32 = 0.5f / std::sqrt(32.0f);
  writeRender(dir + "/a.exr", 0.5f, 32, 7,
              [&](int x, int y) { return x < 8 && y < 8 ? 8 * sigma32 : 0.0f; });
  StatisticalResult r = diffStatistical(dir + "/a.exr", dir + "/ref.exr", {});
  EXPECT_EQ(r.verdict, DiffVerdict::Fail);
  EXPECT_GT(r.failPixels, 32u);  // most of the 64 biased pixels
  EXPECT_LT(r.passPercent, 99.5);
  EXPECT_LT(r.maxZX, 8);
  EXPECT_LT(r.maxZY, 8);
  // The heat map marks them.
  writeZHeatMap(dir + "/heat.png", r);
  auto in = OIIO::ImageInput::open(dir + "/heat.png");
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().width, kW);
  EXPECT_EQ(in->spec().height, kH);
}

// A bias of 0.2σ everywhere: no single pixel shows it, the global test does.
TEST(StatisticalDiff, ASmallGlobalBiasFailsTheGlobalTest) {
  std::string dir = test::scratchDir("StatisticalDiff.ASmallGlobalBiasFailsTheGlobalTest");
  writeReference(dir + "/ref.exr", 0.5f, 4096, 1);
  const float sigma32 = 0.5f / std::sqrt(32.0f);
  writeRender(dir + "/a.exr", 0.5f, 32, 9, [&](int, int) { return 0.2f * sigma32; });
  StatisticalResult r = diffStatistical(dir + "/a.exr", dir + "/ref.exr", {});
  EXPECT_GE(r.passPercent, 99.5);
  EXPECT_TRUE(r.biased);
  for (double z : r.globalZ) EXPECT_GT(z, r.globalZLimit);
  EXPECT_EQ(r.verdict, DiffVerdict::Fail);
}

TEST(StatisticalDiff, TheErrorCapFailsOneBadPixel) {
  std::string dir = test::scratchDir("StatisticalDiff.TheErrorCapFailsOneBadPixel");
  writeReference(dir + "/ref.exr", 0.5f, 4096, 1);
  writeRender(dir + "/a.exr", 0.5f, 32, 11,
              [](int x, int y) { return x == 30 && y == 20 ? 0.8f : 0.0f; });
  StatisticalThresholds t;
  StatisticalResult r = diffStatistical(dir + "/a.exr", dir + "/ref.exr", t);
  EXPECT_EQ(r.verdict, DiffVerdict::Pass) << "one pixel in 3072 is within the allowed fraction";
  EXPECT_EQ(r.maxErrorX, 30);
  EXPECT_EQ(r.maxErrorY, 20);
  t.maxError = 0.5;
  r = diffStatistical(dir + "/a.exr", dir + "/ref.exr", t);
  EXPECT_TRUE(r.errorCapExceeded);
  EXPECT_EQ(r.verdict, DiffVerdict::Fail);
}

TEST(StatisticalDiff, NonFiniteValuesFail) {
  std::string dir = test::scratchDir("StatisticalDiff.NonFiniteValuesFail");
  writeReference(dir + "/ref.exr", 0.5f, 4096, 1);
  writeRender(dir + "/a.exr", 0.5f, 32, 13, [](int x, int y) {
    return x == 3 && y == 4 ? std::numeric_limits<float>::quiet_NaN() : 0.0f;
  });
  StatisticalResult r = diffStatistical(dir + "/a.exr", dir + "/ref.exr", {});
  EXPECT_EQ(r.nonFinite, 3u);
  EXPECT_EQ(r.verdict, DiffVerdict::Fail);
}

// Without glint:spp in the render, its sample count must be given, or its own variance used.
TEST(StatisticalDiff, SampleCountsComeFromTheFilesOrTheCaller) {
  std::string dir = test::scratchDir("StatisticalDiff.SampleCountsComeFromTheFilesOrTheCaller");
  writeReference(dir + "/ref.exr", 0.5f, 4096, 1);
  writeRender(dir + "/a.exr", 0.5f, 32, 15, noBias, /*withSpp=*/false);
  EXPECT_THROW(diffStatistical(dir + "/a.exr", dir + "/ref.exr", {}), ImageReadError);
  StatisticalThresholds t;
  t.sppA = 32;
  StatisticalResult r = diffStatistical(dir + "/a.exr", dir + "/ref.exr", t);
  EXPECT_EQ(r.verdict, DiffVerdict::Pass);
  EXPECT_NEAR(r.meanZ2, 1.0, 0.15);
  // A reference compared with itself: its own variance serves (and nothing differs).
  r = diffStatistical(dir + "/ref.exr", dir + "/ref.exr", {});
  EXPECT_EQ(r.varianceModel, "max(own, predicted)");
  EXPECT_EQ(r.maxZ, 0);
  EXPECT_EQ(r.verdict, DiffVerdict::Pass);
}

TEST(StatisticalDiff, AReferenceWithoutVarianceIsRefusedByName) {
  std::string dir = test::scratchDir("StatisticalDiff.AReferenceWithoutVarianceIsRefusedByName");
  writeRender(dir + "/a.exr", 0.5f, 32, 17, noBias);
  writeRender(dir + "/plain.exr", 0.5f, 1024, 18, noBias);
  try {
    diffStatistical(dir + "/a.exr", dir + "/plain.exr", {});
    FAIL() << "expected ImageReadError";
  } catch (const ImageReadError& e) {
    EXPECT_NE(std::string(e.what()).find("plain.exr"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--aovs"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace glint
