// Tests for image/tonemap: exposure and Ward's (1994) contrast-based scale factor.
#include "image/tonemap.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <span>
#include <vector>

#include "image/color.h"
#include "image/input.h"
#include "image/output.h"
#include "test_support.h"

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

TEST(ToneMap, AllBlackGivesDeltaAndBadSamplesDoNotPoison) {
  ToneMapSettings s;
  s.op = "ward";
  LogLuminanceStats black;
  black.add(constantImage(16, {0, 0, 0}), s);
  EXPECT_NEAR(black.logAverage(), kWardLogDelta, 1e-15);
  EXPECT_TRUE(black.allBlack());
  EXPECT_EQ(black.count, 0u);
  EXPECT_EQ(black.dark, 16u);
  EXPECT_EQ(LogLuminanceStats{}.logAverage(), kWardLogDelta);

  LogLuminanceStats bad;
  bad.add(std::vector<Rgb>{{NAN, 0, 0}, {-1, -1, -1}}, s);
  EXPECT_TRUE(std::isfinite(bad.logAverage()));
  EXPECT_EQ(bad.nonFinite, 1u);
  EXPECT_EQ(bad.count, 0u);
  EXPECT_EQ(bad.dark, 1u);  // the negative pixel counts as black, left out
  EXPECT_TRUE(bad.allBlack());

  // Black and near-black pixels (Lw <= δ) are left out of the log-average; the rest count.
  LogLuminanceStats mixed;
  const float nearBlack = float(kWardLogDelta / 100.0);  // Lw = δ at 100 cd/m² for 1.0
  mixed.add(
      std::vector<Rgb>{
          {0, 0, 0}, {nearBlack, nearBlack, nearBlack}, {0.3f, 0.3f, 0.3f}, {1.2f, 1.2f, 1.2f}},
      s);
  EXPECT_EQ(mixed.count, 2u);
  EXPECT_EQ(mixed.dark, 2u);
  const double lwa = std::sqrt((30 + kWardLogDelta) * (120 + kWardLogDelta));
  EXPECT_NEAR(mixed.logAverage(), lwa, 1e-6 * lwa);
}

// A non-constant image: Lwa = exp(mean log(δ + Lw)) over the lit pixels and m, written out by
// hand.
TEST(ToneMap, WardFactorEqualsClosedFormForAGradient) {
  ToneMapSettings s;
  s.op = "ward";
  s.wardDisplayMax = 120;
  s.wardSceneLuminance = 40;
  s.exposure = -1;
  std::vector<Rgb> img;
  double sumLog = 0;
  for (int i = 0; i < 100; ++i) {
    float v = 0.05f * float(i);  // 0 … 4.95, grey, so luminance = v
    img.push_back({v, v, v});
    if (i > 0) sumLog += std::log(kWardLogDelta + double(v) * 0.5 * 40.0);  // 0 is left out
  }
  const double lwa = std::exp(sumLog / 99.0);
  LogLuminanceStats stats;
  stats.add(img, s);
  EXPECT_NEAR(stats.logAverage(), lwa, 1e-6 * lwa);  // luminance() sums in float
  EXPECT_EQ(stats.count, 99u);
  EXPECT_EQ(stats.dark, 1u);
  const double m = closedFormWard(lwa, 120);
  EXPECT_NEAR(toneMapScale(s, stats.logAverage()), 0.5 * 40.0 * m / 120.0, 1e-6);
  // Brighter scenes get a smaller factor: Ward maps more world contrast onto the display.
  EXPECT_GT(wardScaleFactor(1, 100), wardScaleFactor(10, 100));
  EXPECT_GT(wardScaleFactor(10, 100), wardScaleFactor(1000, 100));
}

// ---- sequences -------------------------------------------------------------------------------

std::vector<LogLuminanceStats> statsOf(const std::vector<std::vector<Rgb>>& frames,
                                       const ToneMapSettings& s) {
  std::vector<LogLuminanceStats> out(frames.size());
  for (size_t i = 0; i < frames.size(); ++i) out[i].add(frames[i], s);
  return out;
}

TEST(ToneMap, SequenceSharesOneScaleSoBrightnessRatiosSurvive) {
  ToneMapSettings s;
  s.op = "ward";
  const std::vector<float> level = {0.05f, 0.1f, 0.4f};
  std::vector<std::vector<Rgb>> frames;
  for (float v : level) frames.push_back(constantImage(64, {v, v, v}));
  std::vector<LogLuminanceStats> perFrame = statsOf(frames, s);
  LogLuminanceStats seq = sequenceStats(perFrame);

  // Equal-size frames: the sequence's Lwa is the geometric mean of the frames' own.
  double expected =
      std::cbrt(perFrame[0].logAverage() * perFrame[1].logAverage() * perFrame[2].logAverage());
  EXPECT_NEAR(seq.logAverage(), expected, 1e-9 * expected);
  EXPECT_EQ(seq.count, 3u * 64u);

  std::vector<std::vector<Rgb>> shared = frames, own = frames;
  for (size_t i = 0; i < frames.size(); ++i) {
    applyToneMap(shared[i], s, seq.logAverage());
    applyToneMap(own[i], s, perFrame[i].logAverage());
  }
  // One scale: frame 2 stays 8× frame 0 and 4× frame 1.
  EXPECT_NEAR(shared[2][0].x / shared[0][0].x, 8.0, 1e-5);
  EXPECT_NEAR(shared[2][0].x / shared[1][0].x, 4.0, 1e-5);
  const float k = float(toneMapScale(s, seq.logAverage()));
  for (size_t i = 0; i < frames.size(); ++i) EXPECT_FLOAT_EQ(shared[i][5].y, level[i] * k);
  // Per frame, Ward adapts to each frame and squeezes the 8× range.
  EXPECT_LT(own[2][0].x / own[0][0].x, 4.0);
  EXPECT_GT(own[2][0].x / own[0][0].x, 1.0);
  // A one-frame sequence maps exactly as the frame alone.
  EXPECT_EQ(sequenceStats(std::span(perFrame.data(), 1)).logAverage(), perFrame[0].logAverage());
}

TEST(ToneMap, SequenceLeavesOutAllBlackFrames) {
  ToneMapSettings s;
  s.op = "ward";
  std::vector<Rgb> lit0 = constantImage(16, {0.2f, 0.2f, 0.2f});
  std::vector<Rgb> lit1 = constantImage(16, {0.3f, 0.1f, 0.5f});
  std::vector<Rgb> black = constantImage(16, {0, 0, 0});
  std::vector<LogLuminanceStats> withBlack = statsOf({lit0, black, lit1, black}, s);
  std::vector<LogLuminanceStats> without = statsOf({lit0, lit1}, s);
  EXPECT_TRUE(withBlack[1].allBlack());
  EXPECT_DOUBLE_EQ(sequenceStats(withBlack).logAverage(), sequenceStats(without).logAverage());

  // Black pixels never enter the statistic, so merging the frames is all it takes. Counting
  // them as δ would pull Lwa down by orders of magnitude: two black frames in four, to
  // sqrt(δ · Lwa).
  LogLuminanceStats merged;
  for (const LogLuminanceStats& f : withBlack) merged.merge(f);
  EXPECT_DOUBLE_EQ(merged.logAverage(), sequenceStats(without).logAverage());
  EXPECT_EQ(merged.dark, 32u);

  // A frame with a single lit pixel is not black: that pixel counts (its black ones do not).
  std::vector<Rgb> nearlyBlack = black;
  nearlyBlack[7] = {0.5f, 0.5f, 0.5f};
  std::vector<LogLuminanceStats> withDim = statsOf({lit0, nearlyBlack, lit1}, s);
  EXPECT_FALSE(withDim[1].allBlack());
  EXPECT_EQ(sequenceStats(withDim).count, 33u);
  EXPECT_EQ(sequenceStats(withDim).dark, 15u);

  // Every frame black: Lwa = δ, and the scale stays finite.
  std::vector<LogLuminanceStats> allBlack = statsOf({black, black}, s);
  LogLuminanceStats seq = sequenceStats(allBlack);
  EXPECT_EQ(seq.count, 0u);
  EXPECT_EQ(seq.dark, 32u);
  EXPECT_NEAR(seq.logAverage(), kWardLogDelta, 1e-15);
  EXPECT_TRUE(std::isfinite(toneMapScale(s, seq.logAverage())));
  EXPECT_EQ(sequenceStats({}).logAverage(), kWardLogDelta);
}

TEST(ToneMap, NanAndInfPixelsAreLeftOutAndCounted) {
  ToneMapSettings s;
  s.op = "ward";
  std::vector<Rgb> clean = {{0.1f, 0.2f, 0.3f}, {1, 1, 1}, {0.5f, 0.25f, 0}, {0, 0, 0}};
  std::vector<Rgb> dirty = clean;
  dirty.insert(dirty.begin() + 1, {NAN, 0.5f, 0.5f});
  dirty.push_back({INFINITY, 1, 1});
  dirty.push_back({-INFINITY, 0, 0});
  LogLuminanceStats a, b;
  a.add(clean, s);
  b.add(dirty, s);
  EXPECT_EQ(b.nonFinite, 3u);
  EXPECT_EQ(b.count, a.count);
  EXPECT_DOUBLE_EQ(b.logAverage(), a.logAverage());

  // A frame of nothing but NaN has no usable pixel: like a black frame, it is left out of a
  // sequence, whose NaN count still reports it.
  LogLuminanceStats nanFrame;
  nanFrame.add(constantImage(8, {NAN, NAN, NAN}), s);
  EXPECT_TRUE(nanFrame.allBlack());
  std::vector<LogLuminanceStats> frames = {a, nanFrame};
  LogLuminanceStats seq = sequenceStats(frames);
  EXPECT_DOUBLE_EQ(seq.logAverage(), a.logAverage());
  EXPECT_EQ(seq.nonFinite, 8u);
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

// ---- applying a given statistic to a file --------------------------------------------------

int code8(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << OIIO::geterror();
  if (!in) return -1;
  std::vector<unsigned char> px(size_t(in->spec().image_pixels()) * size_t(in->spec().nchannels));
  EXPECT_TRUE(in->read_image(0, 0, 0, -1, OIIO::TypeDesc::UINT8, px.data()));
  return px[0];
}

// The path `glint tonemap --sequence` takes: EXR in, the sequence's Lwa, display image out.
TEST(ToneMap, DisplayImageUsesTheGivenLogAverage) {
  const char* ocio = std::getenv("OCIO");
  std::string savedOcio = ocio ? ocio : "";
  ::unsetenv("OCIO");
  struct Restore {
    std::string value;
    ~Restore() {
      if (!value.empty()) ::setenv("OCIO", value.c_str(), 1);
    }
  } restore{savedOcio};
  std::string dir = test::scratchDir("ToneMap.DisplayImageUsesTheGivenLogAverage");
  Film film(3, 2, false);
  for (size_t i = 0; i < film.color.size(); ++i) film.color[i] = {0.1f, 0.1f, 0.1f};
  film.alpha.assign(film.alpha.size(), 1.0f);
  RenderSettings rs;
  writeImage(dir + "/in.exr", film, rs, {"scene.gltf", 4, 7, 1.5, "embree", "whitted"});

  ImageMetadata meta;
  Film back = readExr(dir + "/in.exr", &meta);
  ASSERT_EQ(back.width, 3);
  ASSERT_EQ(back.height, 2);
  EXPECT_EQ(back.color[4], (Rgb{0.1f, 0.1f, 0.1f}));
  EXPECT_EQ(meta.scene, "scene.gltf");
  EXPECT_EQ(meta.spp, 4);

  ToneMapSettings s;
  s.op = "ward";
  s.view = "Raw";          // code values proportional to the scaled radiance
  const double lwa = 2.5;  // not this image's own (10 + δ)
  writeDisplayImage(dir + "/out.png", back, s, lwa, meta);
  double k = toneMapScale(s, lwa);
  EXPECT_EQ(code8(dir + "/out.png"), int(std::lround(0.1 * k * 255)));
  EXPECT_NE(int(std::lround(0.1 * k * 255)), int(std::lround(0.1 * toneMapScale(s, 10) * 255)));

  EXPECT_THROW(writeDisplayImage(dir + "/out.exr", back, s, lwa, meta), OutputError);
  EXPECT_THROW(readExr(dir + "/missing.exr"), ImageReadError);
  EXPECT_THROW(readExr(dir + "/out.png"), ImageReadError);  // not an EXR
}

// ---- an object on black -------------------------------------------------------------------

// The 8-bit RGB code values of a whole image.
std::vector<unsigned char> codes8(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << OIIO::geterror();
  if (!in) return {};
  std::vector<unsigned char> px(size_t(in->spec().image_pixels()) * size_t(in->spec().nchannels));
  EXPECT_TRUE(in->read_image(0, 0, 0, -1, OIIO::TypeDesc::UINT8, px.data()));
  return px;
}

// A 64×64 frame, black but for a 14×14 square (about 5 % of it) of grey `v` with a brighter
// corner: an object lit on a black background.
Film objectOnBlack(float v) {
  Film film(64, 64, false);
  film.alpha.assign(film.alpha.size(), 0.0f);
  for (int y = 20; y < 34; ++y)
    for (int x = 30; x < 44; ++x) {
      const float c = x >= 40 && y >= 30 ? 2 * v : v;
      film.color[size_t(y) * 64 + size_t(x)] = {c, c, c};
      film.alpha[size_t(y) * 64 + size_t(x)] = 1.0f;
    }
  return film;
}

// Ward adapts to the lit pixels: the object maps as it would if it filled the frame, not 50
// times brighter because the black background pulled the log-average down to near δ. Both
// ways to a PNG, `glint render -o x.png` (writeImage) and `glint tonemap` (LogLuminanceStats,
// then writeDisplayImage), give the same, unclipped, image.
TEST(ToneMap, WardOnAnObjectOnBlackAdaptsToTheObject) {
  test::ScopedEnv noOcio("OCIO", nullptr);
  const std::string dir = test::scratchDir("ToneMap.WardOnAnObjectOnBlackAdaptsToTheObject");
  RenderSettings rs;
  rs.tonemap.op = "ward";
  rs.tonemap.view = "Raw";  // code values proportional to the tone-mapped values
  const float v = 0.2f;     // 20 cd/m² at the default 100 cd/m² for 1.0
  const Film film = objectOnBlack(v);

  LogLuminanceStats stats;
  stats.add(film.color, rs.tonemap);
  EXPECT_EQ(stats.count, 14u * 14u);
  EXPECT_EQ(stats.dark, 64u * 64u - 14u * 14u);
  // The log-average of the object alone: 180 pixels of 20 cd/m² and 16 of 40 (+ δ).
  const double lwa =
      std::exp((180 * std::log(20.0 + kWardLogDelta) + 16 * std::log(40.0 + kWardLogDelta)) / 196);
  EXPECT_NEAR(stats.logAverage(), lwa, 1e-5 * lwa);
  const double k = toneMapScale(rs.tonemap, lwa);
  EXPECT_LT(2 * v * k, 1.0);  // the brightest object pixel fits the display

  writeImage(dir + "/render.png", film, rs, {});
  writeDisplayImage(dir + "/tonemap.png", film, rs.tonemap, stats.logAverage(), {});
  const std::vector<unsigned char> render = codes8(dir + "/render.png");
  ASSERT_EQ(render.size(), 64u * 64u * 3u);
  EXPECT_EQ(render, codes8(dir + "/tonemap.png"));
  int clipped = 0;
  for (unsigned char c : render) clipped += c == 255;
  EXPECT_EQ(clipped, 0);
  EXPECT_NEAR(render[3 * (25 * 64 + 32)], v * k * 255, 0.51);      // the grey
  EXPECT_NEAR(render[3 * (32 * 64 + 42)], 2 * v * k * 255, 0.51);  // the bright corner
  EXPECT_EQ(render[3 * (5 * 64 + 5)], 0);                          // the background
}

// A frame without black pixels maps exactly as Ward's statistic over every pixel did before
// the black ones were left out: a synthetic gradient and a rendered Cornell box.
TEST(ToneMap, WardOnAFrameWithoutBlackIsUnchanged) {
  ToneMapSettings s;
  s.op = "ward";
  auto everyPixel = [&](const std::vector<Rgb>& img) {
    double sum = 0;
    for (const Rgb& c : img)
      sum += std::log(kWardLogDelta + std::max(0.0, double(luminance(c)) * 100.0));
    return std::exp(sum / double(img.size()));
  };
  std::vector<Rgb> gradient;
  for (int i = 0; i < 256; ++i) gradient.push_back({0.01f * float(i + 1), 0.5f, 0.02f});
  LogLuminanceStats g;
  g.add(gradient, s);
  EXPECT_EQ(g.dark, 0u);
  EXPECT_NEAR(g.logAverage(), everyPixel(gradient), 1e-9 * everyPixel(gradient));

  const test::Rendered box =
      test::renderJson(test::cornellBoxJson(24, 4, 1, R"({"type": "path"})"));
  LogLuminanceStats b;
  b.add(box.film.color, s);
  EXPECT_EQ(b.dark, 0u);
  const double before = everyPixel(box.film.color);
  EXPECT_NEAR(b.logAverage(), before, 1e-9 * before);
  EXPECT_NEAR(toneMapScale(s, b.logAverage()), toneMapScale(s, before), 1e-9);
}

}  // namespace
}  // namespace glint
