// Pieces of a frame: `glint render --crop/--tile` and `glint assemble`. Samples are keyed by
// pixel, sample and seed, so a frame rendered in tiles on one thread and assembled equals the
// frame rendered whole on two threads bit for bit, AOVs and variance included.
#include "apps/tiles.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "geometry/error.h"
#include "test_support.h"

namespace glint::app {
namespace {

struct Pixels {
  OIIO::ImageSpec spec;
  std::vector<float> values;
};

Pixels readAll(const std::string& path) {
  Pixels p;
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << path;
  if (!in) return p;
  p.spec = in->spec();
  p.values.resize(size_t(p.spec.image_pixels()) * size_t(p.spec.nchannels));
  EXPECT_TRUE(in->read_image(0, 0, 0, p.spec.nchannels, OIIO::TypeDesc::FLOAT, p.values.data()));
  return p;
}

// The lens + motion blur camera: every sampler dimension of a camera path is used.
std::string scene() { return "'" + test::sourceDir() + "/scenes/motion/effects.json'"; }
const std::string kSmall = " --width 40 --height 30 --spp 4 --aovs --quiet";

TEST(Tiles, ArgumentsAreCheckedWithTheReason) {
  EXPECT_EQ(parseCropWindow("1,2,30,40"), (PixelWindow{1, 2, 30, 40}));
  EXPECT_EQ(parseTileSpec("2/5").index, 2);
  EXPECT_EQ(parseTileSpec("2/5").count, 5);
  for (const char* bad :
       {"", "1,2,3", "1,2,3,4,5", "3,0,3,4", "0,5,4,2", "-1,0,2,2", "a,b,c,d", "1,2,3,4x"})
    EXPECT_THROW(parseCropWindow(bad), InputError) << bad;
  for (const char* bad : {"", "1", "3/3", "-1/2", "0/0", "1/2/3", "x/2"})
    EXPECT_THROW(parseTileSpec(bad), InputError) << bad;
  // Bands cover the image exactly, in order.
  int next = 0;
  for (int i = 0; i < 7; ++i) {
    const PixelWindow w = tileWindow(50, 30, i, 7);
    EXPECT_EQ(w.y0, next);
    EXPECT_GT(w.height(), 0);
    EXPECT_EQ(w.width(), 50);
    next = w.y1;
  }
  EXPECT_EQ(next, 30);
  EXPECT_THROW(tileWindow(50, 30, 0, 31), InputError);
}

TEST(Tiles, AssembledTilesEqualTheWholeFrameBitForBit) {
  const std::string dir = test::scratchDir("tiles_assemble");
  ASSERT_EQ(test::runGlint("render " + scene() + kSmall + " --threads 2 -o " + dir + "/whole.exr")
                .exitCode,
            0);
  for (int i = 0; i < 3; ++i) {
    const test::CommandResult r =
        test::runGlint("render " + scene() + kSmall + " --threads 1 --tile " + std::to_string(i) +
                       "/3 -o " + dir + "/tile_" + std::to_string(i) + ".exr");
    ASSERT_EQ(r.exitCode, 0) << r.err;
  }
  const Pixels piece = readAll(dir + "/tile_1.exr");
  EXPECT_EQ(piece.spec.y, 10);  // the data window of band 1 of 3 in 30 rows
  EXPECT_EQ(piece.spec.height, 10);
  EXPECT_EQ(piece.spec.full_height, 30);
  const test::CommandResult a =
      test::runGlint("assemble '" + dir + "/tile_#.exr' -o " + dir + "/assembled.exr");
  ASSERT_EQ(a.exitCode, 0) << a.err;
  const Pixels whole = readAll(dir + "/whole.exr"), assembled = readAll(dir + "/assembled.exr");
  EXPECT_EQ(assembled.spec.width, 40);
  EXPECT_EQ(assembled.spec.height, 30);
  EXPECT_EQ(assembled.spec.channelnames, whole.spec.channelnames);
  EXPECT_GT(whole.spec.nchannels, 4);  // AOVs and variance are compared too
  ASSERT_EQ(assembled.values.size(), whole.values.size());
  size_t differ = 0;
  for (size_t i = 0; i < whole.values.size(); ++i)
    differ += std::memcmp(&whole.values[i], &assembled.values[i], sizeof(float)) != 0;
  EXPECT_EQ(differ, 0u);
  // So the checksum that --resume trusts is the same too.
  EXPECT_EQ(assembled.spec.get_string_attribute("glint:checksum"),
            whole.spec.get_string_attribute("glint:checksum"));
  EXPECT_EQ(assembled.spec.get_string_attribute("glint:checksum").size(), 16u);
  // The frame's estimated error, not the first tile's.
  const auto error = [](const Pixels& p) {
    const OIIO::ParamValue* e = p.spec.find_attribute("glint:error", OIIO::TypeDesc::DOUBLE);
    return e ? e->get<double>() : -1.0;
  };
  EXPECT_GT(error(whole), 0);
  EXPECT_DOUBLE_EQ(error(assembled), error(whole));
}

TEST(Tiles, ACropIsThatPartOfTheWholeFrame) {
  const std::string dir = test::scratchDir("tiles_crop");
  ASSERT_EQ(test::runGlint("render " + scene() + kSmall + " -o " + dir + "/whole.exr").exitCode, 0);
  const test::CommandResult r =
      test::runGlint("render " + scene() + kSmall + " --crop 7,3,29,21 -o " + dir + "/crop.exr");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const Pixels whole = readAll(dir + "/whole.exr"), crop = readAll(dir + "/crop.exr");
  ASSERT_EQ(crop.spec.width, 22);
  ASSERT_EQ(crop.spec.height, 18);
  EXPECT_EQ(crop.spec.x, 7);
  EXPECT_EQ(crop.spec.full_width, 40);
  const int n = whole.spec.nchannels;
  size_t differ = 0;
  for (int y = 0; y < crop.spec.height; ++y)
    for (int x = 0; x < crop.spec.width; ++x)
      for (int c = 0; c < n; ++c)
        differ += crop.values[(size_t(y) * 22 + size_t(x)) * size_t(n) + size_t(c)] !=
                  whole.values[(size_t(y + 3) * 40 + size_t(x + 7)) * size_t(n) + size_t(c)];
  EXPECT_EQ(differ, 0u);
}

TEST(Tiles, BadPiecesAndArgumentsAreInputErrors) {
  const std::string dir = test::scratchDir("tiles_errors");
  for (int i = 0; i < 2; ++i)
    ASSERT_EQ(test::runGlint("render " + scene() + kSmall + " --tile " + std::to_string(i) +
                             "/2 -o " + dir + "/t" + std::to_string(i) + ".exr")
                  .exitCode,
              0);
  ASSERT_EQ(test::runGlint("render " + scene() +
                           " --width 40 --height 30 --spp 8 --aovs --quiet --tile 1/2 -o " + dir +
                           "/other.exr")
                .exitCode,
            0);
  struct Case {
    std::string args, phrase;
  };
  for (const Case& c : std::vector<Case>{
           {"assemble " + dir + "/t0.exr -o " + dir + "/a.exr", "in no piece"},
           {"assemble " + dir + "/t0.exr " + dir + "/t0.exr -o " + dir + "/a.exr",
            "also in an earlier piece"},
           {"assemble " + dir + "/t0.exr " + dir + "/other.exr -o " + dir + "/a.exr", "glint:spp"},
           {"assemble " + dir + "/missing.exr -o " + dir + "/a.exr", "missing.exr"},
           {"render " + scene() + kSmall + " --tile 0/2 -o " + dir + "/t.png", "partial EXRs"},
           {"render " + scene() + kSmall + " --crop 0,0,41,5 -o " + dir + "/t.exr",
            "outside the 40x30 image"},
           {"render " + scene() + kSmall + " --crop 0,0,4,5 --tile 0/2 -o " + dir + "/t.exr",
            "exclude each other"},
       }) {
    const test::CommandResult r = test::runGlint(c.args);
    EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.phrase), std::string::npos) << c.args << "\n" << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/a.exr"));
}

}  // namespace
}  // namespace glint::app
