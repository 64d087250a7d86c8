// Tests for renderer/color: the shipped OCIO config, $OCIO, display/view lookup and transforms.
#include "renderer/color.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <vector>

#include "test_support.h"

namespace glint {
namespace {

class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value)
      ::setenv(name, value, 1);
    else
      ::unsetenv(name);
  }
  ~ScopedEnv() {
    if (old_)
      ::setenv(name_.c_str(), old_->c_str(), 1);
    else
      ::unsetenv(name_.c_str());
  }

 private:
  std::string name_;
  std::optional<std::string> old_;
};

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
  EXPECT_EQ(info.displays[0].views, (std::vector<std::string>{"Standard", "Raw"}));
  EXPECT_EQ(info.displays[0].defaultView, "Standard");
  EXPECT_EQ(info.displays[1].display, "Rec.1886 / Gamma 2.2");
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
