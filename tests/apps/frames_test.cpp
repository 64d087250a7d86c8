// Tests for frame ranges and numbered file patterns (apps/frames.h) and for sequences
// rendered with `glint render --frames`.
#include "apps/frames.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "geometry/error.h"
#include "test_support.h"

namespace glint::app {
namespace {

TEST(Frames, RangesWithAndWithoutStep) {
  EXPECT_EQ(parseFrameRange("3").frames(), (std::vector<int>{3}));
  EXPECT_EQ(parseFrameRange("0-4").frames(), (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_EQ(parseFrameRange("1-10:4").frames(), (std::vector<int>{1, 5, 9}));
  EXPECT_EQ(parseFrameRange("7-7:3").frames(), (std::vector<int>{7}));
  EXPECT_TRUE(parseFrameRange("1-10:4").contains(9));
  EXPECT_FALSE(parseFrameRange("1-10:4").contains(8));
}

TEST(Frames, BadRangesAreRejectedWithTheReason) {
  for (const char* bad :
       {"", "a-b", "5-2", "1-4:0", "-3", "1-", "1-4:", "1.5-3", "1-4:x", "0-999999999"}) {
    try {
      parseFrameRange(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--frames"), std::string::npos) << e.what();
    }
  }
}

TEST(Frames, PatternsArePaddedToTheRunOfHashes) {
  EXPECT_EQ(parseFramePattern("out/frame_####.exr").path(42), "out/frame_0042.exr");
  EXPECT_EQ(parseFramePattern("f#.png").path(7), "f7.png");
  EXPECT_EQ(parseFramePattern("f##.png").path(12345), "f12345.png");  // wider: in full
  EXPECT_EQ(parseFramePattern("still.exr").path(3), "still.exr");
  EXPECT_FALSE(parseFramePattern("still.exr").isPattern());
  EXPECT_THROW(parseFramePattern("a#/b_###.exr"), InputError);
  EXPECT_THROW(parseFramePattern("f_##_##.exr"), InputError);
}

}  // namespace
}  // namespace glint::app

// ---- glint render --frames ------------------------------------------------------------------

namespace glint::app {
namespace {

namespace fs = std::filesystem;

// A white eyelight ball moving from x = -1 to x = 1 over one second, seen by an orthographic
// camera covering x in [-2, 2]; 32x16 pixels.
std::string writeMovingBallScene(const std::string& dir) {
  std::string path = dir + "/moving_ball.json";
  std::ofstream(path) << R"({
  "render": {"width": 32, "height": 16, "spp": 4, "fps": 2, "default_light": false,
             "filter": {"type": "box", "radius": 0.5}},
  "cameras": [{"name": "front", "type": "orthographic", "xmag": 2, "ymag": 1,
               "position": [0, 0, 5], "look_at": [0, 0, 0]}],
  "materials": [{"name": "white", "type": "eyelight", "color": [1, 1, 1]}],
  "objects": [{"name": "ball", "type": "sphere", "radius": 0.5, "material": "white",
               "animation": {"translation": {"keys": [[0, [-1, 0, 0]], [1, [1, 0, 0]]]}}}]
})";
  return path;
}

// The mean x (in pixels) of the image's bright pixels: where the ball is.
double brightCentroidX(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << path;
  if (!in) return -1;
  const OIIO::ImageSpec& spec = in->spec();
  std::vector<float> px(size_t(spec.image_pixels()) * size_t(spec.nchannels));
  EXPECT_TRUE(in->read_image(0, 0, 0, -1, OIIO::TypeDesc::FLOAT, px.data()));
  double sum = 0, weight = 0;
  for (int y = 0; y < spec.height; ++y)
    for (int x = 0; x < spec.width; ++x) {
      float v = px[(size_t(y) * size_t(spec.width) + size_t(x)) * size_t(spec.nchannels)];
      sum += v * (x + 0.5);
      weight += v;
    }
  return weight > 0 ? sum / weight : -1;
}

nlohmann::json readJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

TEST(CliFrames, RendersEveryFrameAtItsTimeWithPerFrameStats) {
  std::string dir = test::scratchDir("CliFrames.Sequence");
  std::string scene = writeMovingBallScene(dir);
  auto r = test::runGlint("render " + scene + " --frames 0-2 -o " + dir + "/f_##.exr --stats " +
                          dir + "/stats.json --quiet");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  // fps 2 from the scene: frames at t = 0, 0.5, 1 put the ball at x = -1, 0, 1, that is at
  // pixels 8, 16, 24 of 32.
  const double expected[] = {8, 16, 24};
  for (int f = 0; f < 3; ++f) {
    std::string frame = dir + "/f_0" + std::to_string(f) + ".exr";
    ASSERT_TRUE(fs::exists(frame)) << frame;
    EXPECT_NEAR(brightCentroidX(frame), expected[f], 0.5) << frame;
  }
  nlohmann::json stats = readJson(dir + "/stats.json");
  ASSERT_EQ(stats["frames"].size(), 3u);
  EXPECT_DOUBLE_EQ(stats["frames"][1]["time"].get<double>(), 0.5);
  EXPECT_EQ(stats["frames"][2]["frame"].get<int>(), 2);
  EXPECT_GE(stats["frames"][0]["render_seconds"].get<double>(), 0.0);
  EXPECT_EQ(stats["frames_rendered"].get<int>(), 3);
}

TEST(CliFrames, StepAndFpsFromTheCommandLine) {
  std::string dir = test::scratchDir("CliFrames.Step");
  std::string scene = writeMovingBallScene(dir);
  // The output folder does not exist yet: it is created.
  auto r = test::runGlint("render " + scene + " --frames 0-8:4 --fps 8 -o " + dir +
                          "/seq/f_###.exr --quiet");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir + "/seq/f_000.exr"));
  EXPECT_FALSE(fs::exists(dir + "/seq/f_001.exr"));
  ASSERT_TRUE(fs::exists(dir + "/seq/f_004.exr"));
  EXPECT_NEAR(brightCentroidX(dir + "/seq/f_004.exr"), 16, 0.5);  // t = 4 / 8 = 0.5
  EXPECT_NEAR(brightCentroidX(dir + "/seq/f_008.exr"), 24, 0.5);
}

TEST(CliFrames, ResumeSkipsCompleteFramesOnly) {
  std::string dir = test::scratchDir("CliFrames.Resume");
  std::string scene = writeMovingBallScene(dir);
  std::string out = " -o " + dir + "/f_#.exr --quiet --stats " + dir + "/stats.json";
  ASSERT_EQ(test::runGlint("render " + scene + " --frames 0-2" + out).exitCode, 0);
  auto kept = fs::last_write_time(dir + "/f_0.exr");
  fs::remove(dir + "/f_1.exr");
  auto r = test::runGlint("render " + scene + " --frames 0-2 --resume" + out);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir + "/f_1.exr"));
  EXPECT_EQ(fs::last_write_time(dir + "/f_0.exr"), kept) << "a complete frame was rendered again";
  nlohmann::json stats = readJson(dir + "/stats.json");
  EXPECT_EQ(stats["frames_rendered"].get<int>(), 1);
  EXPECT_EQ(stats["frames_skipped"].get<int>(), 2);
  ASSERT_EQ(stats["frames"].size(), 1u);
  EXPECT_EQ(stats["frames"][0]["frame"].get<int>(), 1);
}

// A frame is done only when its file is complete and of this render: a file cut short (a copy
// from a node that died) or rendered with other settings is redone, and --list-missing names
// exactly the frames --resume renders.
TEST(CliFrames, ResumeRedoesPartialAndForeignFrames) {
  std::string dir = test::scratchDir("CliFrames.ResumePartial");
  std::string scene = writeMovingBallScene(dir);
  const std::string out = " -o " + dir + "/f_#.exr";
  ASSERT_EQ(test::runGlint("render " + scene + " --frames 0-3 --quiet" + out).exitCode, 0);
  fs::resize_file(dir + "/f_1.exr", fs::file_size(dir + "/f_1.exr") / 2);
  ASSERT_EQ(test::runGlint("render " + scene + " --frames 2-2 --spp 2 --quiet" + out).exitCode, 0);
  fs::remove(dir + "/f_3.exr");
  const auto kept = fs::last_write_time(dir + "/f_0.exr");

  auto list = test::runGlint("render " + scene + " --frames 0-3 --list-missing" + out);
  ASSERT_EQ(list.exitCode, 0) << list.err;
  EXPECT_EQ(list.out, "1\n2\n3\n");
  EXPECT_FALSE(fs::exists(dir + "/f_3.exr")) << "--list-missing rendered";

  auto r = test::runGlint("render " + scene + " --frames 0-3 --resume" + out + " --stats " + dir +
                          "/stats.json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("frame 1: redoing"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("2 spp, not 4"), std::string::npos) << r.err;
  EXPECT_EQ(fs::last_write_time(dir + "/f_0.exr"), kept) << "a complete frame was rendered again";
  nlohmann::json stats = readJson(dir + "/stats.json");
  EXPECT_EQ(stats["frames_rendered"].get<int>(), 3);
  EXPECT_EQ(stats["frames_skipped"].get<int>(), 1);

  list = test::runGlint("render " + scene + " --frames 0-3 --list-missing" + out);
  EXPECT_EQ(list.out, "");
  // Tiles are frames' pieces: a tile's file is complete for its own window only.
  ASSERT_EQ(
      test::runGlint("render " + scene + " --frames 0-1 --tile 1/2 --quiet -o " + dir + "/t1_#.exr")
          .exitCode,
      0);
  EXPECT_EQ(test::runGlint("render " + scene + " --frames 0-1 --tile 1/2 --list-missing -o " + dir +
                           "/t1_#.exr")
                .out,
            "");
  EXPECT_EQ(test::runGlint("render " + scene + " --frames 0-1 --tile 0/2 --list-missing -o " + dir +
                           "/t1_#.exr")
                .out,
            "0\n1\n");
}

TEST(CliFrames, BadSequenceArgumentsExitTwo) {
  std::string dir = test::scratchDir("CliFrames.Bad");
  std::string scene = writeMovingBallScene(dir);
  struct Case {
    std::string args, message;
  } cases[] = {
      {"--frames 0-2 -o " + dir + "/still.exr", "needs a '#' run"},
      {"--frames 5-2 -o " + dir + "/f_#.exr", "before the first"},
      {"--frames 0-2:0 -o " + dir + "/f_#.exr", "step"},
      {"--time-limit 5x -o " + dir + "/x.exr", "--time-limit '5x': need a duration > 0"},
      {"--time-limit 0s -o " + dir + "/x.exr", "--time-limit '0s': need a duration > 0"},
      {"--time-limit 1h30 -o " + dir + "/x.exr", "--time-limit '1h30': need a duration"},
      {"--noise-target 2 -o " + dir + "/x.exr", "--noise-target: must be > 0 and < 1"},
      {"--list-missing -o " + dir + "/x.exr", "--list-missing applies to a sequence"},
      {"--frames 0-1 --tile 0/17 --resume -o " + dir + "/f_#.exr", "N <= the image height"},
      {"--frames 0-1 --time 0.5 -o " + dir + "/f_#.exr", "exclude each other"},
      {"--frames 0-1 --fps 0 -o " + dir + "/f_#.exr", "--fps must be > 0"},
  };
  for (const Case& c : cases) {
    auto r = test::runGlint("render " + scene + " " + c.args + " --quiet");
    EXPECT_EQ(r.exitCode, 2) << c.args;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
  }
  EXPECT_FALSE(fs::exists(dir + "/f_0.exr"));
}

TEST(CliFrames, TimeOptionRendersOneFrameAtThatTime) {
  std::string dir = test::scratchDir("CliFrames.Time");
  std::string scene = writeMovingBallScene(dir);
  auto r = test::runGlint("render " + scene + " --time 0.75 -o " + dir + "/t.exr --quiet");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NEAR(brightCentroidX(dir + "/t.exr"), 20, 0.5);  // x = 0.5
}

}  // namespace
}  // namespace glint::app
