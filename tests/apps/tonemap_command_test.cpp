// `glint tonemap` end to end: frame patterns, one Ward scale for a sequence versus one per
// frame, bad input (exit 2, the file named, nothing overwritten) and the optional ffmpeg step.
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

#include "image/output.h"
#include "test_support.h"

namespace glint {
namespace {

namespace fs = std::filesystem;

using test::ScopedEnv;

std::string quote(const std::string& s) { return "'" + s + "'"; }

void writeGreyExr(const std::string& path, float v, int w = 4, int h = 3) {
  Film film(w, h, false);
  film.color.assign(film.color.size(), Rgb{v, v, v});
  film.alpha.assign(film.alpha.size(), 1.0f);
  writeImage(path, film, RenderSettings{}, {});
}

// The 8-bit red code value of the first pixel.
int code8(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << path << ": " << OIIO::geterror();
  if (!in) return -1;
  std::vector<unsigned char> px(size_t(in->spec().image_pixels()) * size_t(in->spec().nchannels));
  EXPECT_TRUE(in->read_image(0, 0, 0, -1, OIIO::TypeDesc::UINT8, px.data()));
  return px[0];
}

using test::listFolder;
using test::slurp;

// Ward (1994) by hand, with glint's defaults: 1.0 scene-linear = 100 cd/m², Ldmax = 100 cd/m².
double wardScale(double lwa) {
  double m = std::pow((1.219 + std::pow(50.0, 0.4)) / (1.219 + std::pow(lwa, 0.4)), 2.5);
  return 100.0 * m / 100.0;
}

// Three frames, each twice as bright as the one before.
const std::vector<float> kLevels = {0.04f, 0.08f, 0.16f};

std::string writeThreeFrames(const std::string& dir) {
  fs::create_directories(dir + "/exr");
  for (int f = 1; f <= 3; ++f)
    writeGreyExr(dir + "/exr/frame_000" + std::to_string(f) + ".exr", kLevels[size_t(f - 1)]);
  return dir + "/exr/frame_####.exr";
}

// ---- sequence versus per frame ---------------------------------------------------------------

TEST(CliTonemap, SequenceKeepsBrightnessRatiosPerFrameNormalises) {
  ScopedEnv noOcio("OCIO", nullptr);
  std::string dir = test::scratchDir("CliTonemap.SequenceKeepsBrightnessRatiosPerFrameNormalises");
  std::string in = writeThreeFrames(dir);
  // The Raw view keeps code values proportional to the tone-mapped values.
  test::CommandResult seq = test::runGlint("tonemap " + quote(in) +
                                           " --operator ward --sequence --ldmax 100 --view Raw "
                                           "-o " +
                                           quote(dir + "/seq/frame_####.png"));
  ASSERT_EQ(seq.exitCode, 0) << seq.err;
  test::CommandResult per =
      test::runGlint("tonemap " + quote(in) + " --operator ward --view Raw -o " +
                     quote(dir + "/per/frame_####.png"));
  ASSERT_EQ(per.exitCode, 0) << per.err;

  double sumLog = 0;
  for (float v : kLevels) sumLog += std::log(1e-4 + 100.0 * v);
  const double seqLwa = std::exp(sumLog / 3);
  std::vector<int> s, p;
  for (int f = 1; f <= 3; ++f) {
    std::string name = "/frame_000" + std::to_string(f) + ".png";
    s.push_back(code8(dir + "/seq" + name));
    p.push_back(code8(dir + "/per" + name));
    const double v = kLevels[size_t(f - 1)];
    EXPECT_NEAR(s.back(), v * wardScale(seqLwa) * 255, 0.51) << "frame " << f;
    EXPECT_NEAR(p.back(), v * wardScale(100.0 * v + 1e-4) * 255, 0.51) << "frame " << f;
  }
  // One scale: 1 : 2 : 4 as in the EXRs (to 8-bit rounding).
  EXPECT_NEAR(double(s[1]) / s[0], 2.0, 0.05);
  EXPECT_NEAR(double(s[2]) / s[0], 4.0, 0.1);
  // One scale per frame: Ward adapts to each, and the 4× range shrinks below 2×.
  EXPECT_LT(double(p[2]) / p[0], 2.0);
  EXPECT_GT(p[2], p[0]);

  EXPECT_NE(seq.out.find("sequence of 3 frames: log-average luminance"), std::string::npos)
      << seq.out;
  EXPECT_NE(seq.out.find(fmt::format("{:.6g} cd/m²", seqLwa)), std::string::npos) << seq.out;
  for (int f = 1; f <= 3; ++f)
    EXPECT_NE(per.out.find("frame_000" + std::to_string(f) + ".exr: log-average luminance"),
              std::string::npos)
        << per.out;
  EXPECT_EQ(seq.err.find('\r'), std::string::npos);  // not a terminal: no progress bar
}

// --scene takes the tone mapping the scene asks for; options on the command line win.
TEST(CliTonemap, SceneSettingsApplyUnlessGivenOnTheCommandLine) {
  ScopedEnv noOcio("OCIO", nullptr);
  std::string dir = test::scratchDir("CliTonemap.SceneSettings");
  std::string in = writeThreeFrames(dir);
  const std::string scene = dir + "/scene.json";
  std::ofstream(scene) << R"({"render": {"tonemap": {"operator": "ward", "view": "Raw",
    "ward": {"display_max": 50, "scene_luminance": 200}}},
    "objects": [{"type": "sphere", "radius": 1}]})";
  test::CommandResult r = test::runGlint("tonemap " + quote(in) + " --sequence --scene " +
                                         quote(scene) + " -o " + quote(dir + "/a/f_####.png"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  // Ward by hand with Ldmax 50 and 1.0 = 200 cd/m²: scale m Ldmax / L(1.0), Raw view.
  double sumLog = 0;
  for (float v : kLevels) sumLog += std::log(1e-4 + 200.0 * v);
  const double lwa = std::exp(sumLog / 3);
  const double m = std::pow((1.219 + std::pow(25.0, 0.4)) / (1.219 + std::pow(lwa, 0.4)), 2.5);
  EXPECT_NEAR(code8(dir + "/a/f_0003.png"), 0.16 * m * 200.0 / 50.0 * 255, 0.51);

  // --ldmax given: the scene's 50 is not used.
  r = test::runGlint("tonemap " + quote(in) + " --sequence --ldmax 100 --scene " + quote(scene) +
                     " -o " + quote(dir + "/b/f_####.png"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const double m100 = std::pow((1.219 + std::pow(50.0, 0.4)) / (1.219 + std::pow(lwa, 0.4)), 2.5);
  EXPECT_NEAR(code8(dir + "/b/f_0003.png"), 0.16 * m100 * 200.0 / 100.0 * 255, 0.51);

  r = test::runGlint("tonemap " + quote(in) + " --scene " + quote(dir + "/none.json"));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("none.json"), std::string::npos) << r.err;
}

TEST(CliTonemap, AllBlackFrameDoesNotDragTheSequence) {
  ScopedEnv noOcio("OCIO", nullptr);
  std::string dir = test::scratchDir("CliTonemap.AllBlackFrameDoesNotDragTheSequence");
  fs::create_directories(dir + "/exr");
  writeGreyExr(dir + "/exr/f_1.exr", 0.05f);
  writeGreyExr(dir + "/exr/f_2.exr", 0.0f);  // a fade to black
  writeGreyExr(dir + "/exr/f_3.exr", 0.2f);
  std::string in = quote(dir + "/exr/f_#.exr");
  test::CommandResult all = test::runGlint(
      "tonemap " + in + " --operator ward --sequence --view Raw -o " + quote(dir + "/all/f_#.png"));
  ASSERT_EQ(all.exitCode, 0) << all.err;
  EXPECT_NE(all.out.find("1 all-black frame left out"), std::string::npos) << all.out;
  // The same sequence without the black frame, selected with --frames.
  test::CommandResult lit = test::runGlint("tonemap " + in +
                                           " --operator ward --sequence --view Raw --frames "
                                           "1-3:2 -o " +
                                           quote(dir + "/lit/f_#.png"));
  ASSERT_EQ(lit.exitCode, 0) << lit.err;
  EXPECT_EQ(listFolder(dir + "/lit"), (std::vector<std::string>{"f_1.png", "f_3.png"}));
  EXPECT_EQ(code8(dir + "/all/f_1.png"), code8(dir + "/lit/f_1.png"));
  EXPECT_EQ(code8(dir + "/all/f_3.png"), code8(dir + "/lit/f_3.png"));
  EXPECT_EQ(code8(dir + "/all/f_2.png"), 0);
  const double lwa = std::sqrt((5 + 1e-4) * (20 + 1e-4));
  EXPECT_NEAR(code8(dir + "/all/f_3.png"), 0.2 * wardScale(lwa) * 255, 0.51);
}

// A lit sphere on a black background (no environment), Ward: `glint render -o x.png` and
// `glint render -o x.exr` + `glint tonemap --operator ward` give the same PNG, and the sphere is
// not blown out to white (Ward adapts to the lit pixels, not to a log-average pulled toward 0
// by the background).
TEST(CliTonemap, WardOnAnObjectOnBlackDoesNotBlowItOut) {
  ScopedEnv noOcio("OCIO", nullptr);
  const std::string dir = test::scratchDir("CliTonemap.WardOnAnObjectOnBlackDoesNotBlowItOut");
  const std::string scene = dir + "/ball.json";
  std::ofstream(scene) << R"({
    "render": {"width": 48, "height": 48, "spp": 4, "tonemap": {"operator": "ward", "view": "Raw"}},
    "cameras": [{"name": "c", "position": [0, 0, 12], "look_at": [0, 0, 0], "yfov_degrees": 30}],
    "lights": [{"name": "sun", "type": "directional", "direction": [-1, -1, -1], "intensity": 1}],
    "materials": [{"name": "grey", "type": "lambert", "diffuse": [0.5, 0.5, 0.5]}],
    "objects": [{"type": "sphere", "radius": 1, "material": "grey"}]})";
  test::CommandResult r =
      test::runGlint("render " + quote(scene) + " --quiet -o " + quote(dir + "/render.png") +
                     " -o " + quote(dir + "/render.exr"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  r = test::runGlint("tonemap " + quote(dir + "/render.exr") + " --operator ward --view Raw -o " +
                     quote(dir + "/tonemap.png"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find(" black left out)"), std::string::npos) << r.out;

  auto codes = [](const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    EXPECT_TRUE(in) << path;
    std::vector<unsigned char> px;
    if (!in) return px;
    px.resize(size_t(in->spec().image_pixels()) * size_t(in->spec().nchannels));
    EXPECT_TRUE(in->read_image(0, 0, 0, -1, OIIO::TypeDesc::UINT8, px.data()));
    return px;
  };
  const std::vector<unsigned char> render = codes(dir + "/render.png");
  EXPECT_EQ(render, codes(dir + "/tonemap.png"));
  size_t lit = 0, clipped = 0, black = 0;
  for (unsigned char c : render) lit += c > 0, clipped += c == 255, black += c == 0;
  EXPECT_GT(lit, 3u * 48u * 48u / 20u);   // the sphere fills about 10 % of the frame
  EXPECT_GT(black, 3u * 48u * 48u / 2u);  // most of the frame is the black background
  EXPECT_EQ(clipped, 0u) << "of " << lit << " lit channel values";
}

// ---- patterns --------------------------------------------------------------------------------

TEST(CliTonemap, FramesArePaddedToTheRunAndSelectedByRange) {
  ScopedEnv noOcio("OCIO", nullptr);
  std::string dir = test::scratchDir("CliTonemap.FramesArePaddedToTheRunAndSelectedByRange");
  fs::create_directories(dir + "/exr");
  for (int f : {8, 9, 10, 11, 12})
    writeGreyExr(dir + "/exr/shot." + std::to_string(1000 + f).substr(1) + ".exr", 0.1f);
  writeGreyExr(dir + "/exr/shot.9.exr", 0.1f);      // not padded to the run: not a frame
  writeGreyExr(dir + "/exr/shot.0009x.exr", 0.1f);  // not the pattern's tail
  test::CommandResult r = test::runGlint("tonemap " + quote(dir + "/exr/shot.###.exr") +
                                         " --quiet -o " + quote(dir + "/png/s_#####.png"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err, "");
  EXPECT_EQ(listFolder(dir + "/png"),
            (std::vector<std::string>{"s_00008.png", "s_00009.png", "s_00010.png", "s_00011.png",
                                      "s_00012.png"}));

  r = test::runGlint("tonemap " + quote(dir + "/exr/shot.###.exr") + " --frames 9-12:3 -o " +
                     quote(dir + "/sel/s_#.png"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(listFolder(dir + "/sel"), (std::vector<std::string>{"s_12.png", "s_9.png"}));
  EXPECT_NE(r.err.find("glint: wrote"), std::string::npos) << r.err;
}

TEST(CliTonemap, SingleFileDefaultsToPngBesideIt) {
  ScopedEnv noOcio("OCIO", nullptr);
  std::string dir = test::scratchDir("CliTonemap.SingleFileDefaultsToPngBesideIt");
  writeGreyExr(dir + "/img.exr", 0.18f);
  test::CommandResult r = test::runGlint("tonemap " + quote(dir + "/img.exr"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(code8(dir + "/img.png"), 118);  // mid-grey through sRGB / Standard
  r = test::runGlint("tonemap " + quote(dir + "/img.exr") + " --exposure 1 --view Raw -o " +
                     quote(dir + "/raw.png"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(code8(dir + "/raw.png"), 92);  // 0.36 · 255
  r = test::runGlint("tonemap " + quote(dir + "/img.exr") + " --view 'ACES 1.0 SDR-video' -o " +
                     quote(dir + "/aces.jpg"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_LT(code8(dir + "/aces.jpg"), 118);  // the filmic toe darkens mid-grey
}

// ---- bad input -------------------------------------------------------------------------------

TEST(CliTonemap, BadInputExitsTwoNamingTheFile) {
  ScopedEnv noOcio("OCIO", nullptr);
  std::string dir = test::scratchDir("CliTonemap.BadInputExitsTwoNamingTheFile");
  std::string in = writeThreeFrames(dir);
  auto expectError = [](const test::CommandResult& r, const std::string& needle) {
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
  };
  expectError(
      test::runGlint("tonemap " + quote(dir + "/nope.exr") + " -o " + quote(dir + "/x.png")),
      dir + "/nope.exr: no such file");
  expectError(test::runGlint("tonemap " + quote(dir + "/exr/shot_####.exr") + " -o " +
                             quote(dir + "/x_####.png")),
              "no frames match '" + dir + "/exr/shot_####.exr'");
  expectError(
      test::runGlint("tonemap " + quote(in) + " --frames 7-9 -o " + quote(dir + "/x_####.png")),
      "no frames match");
  expectError(test::runGlint("tonemap " + quote(in) + " -o " + quote(dir + "/x.png")),
              "mismatched patterns");
  expectError(test::runGlint("tonemap " + quote(dir + "/exr/frame_0001.exr") + " -o " +
                             quote(dir + "/x_##.png")),
              "mismatched patterns");
  expectError(
      test::runGlint("tonemap " + quote(in) + " --view Nope -o " + quote(dir + "/x_####.png")),
      "unknown OCIO view 'Nope'");
  expectError(
      test::runGlint("tonemap " + quote(in) + " --display Nope -o " + quote(dir + "/x_####.png")),
      "config.ocio");
  expectError(test::runGlint("tonemap " + quote(in) + " --operator reinhard -o " +
                             quote(dir + "/x_####.png")),
              "unknown tone-map operator 'reinhard'");
  expectError(
      test::runGlint("tonemap " + quote(in) + " --sequence -o " + quote(dir + "/x_####.png")),
      "needs --operator ward");
  expectError(test::runGlint("tonemap " + quote(in) + " -o " + quote(dir + "/x_####.exr")),
              "EXR stays scene-linear");
  expectError(test::runGlint("tonemap " + quote(in) + " -o " + quote(dir + "/x_##_##.png")),
              "more than one run of '#'");

  // A file that is not an image, in the middle of a pattern.
  std::ofstream(dir + "/exr/frame_0002.exr") << "not an EXR";
  expectError(test::runGlint("tonemap " + quote(in) + " -o " + quote(dir + "/png/x_####.png")),
              dir + "/exr/frame_0002.exr");
  // Every frame is read before any is written.
  EXPECT_FALSE(fs::exists(dir + "/png"));
  for (const std::string& name : listFolder(dir))
    EXPECT_EQ(name.find(".png"), std::string::npos) << name;
}

// A failed run (here a truncated frame) must leave the images of an earlier good run untouched
// and no temporary files behind.
TEST(CliTonemap, FailedRunKeepsTheExistingGoodPngs) {
  ScopedEnv noOcio("OCIO", nullptr);
  std::string dir = test::scratchDir("CliTonemap.FailedRunKeepsTheExistingGoodPngs");
  std::string in = writeThreeFrames(dir);
  std::string out = quote(dir + "/png/frame_####.png");
  for (const char* mode : {" --sequence", ""}) {
    SCOPED_TRACE(mode);
    writeThreeFrames(dir);
    ASSERT_EQ(test::runGlint("tonemap " + quote(in) + " --operator ward -o " + out).exitCode, 0);
    std::vector<std::string> good;
    for (int f = 1; f <= 3; ++f)
      good.push_back(slurp(dir + "/png/frame_000" + std::to_string(f) + ".png"));

    std::string exr = dir + "/exr/frame_0003.exr";
    std::string bytes = slurp(exr);
    std::ofstream(exr, std::ios::binary | std::ios::trunc) << bytes.substr(0, bytes.size() / 2);
    test::CommandResult r = test::runGlint("tonemap " + quote(in) + " --operator ward" + mode +
                                           " --exposure 2 -o " + out);
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_NE(r.err.find(exr), std::string::npos) << r.err;
    for (int f = 1; f <= 3; ++f)
      EXPECT_EQ(slurp(dir + "/png/frame_000" + std::to_string(f) + ".png"), good[size_t(f - 1)])
          << "frame " << f;
    EXPECT_EQ(listFolder(dir + "/png"),
              (std::vector<std::string>{"frame_0001.png", "frame_0002.png", "frame_0003.png"}));
  }
}

// ---- ffmpeg ----------------------------------------------------------------------------------

TEST(CliTonemap, Mp4WithoutFfmpegFailsBeforeAnyWork) {
  ScopedEnv noOcio("OCIO", nullptr);
  std::string dir = test::scratchDir("CliTonemap.Mp4WithoutFfmpegFailsBeforeAnyWork");
  std::string in = writeThreeFrames(dir);
  fs::create_directories(dir + "/emptybin");
  ScopedEnv path("PATH", (dir + "/emptybin").c_str());
  test::CommandResult r =
      test::runGlint("tonemap " + quote(in) + " -o " + quote(dir + "/png/f_####.png") + " --mp4 " +
                     quote(dir + "/movie.mp4"));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.err,
            "glint: ffmpeg not found on PATH; install it (apt install ffmpeg) or encode the PNGs "
            "yourself\n");
  EXPECT_FALSE(fs::exists(dir + "/png"));
  EXPECT_FALSE(fs::exists(dir + "/movie.mp4"));
}

// A stand-in ffmpeg that records its arguments and stores what it is sent: the PNG frames, in
// order, at the requested frame rate, written atomically under the final name.
TEST(CliTonemap, Mp4PipesEveryFrameToFfmpeg) {
  ScopedEnv noOcio("OCIO", nullptr);
  std::string dir = test::scratchDir("CliTonemap.Mp4PipesEveryFrameToFfmpeg");
  std::string in = writeThreeFrames(dir);
  fs::create_directories(dir + "/bin");
  std::string fake = dir + "/bin/ffmpeg";
  std::ofstream(fake) << "#!/bin/sh\n"
                         "printf '%s\\n' \"$@\" > \"$(dirname \"$0\")/args.txt\"\n"
                         "for last; do :; done\n"
                         "cat > \"$last\"\n";
  fs::permissions(fake, fs::perms::owner_all);
  const char* oldPath = std::getenv("PATH");
  ScopedEnv path("PATH", (dir + "/bin:" + (oldPath ? oldPath : "/usr/bin:/bin")).c_str());
  test::CommandResult r =
      test::runGlint("tonemap " + quote(in) + " --quiet -o " + quote(dir + "/png/f_####.png") +
                     " --mp4 " + quote(dir + "/movie.mp4") + " --fps 12");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  std::string movie = slurp(dir + "/movie.mp4");
  std::string frames;
  for (int f = 1; f <= 3; ++f) frames += slurp(dir + "/png/f_000" + std::to_string(f) + ".png");
  EXPECT_EQ(movie, frames);
  std::string args = slurp(dir + "/bin/args.txt");
  EXPECT_NE(args.find("-framerate\n12\n"), std::string::npos) << args;
  EXPECT_NE(args.find("-i\n-\n"), std::string::npos) << args;
  EXPECT_EQ(listFolder(dir), (std::vector<std::string>{"bin", "exr", "movie.mp4", "png"}));

  // ffmpeg failing is a failed run (exit 1) that leaves no movie.
  std::ofstream(fake, std::ios::trunc) << "#!/bin/sh\ncat >/dev/null\nexit 3\n";
  r = test::runGlint("tonemap " + quote(in) + " --quiet -o " + quote(dir + "/png/f_####.png") +
                     " --mp4 " + quote(dir + "/second.mp4"));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("second.mp4"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/second.mp4"));
  EXPECT_EQ(listFolder(dir), (std::vector<std::string>{"bin", "exr", "movie.mp4", "png"}));
}

}  // namespace
}  // namespace glint
