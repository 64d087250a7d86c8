// Tests for image/color: the shipped OCIO config, $OCIO, display/view lookup and transforms.
#include "image/color.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <optional>
#include <vector>

#include "image/output.h"
#include "test_support.h"

namespace glint {
namespace {

using test::ScopedEnv;

// IEC 61966-2-1 encoding.
double srgbEncode(double v) {
  return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

// A minimal valid config whose only display has Raw as its default view.
const char* kRawDefaultConfig = R"(ocio_profile_version: 2
roles:
  default: linear
  scene_linear: linear
  data: raw
file_rules:
  - !<Rule> {name: Default, colorspace: default}
displays:
  Monitor:
    - !<View> {name: Raw, colorspace: raw}
    - !<View> {name: Gamma, colorspace: gamma2}
colorspaces:
  - !<ColorSpace>
    name: linear
  - !<ColorSpace>
    name: raw
    isdata: true
  - !<ColorSpace>
    name: gamma2
    from_scene_reference: !<ExponentTransform> {value: [2, 2, 2, 1], direction: inverse}
)";

TEST(Color, ShippedConfigLoadsWithSrgbAndGamma22Displays) {
  ScopedEnv noOcio("OCIO", nullptr);
  ColorConfigInfo info = colorConfigInfo();
  EXPECT_EQ(info.path, defaultOcioConfigPath());
  EXPECT_EQ(info.defaultDisplay, "sRGB");
  ASSERT_EQ(info.displays.size(), 2u);
  EXPECT_EQ(info.displays[0].display, "sRGB");
  EXPECT_EQ(info.displays[0].views,
            (std::vector<std::string>{"Standard", "Raw", "ACES 1.0 SDR-video"}));
  EXPECT_EQ(info.displays[0].defaultView, "Standard");
  EXPECT_EQ(info.displays[1].display, "Rec.1886 / Gamma 2.2");
  EXPECT_EQ(info.displays[1].views,
            (std::vector<std::string>{"Standard", "Raw", "ACES 1.0 SDR-video"}));
  EXPECT_EQ(info.displays[1].defaultView, "Standard");
  EXPECT_EQ(resolveDisplayView("", ""), (std::pair<std::string, std::string>{"sRGB", "Standard"}));
}

TEST(Color, StandardViewIsThePiecewiseSrgbCurve) {
  ScopedEnv noOcio("OCIO", nullptr);
  const std::vector<double> linear = {0.0, 1e-4, 0.002, 0.0031308, 0.01, 0.18, 0.5, 0.9, 1.0};
  std::vector<float> rgb;
  for (double v : linear) rgb.insert(rgb.end(), {float(v), float(v), float(v)});
  applyDisplayView(rgb, "", "");
  for (size_t i = 0; i < linear.size(); ++i)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(rgb[3 * i + size_t(c)], srgbEncode(linear[i]), 2e-5) << "linear " << linear[i];
}

// OCIO's own checker, as a user would run it. scripts/setup.sh installs it, so its absence is a
// broken setup, not a reason to skip.
TEST(Color, ShippedConfigPassesOciocheck) {
  ASSERT_EQ(std::system("command -v ociocheck >/dev/null 2>&1"), 0)
      << "ociocheck is not on PATH: run scripts/setup.sh (Debian package opencolorio-tools)";
  std::string dir = test::scratchDir("Color.ShippedConfigPassesOciocheck");
  std::string log = dir + "/ociocheck.log";
  // ociocheck reads $OCIO when it is set, and --iconfig otherwise: keep it out of the way.
  std::string command =
      "env -u OCIO ociocheck --iconfig '" + defaultOcioConfigPath() + "' >'" + log + "' 2>&1";
  int status = std::system(command.c_str());
  std::ifstream in(log);
  std::string output((std::istreambuf_iterator<char>(in)), {});
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << output;
  EXPECT_NE(output.find("** Validation **\npassed"), std::string::npos) << output;
  EXPECT_NE(output.find("(sRGB, ACES 1.0 SDR-video)"), std::string::npos) << output;
  EXPECT_EQ(output.find("ERROR"), std::string::npos) << output;

  // The check itself can fail: a config naming a built-in transform OCIO does not have.
  std::string config;
  {
    std::ifstream src(defaultOcioConfigPath());
    config.assign(std::istreambuf_iterator<char>(src), {});
  }
  size_t at = config.find("SDR-VIDEO_1.0");
  ASSERT_NE(at, std::string::npos);
  config.replace(at, 13, "SDR-VIDEO_9.9");
  std::ofstream(dir + "/broken.ocio") << config;
  status = std::system(
      ("env -u OCIO ociocheck --iconfig '" + dir + "/broken.ocio' >/dev/null 2>&1").c_str());
  EXPECT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
}

// Scene-linear 18 % grey, by hand: 1.055 · 0.18^(1/2.4) − 0.055 = 0.4613, and 0.4613 · 255 =
// 117.6, so 8-bit code 118, through the default display (sRGB) and view (Standard).
TEST(Color, MidGreyIsSrgbCode118ThroughTheDefaultView) {
  ScopedEnv noOcio("OCIO", nullptr);
  const double encoded = 1.055 * std::pow(0.18, 1.0 / 2.4) - 0.055;
  ASSERT_NEAR(encoded, 0.4613, 1e-4);
  std::vector<float> rgb = {0.18f, 0.18f, 0.18f};
  applyDisplayView(rgb, "", "");
  for (float v : rgb) EXPECT_NEAR(v, encoded, 2e-5);

  std::string dir = test::scratchDir("Color.MidGreyIsSrgbCode118ThroughTheDefaultView");
  Film film(2, 2, false);
  film.color.assign(4, Rgb{0.18f, 0.18f, 0.18f});
  film.alpha.assign(4, 1.0f);
  writeImage(dir + "/grey.png", film, RenderSettings{}, {});
  auto in = OIIO::ImageInput::open(dir + "/grey.png");
  ASSERT_TRUE(in) << OIIO::geterror();
  std::vector<unsigned char> px(4 * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, -1, OIIO::TypeDesc::UINT8, px.data()));
  for (unsigned char c : px) EXPECT_EQ(int(c), 118);
}

// The filmic view: a toe, then a shoulder that rolls highlights off where Standard clips.
TEST(Color, AcesViewRollsOffHighlightsMonotonically) {
  ScopedEnv noOcio("OCIO", nullptr);
  const std::vector<float> linear = {0.01f, 0.02f, 0.05f, 0.1f, 0.18f, 0.35f, 0.5f, 1.0f,
                                     2.0f,  4.0f,  6.0f,  8.0f, 11.0f, 14.0f, 16.0f};
  for (const char* display : {"sRGB", "Rec.1886 / Gamma 2.2"}) {
    std::vector<float> aces, standard;
    for (float v : linear) aces.insert(aces.end(), {v, v, v});
    standard = aces;
    applyDisplayView(aces, display, "ACES 1.0 SDR-video");
    applyDisplayView(standard, display, "Standard");
    for (size_t i = 0; i < linear.size(); ++i) {
      SCOPED_TRACE(std::string(display) + ", linear " + std::to_string(linear[i]));
      const float v = aces[3 * i];
      EXPECT_NEAR(aces[3 * i + 1], v, 1e-4);  // grey stays grey
      EXPECT_NEAR(aces[3 * i + 2], v, 1e-4);
      EXPECT_GT(v, 0.0f);
      EXPECT_LT(v, 1.0f);  // 16 (6.5 stops over mid-grey) still below display white
      if (i > 0) {
        EXPECT_GT(v, aces[3 * (i - 1)]);
      }
    }
    // Standard clips everything from 1.0 up; the filmic view keeps 1, 4 and 16 apart ...
    EXPECT_GE(standard[3 * 7], 0.999f);
    EXPECT_GT(aces[3 * 9] - aces[3 * 7], 0.1f);
    // ... with a shoulder: two stops from 4 to 16 gain less than the one from 0.5 to 1.
    EXPECT_LT(aces[3 * 14] - aces[3 * 9], aces[3 * 7] - aces[3 * 6]);
  }
}

TEST(Color, Gamma22DisplayAndRawView) {
  ScopedEnv noOcio("OCIO", nullptr);
  std::vector<float> rgb = {0.5f, 0.25f, 2.0f};
  applyDisplayView(rgb, "Rec.1886 / Gamma 2.2", "");
  EXPECT_NEAR(rgb[0], std::pow(0.5, 1 / 2.2), 1e-5);
  EXPECT_NEAR(rgb[1], std::pow(0.25, 1 / 2.2), 1e-5);
  rgb = {0.5f, 0.25f, 2.0f};
  applyDisplayView(rgb, "sRGB", "Raw");
  EXPECT_EQ(rgb, (std::vector<float>{0.5f, 0.25f, 2.0f}));
}

TEST(Color, UnknownViewListsTheAvailableOnes) {
  ScopedEnv noOcio("OCIO", nullptr);
  std::vector<float> rgb = {0.5f, 0.5f, 0.5f};
  try {
    applyDisplayView(rgb, "sRGB", "Filmic");
    FAIL() << "expected ColorError";
  } catch (const ColorError& e) {
    std::string what = e.what();
    EXPECT_NE(what.find("'Filmic'"), std::string::npos) << what;
    EXPECT_NE(what.find("'Standard', 'Raw'"), std::string::npos) << what;
  }
  try {
    resolveDisplayView("DCI-P3", "");
    FAIL() << "expected ColorError";
  } catch (const ColorError& e) {
    std::string what = e.what();
    EXPECT_NE(what.find("'sRGB', 'Rec.1886 / Gamma 2.2'"), std::string::npos) << what;
  }
}

TEST(Color, OcioEnvironmentVariableIsHonoured) {
  std::string dir = test::scratchDir("Color.OcioEnvironmentVariableIsHonoured");
  std::string path = dir + "/raw_default.ocio";
  std::ofstream(path) << kRawDefaultConfig;
  ScopedEnv ocio("OCIO", path.c_str());

  ColorConfigInfo info = colorConfigInfo();
  EXPECT_EQ(info.path, path);
  EXPECT_EQ(info.defaultDisplay, "Monitor");
  EXPECT_EQ(resolveDisplayView("", ""), (std::pair<std::string, std::string>{"Monitor", "Raw"}));
  std::vector<float> rgb = {0.25f, 0.5f, 0.75f};
  applyDisplayView(rgb, "", "");
  EXPECT_EQ(rgb, (std::vector<float>{0.25f, 0.5f, 0.75f}));
  applyDisplayView(rgb, "", "Gamma");
  EXPECT_NEAR(rgb[0], 0.5f, 1e-6);
  // The shipped config's display does not exist in this one.
  EXPECT_THROW(resolveDisplayView("sRGB", ""), ColorError);
}

TEST(Color, BrokenOcioFallsBackToTheShippedConfig) {
  std::string dir = test::scratchDir("Color.BrokenOcioFallsBackToTheShippedConfig");
  std::string path = dir + "/broken.ocio";
  std::ofstream(path) << "ocio_profile_version: 2\nroles: [this is not a config\n";
  ScopedEnv ocio("OCIO", path.c_str());
  EXPECT_EQ(colorConfigInfo().path, defaultOcioConfigPath());
}

}  // namespace
}  // namespace glint
