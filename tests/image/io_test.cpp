// Tests for image/io and image/exr: OpenEXR files read with the OpenEXR library present what
// OpenImageIO's reader presented (channel order, windows, types, values), damaged files are
// DecodeErrors that say whether the header was read, and glint needs its OpenImageIO plugin
// only for other formats.
#include "image/io.h"

#include <Imath/half.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "image/exr.h"
#include "test_support.h"

namespace glint {
namespace {

// An EXR written by OpenImageIO (not by glint): channels out of the usual order, a data window
// inside a larger display window, 4x4 tiles, half and float channels mixed.
std::string writeOddExr(const std::string& dir, std::vector<float>* values) {
  const std::string path = dir + "/odd.exr";
  const std::vector<std::string> names = {"Z", "albedo.G", "B", "A", "albedo.R", "G", "R", "extra"};
  OIIO::ImageSpec spec(5, 3, int(names.size()), OIIO::TypeDesc::HALF);
  spec.channelnames = names;
  spec.channelformats.assign(names.size(), OIIO::TypeDesc::HALF);
  spec.channelformats[0] = OIIO::TypeDesc::FLOAT;  // Z
  spec.x = 2, spec.y = 1;
  spec.full_x = 0, spec.full_y = 0, spec.full_width = 8, spec.full_height = 6;
  spec.tile_width = spec.tile_height = 4;
  spec.attribute("glint:spp", 12);
  spec.attribute("glint:seed", "7");
  values->clear();
  for (int i = 0; i < 5 * 3 * int(names.size()); ++i) values->push_back(0.25f * float(i));
  auto out = OIIO::ImageOutput::create(path);
  EXPECT_TRUE(out && out->open(path, spec)) << OIIO::geterror();
  EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, values->data())) << out->geterror();
  out->close();
  return path;
}

TEST(ImageIo, ExrReadsAsOpenImageIOPresentsIt) {
  const std::string dir = test::scratchDir("ImageIo.ExrReadsAsOpenImageIOPresentsIt");
  std::vector<float> written;
  const std::string path = writeOddExr(dir, &written);
  ASSERT_TRUE(isExrFile(path));

  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in) << OIIO::geterror();
  const OIIO::ImageSpec spec = in->spec();
  std::vector<float> expected(size_t(spec.image_pixels()) * size_t(spec.nchannels));
  ASSERT_TRUE(in->read_image(0, 0, 0, -1, OIIO::TypeDesc::FLOAT, expected.data()));

  const Image image = readImage(path);
  EXPECT_EQ(image.format, "openexr");
  EXPECT_EQ(image.names, spec.channelnames);
  EXPECT_EQ(image.names,
            (std::vector<std::string>{"R", "G", "B", "A", "Z", "extra", "albedo.R", "albedo.G"}));
  EXPECT_EQ(image.width, 5);
  EXPECT_EQ(image.height, 3);
  EXPECT_EQ(image.x, 2);
  EXPECT_EQ(image.y, 1);
  EXPECT_EQ(image.fullWidth, 8);
  EXPECT_EQ(image.fullHeight, 6);
  EXPECT_EQ(image.type, PixelType::Half);
  EXPECT_TRUE(image.floatingPoint);
  EXPECT_EQ(image.meta.spp, 12);
  EXPECT_TRUE(image.hasSeed);
  EXPECT_EQ(image.meta.seed, 7u);
  EXPECT_EQ(image.attribute("glint:spp"), "12");
  EXPECT_EQ(image.pixels, expected);
  // And the values are the ones written (all exact in half), each under its own name.
  const int extra = image.channel("extra");
  ASSERT_GE(extra, 0);
  EXPECT_EQ(image.pixels[size_t(image.channels) * 4 + size_t(extra)], written[8 * 4 + 7]);
}

TEST(ImageIo, GlintExrRoundTripsThroughItsOwnReader) {
  const std::string dir = test::scratchDir("ImageIo.GlintExrRoundTripsThroughItsOwnReader");
  Image image;
  image.width = 3, image.height = 2, image.channels = 5;
  image.names = {"R", "G", "B", "A", "Z"};
  image.x = 1, image.y = 4, image.fullWidth = 10, image.fullHeight = 10;
  image.type = PixelType::Half;
  for (int i = 0; i < 30; ++i) image.pixels.push_back(i == 4 ? 1e6f : 0.1f * float(i));
  image.hasMeta = true;
  image.meta.scene = "s.json";
  image.meta.spp = 3;
  image.meta.stop = "time-limit";
  image.meta.error = 0.02;
  writeImageFile(dir + "/a.exr", image);

  const Image back = readImage(dir + "/a.exr");
  EXPECT_EQ(back.names, image.names);
  EXPECT_EQ(back.x, 1);
  EXPECT_EQ(back.y, 4);
  EXPECT_EQ(back.fullWidth, 10);
  EXPECT_EQ(back.type, PixelType::Half);
  EXPECT_EQ(back.pixels[4], 1e6f);  // Z stays float: half would overflow
  EXPECT_EQ(back.pixels[1], float(Imath::half(0.1f)));
  EXPECT_EQ(back.meta.scene, "s.json");
  EXPECT_EQ(back.meta.stop, "time-limit");
  EXPECT_DOUBLE_EQ(back.meta.error, 0.02);
  EXPECT_EQ(back.checksum, pixelChecksum(back.pixels, back.names));
}

// Every glint attribute comes back as it was written, whatever the format: the EXR writer and
// the OpenImageIO plugin walk one list of them (forEachMetadataField), and a format that keeps
// attributes as text (PNG) hands numbers back as strings, which the reader parses.
TEST(ImageIo, GlintAttributesRoundTripInEveryFormat) {
  const std::string dir = test::scratchDir("ImageIo.GlintAttributesRoundTripInEveryFormat");
  Image image;
  image.width = 4, image.height = 2, image.channels = 4;
  image.names = {"R", "G", "B", "A"};
  image.fullWidth = 4, image.fullHeight = 2;
  for (int i = 0; i < 32; ++i) image.pixels.push_back(float(i % 4) / 4.0f);
  image.hasMeta = true;
  image.meta.scene = "scenes/a b.json";
  image.meta.spp = 1024;
  image.meta.seed = 18446744073709551557ull;  // above 2^63: no integer attribute holds it
  image.meta.renderSeconds = 12.345678912345;
  image.meta.accel = "kdtree";
  image.meta.integrator = "whitted";
  image.meta.time = 1.0 / 3.0;
  image.meta.stop = "noise-target";
  image.meta.error = 0.0123456789012;
  for (const char* ext : {"exr", "png", "tif", "jpg"}) {
    SCOPED_TRACE(ext);
    Image written = image;
    if (std::string(ext) != "exr") written.type = PixelType::UInt8;
    const std::string path = dir + "/a." + ext;
    writeImageFile(path, written);
    const Image back = readImage(path);
    EXPECT_TRUE(back.hasMeta);
    EXPECT_TRUE(back.hasSeed);
    EXPECT_TRUE(back.hasTime);
    EXPECT_EQ(back.meta.scene, image.meta.scene);
    EXPECT_EQ(back.meta.spp, image.meta.spp);
    EXPECT_EQ(back.meta.seed, image.meta.seed);
    EXPECT_EQ(back.meta.accel, image.meta.accel);
    EXPECT_EQ(back.meta.integrator, image.meta.integrator);
    EXPECT_EQ(back.meta.stop, image.meta.stop);
    // Doubles to the last bit where the format stores them, and to the text's 17 digits where
    // it stores text: the same either way.
    EXPECT_EQ(back.meta.renderSeconds, image.meta.renderSeconds);
    EXPECT_EQ(back.meta.time, image.meta.time);
    EXPECT_EQ(back.meta.error, image.meta.error);
    // Shown as the EXR reader shows them: text quoted, numbers bare.
    EXPECT_EQ(back.attribute("glint:scene"), "\"scenes/a b.json\"");
    EXPECT_EQ(back.attribute("glint:spp"), "1024");
  }
  // Without a stop reason the stop and its error are not written at all.
  Image plain = image;
  plain.meta.stop.clear();
  plain.type = PixelType::UInt8;
  for (const char* ext : {"exr", "png"}) {
    const std::string path = dir + "/plain." + ext;
    writeImageFile(path, plain);
    const Image back = readImage(path);
    EXPECT_EQ(back.attribute("glint:stop"), "(none)") << ext;
    EXPECT_EQ(back.attribute("glint:error"), "(none)") << ext;
    EXPECT_EQ(back.meta.error, 0.0) << ext;
    EXPECT_EQ(back.meta.spp, 1024) << ext;
  }
}

TEST(ImageIo, TruncatedExrIsADecodeErrorAfterItsHeader) {
  const std::string dir = test::scratchDir("ImageIo.TruncatedExrIsADecodeErrorAfterItsHeader");
  Image image;
  image.width = 64, image.height = 64, image.channels = 3;
  image.names = {"R", "G", "B"};
  for (size_t i = 0; i < 64 * 64 * 3; ++i) image.pixels.push_back(float(i % 97) / 7.0f);
  const std::string path = dir + "/t.exr";
  writeImageFile(path, image);
  std::filesystem::resize_file(path, std::filesystem::file_size(path) * 2 / 3);

  EXPECT_EQ(readImage(path, /*pixels=*/false).width, 64);  // the header is intact
  try {
    readImage(path);
    FAIL() << "a truncated file read";
  } catch (const DecodeError& e) {
    EXPECT_TRUE(e.afterHeader());
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }

  std::ofstream(dir + "/junk.exr") << "v/1\x01 and then nothing an EXR header needs";
  try {
    readImage(dir + "/junk.exr");
    FAIL() << "junk read";
  } catch (const DecodeError& e) {
    EXPECT_FALSE(e.afterHeader());
  }
}

// glint renders to EXR without its OpenImageIO plugin (it never loads it); a PNG needs it, and
// a missing plugin is a clear failure (exit code 1), never a crash or a half-written file.
TEST(ImageIo, OnlyOtherFormatsNeedTheOpenImageIOPlugin) {
  const std::string dir = test::scratchDir("ImageIo.OnlyOtherFormatsNeedTheOpenImageIOPlugin");
  const std::string scene = dir + "/ball.json";
  std::ofstream(scene) << test::litBallJson(16, 12);
  test::ScopedEnv noPlugin("GLINT_OIIO_PLUGIN", (dir + "/missing/libglint_oiio.so").c_str());

  test::CommandResult exr =
      test::runGlint("render '" + scene + "' -q --spp 2 -o '" + dir + "/ball.exr'");
  EXPECT_EQ(exr.exitCode, 0) << exr.err;
  EXPECT_TRUE(std::filesystem::exists(dir + "/ball.exr"));

  test::CommandResult png =
      test::runGlint("render '" + scene + "' -q --spp 2 -o '" + dir + "/ball.png'");
  EXPECT_EQ(png.exitCode, 1) << png.err;
  EXPECT_NE(png.err.find("OpenImageIO plugin"), std::string::npos) << png.err;
  EXPECT_NE(png.err.find("missing/libglint_oiio.so"), std::string::npos) << png.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/ball.png"));
  EXPECT_EQ(test::listFolder(dir), (std::vector<std::string>{"ball.exr", "ball.json"}));

  // An image texture needs it too; its absence is not the scene's fault (exit code 1, not 2).
  test::CommandResult textured =
      test::runGlint("render '" + test::dataDir() + "/scenes/textured_quad.gltf' -q --spp 1 -o '" +
                     dir + "/quad.exr'");
  EXPECT_EQ(textured.exitCode, 1) << textured.err;
  EXPECT_NE(textured.err.find("OpenImageIO plugin"), std::string::npos) << textured.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/quad.exr"));
}

}  // namespace
}  // namespace glint
