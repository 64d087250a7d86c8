// Reference images: small scenes under tests/images/scenes rendered by `glint render` and
// compared with `glint diff` against the EXRs stored in tests/images/references. The
// thresholds allow what legitimately differs between machines (Embree picks SSE/AVX2/AVX-512
// kernels at run time, whose last-bit differences move a few edge samples) and nothing more; a
// test below checks that a visibly different scene does fail them.
// Regenerate the references with tests/images/update_references.sh after an intended change.
//
// Two kinds of scene: glint scenes (tests/images/scenes/NAME.json) and Khronos glTF samples
// from the shared asset folder, each rendered with its sidecar
// (tests/images/scenes/NAME.glint.json: camera, lights, render settings). A missing asset
// fails its test (never skips).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <ostream>
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

// Renders `scenePath` (with `sidecar` when not empty) into `dir` and compares it with
// `reference`.
test::CommandResult renderAndDiff(const std::string& scenePath, const std::string& reference,
                                  const std::string& dir, const std::string& sidecar = "") {
  std::string out = dir + "/" + fs::path(reference).filename().string();
  std::string args = "render '" + scenePath + "' --quiet -o '" + out + "'";
  if (!sidecar.empty()) args += " --sidecar '" + sidecar + "'";
  test::CommandResult r = test::runGlint(args);
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
                         testing::Values("primitives", "transforms", "csg", "terrain", "procedural",
                                         "bump_wall", "glass", "fog", "fog_lamps",
                                         "projective_clouds", "cornell_ir", "cornell_path"),
                         [](const testing::TestParamInfo<const char*>& p) {
                           return std::string(p.param);
                         });

// Khronos glTF samples from the shared asset folder, each with the sidecar
// tests/images/scenes/NAME.glint.json; tests/images/update_references.sh holds the same list.
struct GltfReference {
  const char* name;   // sidecar, reference and test name
  const char* asset;  // path under test::assetsDir()
};

// Names the parameter in test listings (ctest -N) instead of its bytes.
void PrintTo(const GltfReference& p, std::ostream* os) { *os << p.name << " (" << p.asset << ")"; }

class GltfImageReference : public testing::TestWithParam<GltfReference> {};

TEST_P(GltfImageReference, MatchesTheStoredReference) {
  const GltfReference& p = GetParam();
  std::string asset = test::assetsDir() + "/" + p.asset;
  ASSERT_TRUE(fs::exists(asset)) << "shared asset " << asset
                                 << " not found; set GLINT_ASSETS to the shared asset folder "
                                    "(see benchmarks/get_assets.sh)";
  std::string name = p.name;
  std::string sidecar = imagesDir() + "/scenes/" + name + ".glint.json";
  std::string reference = imagesDir() + "/references/" + name + ".exr";
  ASSERT_TRUE(fs::exists(sidecar)) << sidecar;
  ASSERT_TRUE(fs::exists(reference)) << reference;
  std::string dir = test::scratchDir("reference_" + name);
  test::CommandResult r = renderAndDiff(asset, reference, dir, sidecar);
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
}

INSTANTIATE_TEST_SUITE_P(
    KhronosSamples, GltfImageReference,
    testing::Values(GltfReference{"box_textured", "gltf/BoxTextured/glTF/BoxTextured.gltf"},
                    GltfReference{"texture_coordinate_test",
                                  "gltf/TextureCoordinateTest/glTF/TextureCoordinateTest.gltf"},
                    GltfReference{"normal_tangent_test",
                                  "gltf/NormalTangentTest/glTF/NormalTangentTest.gltf"}),
    [](const testing::TestParamInfo<GltfReference>& p) { return std::string(p.param.name); });

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

// The effects `glint info` lists for a scene (its "effects:" line; other lines, such as
// "textures: 0 (0 images)", name the same words).
std::string effectsOf(const std::string& scene) {
  test::CommandResult r = test::runGlint("info '" + imagesDir() + "/scenes/" + scene + "'");
  EXPECT_EQ(r.exitCode, 0) << r.err;
  std::istringstream lines(r.out);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("effects:", 0) == 0) return line.substr(8) + ",";  // "effects: a, b" -> " a, b,"
  ADD_FAILURE() << "no effects line in:\n" << r.out;
  return "";
}

bool lists(const std::string& effects, const std::string& effect) {
  return effects.find(" " + effect + ",") != std::string::npos;
}

TEST(ImageReferenceInfo, ListsTheMaterialEffects) {
  std::string e = effectsOf("procedural.json");
  EXPECT_TRUE(lists(e, "procedural")) << e;
  EXPECT_FALSE(lists(e, "textures")) << e;  // noise patterns need no UVs or images
  e = effectsOf("bump_wall.json");
  EXPECT_TRUE(lists(e, "bump")) << e;
  EXPECT_TRUE(lists(e, "textures")) << e;
  e = effectsOf("glass.json");
  EXPECT_TRUE(lists(e, "refraction")) << e;
}

TEST(ImageReferenceInfo, APlainSceneListsNoMaterialEffects) {
  std::string e = effectsOf("primitives.json");
  EXPECT_TRUE(lists(e, "analytic")) << e;
  for (const char* effect : {"textures", "bump", "procedural", "refraction", "transparency"})
    EXPECT_FALSE(lists(e, effect)) << effect << " in" << e;
}

}  // namespace
}  // namespace glint
