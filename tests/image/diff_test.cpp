// Tests for image/diff: metrics on known image pairs and idiff's pass/fail rule.
#include "image/diff.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "test_support.h"

namespace glint {
namespace {

void writeTestImage(const std::string& path, int w, int h, std::vector<std::string> channels,
                    const std::vector<float>& pixels,
                    OIIO::TypeDesc format = OIIO::TypeDesc::FLOAT) {
  OIIO::ImageSpec spec(w, h, int(channels.size()), format);
  spec.channelnames = channels;
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out) << OIIO::geterror();
  ASSERT_TRUE(out->open(path, spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data())) << out->geterror();
  ASSERT_TRUE(out->close());
}

// A 4×4 RGB image with a gentle gradient: 48 values, all ≥ 0.1.
std::vector<float> gradient() {
  std::vector<float> px;
  for (int i = 0; i < 16; ++i) px.insert(px.end(), {0.1f + 0.05f * float(i), 0.5f, 0.25f});
  return px;
}

struct Pair {
  std::string a, b;
};

// a = gradient with pixel (2, 1) green raised by 0.5; b = gradient.
Pair onePixelOff(const std::string& name) {
  std::string dir = test::scratchDir(name);
  std::vector<float> b = gradient(), a = b;
  a[(1 * 4 + 2) * 3 + 1] += 0.5f;
  Pair p{dir + "/a.exr", dir + "/b.exr"};
  writeTestImage(p.a, 4, 4, {"R", "G", "B"}, a);
  writeTestImage(p.b, 4, 4, {"R", "G", "B"}, b);
  return p;
}

TEST(ImageDiff, IdenticalImagesPassWithZeroMetrics) {
  std::string dir = test::scratchDir("ImageDiff.IdenticalImagesPassWithZeroMetrics");
  writeTestImage(dir + "/a.exr", 4, 4, {"R", "G", "B"}, gradient());
  DiffResult r = diffImages(dir + "/a.exr", dir + "/a.exr", DiffThresholds{});
  EXPECT_EQ(r.verdict, DiffVerdict::Pass);
  EXPECT_FALSE(r.sizeMismatch);
  EXPECT_EQ(r.pixels, 16u);
  EXPECT_EQ(r.channels, (std::vector<std::string>{"R", "G", "B"}));
  EXPECT_EQ(r.meanAbsError, 0);
  EXPECT_EQ(r.rmse, 0);
  EXPECT_EQ(r.relMse, 0);
  EXPECT_EQ(r.maxError, 0);
  EXPECT_TRUE(std::isinf(r.psnr));
  EXPECT_EQ(r.failPixels, 0u);
  EXPECT_EQ(r.warnPixels, 0u);
}

TEST(ImageDiff, OnePixelOffByHalf) {
  Pair p = onePixelOff("ImageDiff.OnePixelOffByHalf");
  DiffResult r = diffImages(p.a, p.b, DiffThresholds{});
  EXPECT_EQ(r.verdict, DiffVerdict::Fail);
  EXPECT_EQ(r.failPixels, 1u);
  EXPECT_EQ(r.warnPixels, 1u);
  EXPECT_DOUBLE_EQ(r.failPixelPercent, 100.0 / 16.0);
  // One error of 0.5 among 16 pixels × 3 channels.
  EXPECT_NEAR(r.meanAbsError, 0.5 / 48.0, 1e-7);
  EXPECT_NEAR(r.rmse, std::sqrt(0.25 / 48.0), 1e-7);
  EXPECT_NEAR(r.psnr, 20.0 * std::log10(1.0 / std::sqrt(0.25 / 48.0)), 1e-4);
  EXPECT_NEAR(r.relMse, 0.25 / (0.25 + 0.01) / 48.0, 1e-6);  // b = 0.5 there
  EXPECT_NEAR(r.maxError, 0.5, 1e-6);
  EXPECT_EQ(r.maxX, 2);
  EXPECT_EQ(r.maxY, 1);
  EXPECT_EQ(r.maxChannel, "G");
}

TEST(ImageDiff, PercentThresholdsSwitchPassAndFail) {
  Pair p = onePixelOff("ImageDiff.PercentThresholdsSwitchPassAndFail");
  DiffThresholds t;
  t.failPercent = 6.25;  // exactly one pixel in 16 is allowed: "more than" P % fails
  t.warnPercent = 6.25;
  EXPECT_EQ(diffImages(p.a, p.b, t).verdict, DiffVerdict::Pass);
  t.failPercent = 6.0;
  EXPECT_EQ(diffImages(p.a, p.b, t).verdict, DiffVerdict::Fail);
  t.failPercent = 10;
  t.warnPercent = 0;
  EXPECT_EQ(diffImages(p.a, p.b, t).verdict, DiffVerdict::Warn);
  // An error below the threshold neither fails nor warns.
  t = DiffThresholds{};
  t.fail = t.warn = 0.6;
  DiffResult r = diffImages(p.a, p.b, t);
  EXPECT_EQ(r.verdict, DiffVerdict::Pass);
  EXPECT_EQ(r.failPixels, 0u);
}

TEST(ImageDiff, DifferentResolutionsFail) {
  std::string dir = test::scratchDir("ImageDiff.DifferentResolutionsFail");
  writeTestImage(dir + "/a.exr", 4, 4, {"R", "G", "B"}, gradient());
  writeTestImage(dir + "/b.exr", 2, 8, {"R", "G", "B"}, gradient());
  DiffResult r = diffImages(dir + "/a.exr", dir + "/b.exr", DiffThresholds{});
  EXPECT_TRUE(r.sizeMismatch);
  EXPECT_EQ(r.verdict, DiffVerdict::Fail);
  EXPECT_EQ(r.widthB, 2);
  EXPECT_EQ(r.heightB, 8);
}

TEST(ImageDiff, ComparesChannelsCommonToBoth) {
  std::string dir = test::scratchDir("ImageDiff.ComparesChannelsCommonToBoth");
  std::vector<float> rgba, rgb = gradient();
  for (size_t i = 0; i < 16; ++i)
    rgba.insert(rgba.end(), {rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2], 0.0f});
  writeTestImage(dir + "/rgba.exr", 4, 4, {"R", "G", "B", "A"}, rgba);
  writeTestImage(dir + "/rgb.png", 4, 4, {"R", "G", "B"}, rgb, OIIO::TypeDesc::UINT8);
  DiffThresholds t;
  t.fail = t.warn = 0.5 / 255 + 1e-6;
  DiffResult r = diffImages(dir + "/rgba.exr", dir + "/rgb.png", t);
  EXPECT_EQ(r.channels, (std::vector<std::string>{"R", "G", "B"}));
  EXPECT_EQ(r.verdict, DiffVerdict::Pass);  // 8-bit quantization only
  EXPECT_GT(r.maxError, 0);
}

TEST(ImageDiff, MissingOrUnreadableFileNamesIt) {
  std::string dir = test::scratchDir("ImageDiff.MissingOrUnreadableFileNamesIt");
  writeTestImage(dir + "/a.exr", 4, 4, {"R", "G", "B"}, gradient());
  try {
    diffImages(dir + "/a.exr", dir + "/missing.exr", DiffThresholds{});
    FAIL() << "expected ImageReadError";
  } catch (const ImageReadError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.exr"), std::string::npos) << e.what();
  }
  {
    std::FILE* f = std::fopen((dir + "/junk.exr").c_str(), "w");
    std::fputs("not an image", f);
    std::fclose(f);
  }
  try {
    diffImages(dir + "/junk.exr", dir + "/a.exr", DiffThresholds{});
    FAIL() << "expected ImageReadError";
  } catch (const ImageReadError& e) {
    EXPECT_NE(std::string(e.what()).find("junk.exr"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace glint
