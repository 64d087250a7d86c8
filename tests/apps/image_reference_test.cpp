// Reference images: small scenes under tests/images/scenes rendered by `glint render` and
// compared with `glint diff` against the EXRs stored in tests/images/references. The
// thresholds allow what legitimately differs between machines (Embree picks SSE/AVX2/AVX-512
// kernels at run time, whose last-bit differences move a few edge samples) and nothing more; a
// test below checks that a visibly different scene does fail them.
// Regenerate the references with tests/images/update_references.sh after an intended change.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "test_support.h"

namespace glint {
namespace {

namespace fs = std::filesystem;

std::string imagesDir() { return std::string(GLINT_SOURCE_DIR) + "/tests/images"; }

// A pixel fails beyond 0.05 (in scene-linear units; these scenes are lit to about 0..1) and
// the comparison fails when more than 0.5% of the pixels do.
const char* kThresholds = "--fail 0.05 --failpercent 0.5";

test::CommandResult renderAndDiff(const std::string& scenePath, const std::string& reference,
                                  const std::string& dir) {
  std::string out = dir + "/" + fs::path(reference).filename().string();
  test::CommandResult r = test::runGlint("render '" + scenePath + "' --quiet -o '" + out + "'");
  if (r.exitCode != 0) return r;
  return test::runGlint("diff '" + out + "' '" + reference + "' " + kThresholds);
}

class ImageReference : public testing::TestWithParam<const char*> {};

TEST_P(ImageReference, MatchesTheStoredReference) {
  std::string name = GetParam();
  std::string dir = test::scratchDir(std::string("reference_") + name);
  std::string reference = imagesDir() + "/references/" + name + ".exr";
  ASSERT_TRUE(fs::exists(reference)) << reference;
  test::CommandResult r = renderAndDiff(imagesDir() + "/scenes/" + name + ".json", reference, dir);
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
}

INSTANTIATE_TEST_SUITE_P(Scenes, ImageReference,
                         testing::Values("primitives", "transforms", "csg", "terrain"),
                         [](const testing::TestParamInfo<const char*>& p) {
                           return std::string(p.param);
                         });

// The thresholds must be able to fail: the CSG scene with one sphere slightly larger.
TEST(ImageReferenceThresholds, AVisibleChangeFails) {
  std::string dir = test::scratchDir("reference_changed");
  std::ifstream in(imagesDir() + "/scenes/csg.json");
  std::stringstream text;
  text << in.rdbuf();
  std::string changed =
      std::regex_replace(text.str(), std::regex("\"radius\": 0\\.75"), "\"radius\": 0.8");
  ASSERT_NE(changed, text.str());
  changed = std::regex_replace(changed, std::regex("\\.\\./\\.\\./\\.\\./scenes"),
                               std::string(GLINT_SOURCE_DIR) + "/scenes");
  { std::ofstream(dir + "/csg.json") << changed; }
  test::CommandResult r =
      renderAndDiff(dir + "/csg.json", imagesDir() + "/references/csg.exr", dir);
  EXPECT_EQ(r.exitCode, 1) << r.out << r.err;
}

TEST(ImageReferenceInfo, ListsTheAnalyticEffects) {
  test::CommandResult r = test::runGlint("info '" + imagesDir() + "/scenes/csg.json'");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("analytic"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("csg"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("terrain"), std::string::npos) << r.out;
  r = test::runGlint("info '" + imagesDir() + "/scenes/terrain.json'");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("terrain"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("32768 triangles"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace glint
