// Tests for image/output: EXR contents and metadata, display-referred 8-bit output through
// the shipped OCIO config, exposure, and atomic writes that never destroy a good image.
#include "image/output.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>

#include "image/color.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace glint {
namespace {

using test::ScopedEnv;

using test::constantFilm;
using test::sampleMetadata;

struct ReadImage {
  OIIO::ImageSpec spec;
  std::vector<float> pixels;
  float at(int x, int y, const std::string& channel) const {
    int c = spec.channelindex(channel);
    EXPECT_GE(c, 0) << "no channel " << channel;
    if (c < 0) return NAN;
    return pixels[(size_t(y) * size_t(spec.width) + size_t(x)) * size_t(spec.nchannels) +
                  size_t(c)];
  }
};

ReadImage readBack(const std::string& path) {
  ReadImage r;
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << OIIO::geterror();
  if (!in) return r;
  r.spec = in->spec();
  r.pixels.resize(size_t(r.spec.width) * size_t(r.spec.height) * size_t(r.spec.nchannels));
  EXPECT_TRUE(in->read_image(0, 0, 0, -1, OIIO::TypeDesc::FLOAT, r.pixels.data()));
  in->close();
  return r;
}

// The 8-bit code value of channel c at (0, 0) of an integer image.
int code8(const std::string& path, int c = 0) {
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << OIIO::geterror();
  if (!in) return -1;
  EXPECT_EQ(in->spec().format, OIIO::TypeDesc::UINT8);
  std::vector<unsigned char> px(size_t(in->spec().image_pixels()) * size_t(in->spec().nchannels));
  EXPECT_TRUE(in->read_image(0, 0, 0, -1, OIIO::TypeDesc::UINT8, px.data()));
  return px[size_t(c)];
}

using test::listFolder;
using test::slurp;

using test::aovFilm;

void expectAovFilm(const ReadImage& r, const Film& film) {
  // Each EXR channel and the film value it must hold exactly.
  struct Channel {
    const char* name;
    float (*value)(const Film&, size_t);
  };
  static const Channel channels[] = {
      {"R", [](const Film& f, size_t i) { return f.color[i].x; }},
      {"G", [](const Film& f, size_t i) { return f.color[i].y; }},
      {"B", [](const Film& f, size_t i) { return f.color[i].z; }},
      {"A", [](const Film& f, size_t i) { return f.alpha[i]; }},
      {"albedo.R", [](const Film& f, size_t i) { return f.albedo[i].x; }},
      {"albedo.G", [](const Film& f, size_t i) { return f.albedo[i].y; }},
      {"albedo.B", [](const Film& f, size_t i) { return f.albedo[i].z; }},
      {"N.X", [](const Film& f, size_t i) { return f.normal[i].x; }},
      {"N.Y", [](const Film& f, size_t i) { return f.normal[i].y; }},
      {"N.Z", [](const Film& f, size_t i) { return f.normal[i].z; }},
      {"Z", [](const Film& f, size_t i) { return f.depth[i]; }},
      {"variance.R", [](const Film& f, size_t i) { return f.variance[i].x; }},
      {"variance.G", [](const Film& f, size_t i) { return f.variance[i].y; }},
      {"variance.B", [](const Film& f, size_t i) { return f.variance[i].z; }},
  };
  for (int y = 0; y < film.height; ++y)
    for (int x = 0; x < film.width; ++x)
      for (const Channel& c : channels)
        EXPECT_EQ(r.at(x, y, c.name), c.value(film, film.index(x, y))) << c.name;
}

void expectMetadata(const OIIO::ImageSpec& spec) {
  EXPECT_EQ(spec.get_string_attribute("Software"), "glint");
  EXPECT_EQ(spec.get_string_attribute("glint:scene"), "scenes/cornell.gltf");
  EXPECT_EQ(spec.get_int_attribute("glint:spp"), 64);
  EXPECT_EQ(spec.get_string_attribute("glint:seed"), "18446744073709551557");
  EXPECT_DOUBLE_EQ(spec.get_float_attribute("glint:render_seconds"), 12.5);
  EXPECT_EQ(spec.get_string_attribute("glint:accel"), "embree");
  EXPECT_EQ(spec.get_string_attribute("glint:integrator"), "path");
}

// ---- EXR -------------------------------------------------------------------------------------

TEST(Output, ExrRoundTripKeepsMetadata) {
  std::string dir = test::scratchDir("Output.ExrRoundTripKeepsMetadata");
  std::string path = dir + "/img.exr";
  Film film = aovFilm();
  writeImage(path, film, RenderSettings{}, sampleMetadata());

  ReadImage r = readBack(path);
  EXPECT_EQ(r.spec.width, 4);
  EXPECT_EQ(r.spec.height, 3);
  EXPECT_EQ(r.spec.nchannels, 14);
  EXPECT_EQ(r.spec.format, OIIO::TypeDesc::FLOAT);
  expectAovFilm(r, film);
  expectMetadata(r.spec);
  EXPECT_EQ(listFolder(dir), std::vector<std::string>{"img.exr"});  // no temp file left
}

TEST(Output, ExrHalfRoundTripKeepsDepthAsFloat) {
  std::string dir = test::scratchDir("Output.ExrHalfRoundTripKeepsDepthAsFloat");
  std::string path = dir + "/img.exr";
  Film film = aovFilm();
  RenderSettings settings;
  settings.exrHalf = true;
  writeImage(path, film, settings, sampleMetadata());

  ReadImage r = readBack(path);
  ASSERT_EQ(r.spec.nchannels, 14);
  ASSERT_EQ(r.spec.channelformats.size(), 14u);
  EXPECT_EQ(r.spec.channelformat(r.spec.channelindex("R")), OIIO::TypeDesc::HALF);
  EXPECT_EQ(r.spec.channelformat(r.spec.channelindex("variance.B")), OIIO::TypeDesc::HALF);
  EXPECT_EQ(r.spec.channelformat(r.spec.channelindex("Z")), OIIO::TypeDesc::FLOAT);
  expectAovFilm(r, film);  // every value in aovFilm is exact in its channel's type
  expectMetadata(r.spec);
}

// Without AOVs an EXR is RGBA and the variance of each pixel's mean: what --resume continues
// from and `glint diff --statistical` tests against.
TEST(Output, ExrWithoutAovsIsRgbaAndVariance) {
  std::string dir = test::scratchDir("Output.ExrWithoutAovsIsRgbaAndVariance");
  Film film = constantFilm(2, 2, {1.5f, 0.25f, 100.0f});
  film.alpha[3] = 0;
  RenderSettings settings;
  settings.exrHalf = true;
  writeImage(dir + "/img.exr", film, settings, {});
  ReadImage r = readBack(dir + "/img.exr");
  ASSERT_EQ(r.spec.nchannels, 7);
  EXPECT_EQ(r.spec.channelnames[4], "variance.R");
  EXPECT_EQ(r.spec.format, OIIO::TypeDesc::HALF);
  EXPECT_EQ(r.spec.alpha_channel, 3);
  EXPECT_EQ(r.at(0, 0, "R"), 1.5f);  // scene-linear: no clamping, no display transform
  EXPECT_EQ(r.at(0, 0, "B"), 100.0f);
  EXPECT_EQ(r.at(1, 1, "A"), 0.0f);
}

// ---- display-referred ------------------------------------------------------------------------

TEST(Output, PngGoesThroughShippedSrgbView) {
  ScopedEnv noOcio("OCIO", nullptr);
  std::string dir = test::scratchDir("Output.PngGoesThroughShippedSrgbView");
  const std::pair<float, int> cases[] = {{0.0f, 0},   {0.5f, 188},      {1.0f, 255},
                                         {7.0f, 255}, {0.0031308f, 10}, {-1.0f, 0}};
  for (auto [linear, expected] : cases) {
    std::string path = dir + "/v.png";
    writeImage(path, constantFilm(3, 2, {linear, linear, linear}), RenderSettings{}, {});
    for (int c = 0; c < 3; ++c) EXPECT_EQ(code8(path, c), expected) << "linear " << linear;
  }
  auto in = OIIO::ImageInput::open(dir + "/v.png");
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().nchannels, 3);
  EXPECT_EQ(in->spec().get_string_attribute("Software"), "glint");
}

TEST(Output, ExposurePlusOneDoublesDisplayValues) {
  ScopedEnv noOcio("OCIO", nullptr);
  std::string dir = test::scratchDir("Output.ExposurePlusOneDoublesDisplayValues");
  RenderSettings settings;
  settings.tonemap.view = "Raw";  // no curve: code values are proportional to radiance
  Film film = constantFilm(2, 2, {0.2f, 0.12f, 0.4f});
  writeImage(dir + "/e0.png", film, settings, {});
  settings.tonemap.exposure = 1;
  writeImage(dir + "/e1.png", film, settings, {});
  EXPECT_EQ(code8(dir + "/e0.png", 0), 51);
  EXPECT_EQ(code8(dir + "/e1.png", 0), 102);
  EXPECT_EQ(code8(dir + "/e0.png", 1), 31);  // 30.6
  EXPECT_EQ(code8(dir + "/e1.png", 1), 61);  // 61.2
  EXPECT_EQ(code8(dir + "/e1.png", 2), 204);

  // Through the sRGB curve, +1 stop at 0.25 is the same as 0.5 unexposed.
  settings.tonemap.view = "";
  writeImage(dir + "/s1.png", constantFilm(1, 1, {0.25f, 0.25f, 0.25f}), settings, {});
  EXPECT_EQ(code8(dir + "/s1.png"), 188);
}

TEST(Output, TiffIs16BitAndJpegIs8Bit) {
  ScopedEnv noOcio("OCIO", nullptr);
  std::string dir = test::scratchDir("Output.TiffIs16BitAndJpegIs8Bit");
  Film film = constantFilm(8, 8, {0.5f, 0.5f, 0.5f});
  writeImage(dir + "/a.tif", film, RenderSettings{}, {});
  writeImage(dir + "/a.JPEG", film, RenderSettings{}, {});
  ReadImage tif = readBack(dir + "/a.tif");
  EXPECT_EQ(tif.spec.format, OIIO::TypeDesc::UINT16);
  EXPECT_NEAR(tif.at(3, 3, "G"), 0.735357f, 1.0f / 65535.0f);
  ReadImage jpg = readBack(dir + "/a.JPEG");
  EXPECT_EQ(jpg.spec.format, OIIO::TypeDesc::UINT8);
  EXPECT_NEAR(jpg.at(3, 3, "G") * 255.0f, 188.0f, 1.0f);
}

TEST(Output, WardToneMappingChangesDisplayOutputOnly) {
  ScopedEnv noOcio("OCIO", nullptr);
  std::string dir = test::scratchDir("Output.WardToneMappingChangesDisplayOutputOnly");
  RenderSettings settings;
  settings.tonemap.op = "ward";
  settings.tonemap.view = "Raw";
  // Lw = 0.2 · 100 cd/m² → Lwa = 20 + δ; m = ((1.219 + 50^0.4) / (1.219 + Lwa^0.4))^2.5.
  Film film = constantFilm(4, 4, {0.2f, 0.2f, 0.2f});
  writeImage(dir + "/w.png", film, settings, {});
  double lwa = 20.0 + 1e-4;
  double m = std::pow((1.219 + std::pow(50.0, 0.4)) / (1.219 + std::pow(lwa, 0.4)), 2.5);
  EXPECT_EQ(code8(dir + "/w.png"), int(std::lround(0.2 * 100.0 * m / 100.0 * 255.0)));
  writeImage(dir + "/w.exr", film, settings, {});
  EXPECT_FLOAT_EQ(readBack(dir + "/w.exr").at(0, 0, "R"), 0.2f);  // EXR stays scene-linear
}

TEST(Output, OcioEnvironmentConfigIsHonoured) {
  std::string dir = test::scratchDir("Output.OcioEnvironmentConfigIsHonoured");
  std::string config = slurp(defaultOcioConfigPath());
  // The same config with the sRGB display's views swapped: Raw becomes the default.
  std::string standard =
      "    - !<View> {name: Standard, colorspace: sRGB Encoded Rec.709 (sRGB)}\n";
  std::string raw = "    - !<View> {name: Raw, colorspace: Raw}\n";
  size_t at = config.find(standard + raw);
  ASSERT_NE(at, std::string::npos);
  config.replace(at, standard.size() + raw.size(), raw + standard);
  std::ofstream(dir + "/raw_default.ocio") << config;

  ScopedEnv ocio("OCIO", (dir + "/raw_default.ocio").c_str());
  writeImage(dir + "/half.png", constantFilm(2, 2, {0.5f, 0.5f, 0.5f}), RenderSettings{}, {});
  EXPECT_EQ(code8(dir + "/half.png"), 128);
}

TEST(Output, UnknownViewIsAColorErrorAndWritesNothing) {
  ScopedEnv noOcio("OCIO", nullptr);
  std::string dir = test::scratchDir("Output.UnknownViewIsAColorErrorAndWritesNothing");
  RenderSettings settings;
  settings.tonemap.view = "Filmic";
  try {
    writeImage(dir + "/x.png", constantFilm(2, 2, {}), settings, {});
    FAIL() << "expected ColorError";
  } catch (const ColorError& e) {
    EXPECT_NE(std::string(e.what()).find("'Standard', 'Raw'"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(listFolder(dir).empty());
}

// ---- formats and atomic writes ---------------------------------------------------------------

TEST(Output, UnknownExtensionIsRejectedWithAReason) {
  std::string why;
  EXPECT_TRUE(isSupportedOutput("a/b.EXR", &why));
  EXPECT_TRUE(isSupportedOutput("b.jpeg", &why));
  EXPECT_TRUE(isSupportedOutput("b.tif", &why));
  EXPECT_FALSE(isSupportedOutput("render.bmp", &why));
  EXPECT_NE(why.find(".bmp"), std::string::npos) << why;
  EXPECT_NE(why.find(".exr"), std::string::npos) << why;
  EXPECT_FALSE(isSupportedOutput("render", &why));
  EXPECT_NE(why.find("no file extension"), std::string::npos) << why;
  EXPECT_THROW(writeImage("render.bmp", constantFilm(1, 1, {}), RenderSettings{}, {}), OutputError);
}

TEST(Output, TargetThatIsAFolderThrowsAndLeavesNoTempFile) {
  std::string dir = test::scratchDir("Output.TargetThatIsAFolderThrowsAndLeavesNoTempFile");
  fs::create_directory(dir + "/img.exr");
  EXPECT_THROW(writeImage(dir + "/img.exr", constantFilm(2, 2, {1, 1, 1}), RenderSettings{}, {}),
               OutputError);
  EXPECT_EQ(listFolder(dir), std::vector<std::string>{"img.exr"});
  EXPECT_TRUE(fs::is_directory(dir + "/img.exr"));
}

TEST(Output, MissingFolderThrows) {
  std::string dir = test::scratchDir("Output.MissingFolderThrows");
  EXPECT_THROW(writeImage(dir + "/no/such/img.png", constantFilm(2, 2, {}), RenderSettings{}, {}),
               OutputError);
}

// A write that fails half-way (here: the file-size limit stands in for a full disk) must leave
// the previous image byte-identical and no temporary file behind.
TEST(Output, FailedWriteKeepsPreviousImage) {
  std::string dir = test::scratchDir("Output.FailedWriteKeepsPreviousImage");
  std::string path = dir + "/img.exr";
  writeImage(path, constantFilm(4, 4, {0.5f, 0.5f, 0.5f}), RenderSettings{}, sampleMetadata());
  const std::string good = slurp(path);
  ASSERT_FALSE(good.empty());

  // Noise does not compress, so this EXR is far larger than the limit.
  Film big(256, 256, true);
  uint32_t state = 12345;
  for (Rgb& c : big.color) {
    state = state * 1664525u + 1013904223u;
    c = {float(state >> 8) / float(1u << 24), float(state & 0xffff) / 65536.0f, 0.5f};
  }
  rlimit saved{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &saved), 0);
  auto oldHandler = std::signal(SIGXFSZ, SIG_IGN);  // a failed write(), not a killed process
  rlimit limited = saved;
  limited.rlim_cur = 16 * 1024;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limited), 0);
  bool threw = false;
  std::string message;
  try {
    writeImage(path, big, RenderSettings{}, sampleMetadata());
  } catch (const OutputError& e) {
    threw = true;
    message = e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &saved);
  std::signal(SIGXFSZ, oldHandler);

  EXPECT_TRUE(threw);
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_EQ(slurp(path), good);
  EXPECT_EQ(listFolder(dir), std::vector<std::string>{"img.exr"});
}

TEST(Output, RewriteReplacesTheImage) {
  std::string dir = test::scratchDir("Output.RewriteReplacesTheImage");
  std::string path = dir + "/img.exr";
  writeImage(path, constantFilm(2, 2, {1, 2, 3}), RenderSettings{}, {});
  writeImage(path, constantFilm(2, 2, {4, 5, 6}), RenderSettings{}, {});
  EXPECT_EQ(readBack(path).at(1, 1, "G"), 5.0f);
  EXPECT_EQ(listFolder(dir), std::vector<std::string>{"img.exr"});
}

}  // namespace
}  // namespace glint
