// Reference images: one small scene per effect family (tests/reference_images/references.json),
// rendered by `glint render` at a few spp and compared by `glint diff --statistical` with a
// reference rendered at 64x the spp that stores each pixel's mean and the variance of that mean
// (tests/reference_images/references/NAME.exr). The comparison is a per-pixel z-test with a Šidák
// correction, a global bias test and a hard cap on any pixel's error (image/statistical.h):
// it tolerates noise and the last-bit differences between CPUs (Embree picks SSE/AVX2/AVX-512
// kernels at run time) and nothing more; tests below check that it does fail a visibly
// different scene and a 3 % darker one.
//
// Every case is also rendered on one thread and must equal the two-thread image exactly:
// samples are keyed by pixel, sample index and seed, never by who renders them.
//
// On failure the test leaves NAME.exr/.png (the render), NAME.reference.png and
// NAME.heatmap.png (each pixel's |z|: black, blue, yellow at the failure threshold, red,
// white) in its scratch folder and prints their paths.
//
// Regenerate the references with tests/reference_images/update_references.py after an intended
// change; the tests never write them. Khronos glTF samples come from the shared asset folder; a
// missing asset fails its test (never skips).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <ostream>
#include <regex>
#include <sstream>

#include "image/diff.h"
#include "test_support.h"

namespace glint {
namespace {

namespace fs = std::filesystem;

std::string imagesDir() { return test::sourceDir() + "/tests/reference_images"; }

// One entry of tests/reference_images/references.json.
struct ReferenceCase {
  std::string name, scene, asset, sidecar, camera;
  int width = 0, height = 0, spp = 0;
};

// Names the parameter in test listings (ctest -N) instead of its bytes.
void PrintTo(const ReferenceCase& c, std::ostream* os) { *os << c.name; }

struct Manifest {
  std::vector<ReferenceCase> cases;
  double significance = 0, minPassPercent = 0, maxError = 0;
};

const Manifest& manifest() {
  static const Manifest m = [] {
    std::ifstream in(imagesDir() + "/references.json");
    nlohmann::json j = nlohmann::json::parse(in);  // a broken manifest fails loudly
    Manifest parsed;
    const nlohmann::json& t = j.at("thresholds");
    parsed.significance = t.at("significance");
    parsed.minPassPercent = t.at("min_pass_percent");
    parsed.maxError = t.at("max_error");
    for (const nlohmann::json& c : j.at("cases")) {
      ReferenceCase rc;
      rc.name = c.at("name");
      rc.scene = c.value("scene", "");
      rc.asset = c.value("asset", "");
      rc.sidecar = c.value("sidecar", "");
      rc.camera = c.value("camera", "");
      rc.width = c.at("size").at(0);
      rc.height = c.at("size").at(1);
      rc.spp = c.at("spp");
      parsed.cases.push_back(rc);
    }
    return parsed;
  }();
  return m;
}

// `glint render` arguments for a case, without outputs and threads.
std::string renderArgs(const ReferenceCase& c) {
  std::string args;
  if (!c.asset.empty())
    args = "'" + test::assetsDir() + "/" + c.asset + "' --sidecar '" + imagesDir() + "/" +
           c.sidecar + "'";
  else
    args = "'" + (fs::path(imagesDir()) / c.scene).string() + "'";  // `scene` may be absolute
  if (!c.camera.empty()) args += " --camera '" + c.camera + "'";
  return args + " --width " + std::to_string(c.width) + " --height " + std::to_string(c.height) +
         " --spp " + std::to_string(c.spp) + " --quiet";
}

// `glint diff --statistical` of `image` against `reference` with the manifest's thresholds
// (text or JSON output); writes the heat map beside `image`.
test::CommandResult statisticalDiff(const std::string& image, const std::string& reference,
                                    bool json = false) {
  const Manifest& m = manifest();
  std::string heatMap = fs::path(image).replace_extension(".heatmap.png").string();
  return test::runGlint("diff '" + image + "' '" + reference + "' --statistical --significance " +
                        std::to_string(m.significance) + " --min-pass " +
                        std::to_string(m.minPassPercent) + " --max-error " +
                        std::to_string(m.maxError) + " --heatmap '" + heatMap + "'" +
                        (json ? " --json" : ""));
}

class ImageReference : public testing::TestWithParam<ReferenceCase> {};

TEST_P(ImageReference, MatchesTheReferenceStatistically) {
  const ReferenceCase& c = GetParam();
  if (!c.asset.empty()) {
    ASSERT_TRUE(fs::exists(test::assetsDir() + "/" + c.asset))
        << "shared asset " << test::assetsDir() << "/" << c.asset
        << " not found; set GLINT_ASSETS to the shared asset folder (see "
           "benchmarks/get_assets.sh)";
  }
  std::string reference = imagesDir() + "/references/" + c.name + ".exr";
  ASSERT_TRUE(fs::exists(reference))
      << reference << " (tests/reference_images/update_references.py)";
  std::string dir = test::scratchDir("reference_" + c.name);
  std::string image = dir + "/" + c.name + ".exr";
  test::CommandResult r = test::runGlint("render " + renderArgs(c) + " --threads 2 -o '" + image +
                                         "' -o '" + dir + "/" + c.name + ".png'");
  ASSERT_EQ(r.exitCode, 0) << r.err;

  test::CommandResult d = statisticalDiff(image, reference);
  if (d.exitCode != 0) {
    fs::copy_file(imagesDir() + "/references/" + c.name + ".png",
                  dir + "/" + c.name + ".reference.png", fs::copy_options::overwrite_existing);
    ADD_FAILURE() << d.out << d.err << "render, reference and heat map: " << dir << "/" << c.name
                  << "{.png,.reference.png,.heatmap.png}";
  }

  // Determinism: one thread gives the very same image.
  std::string oneThread = dir + "/" + c.name + ".threads1.exr";
  r = test::runGlint("render " + renderArgs(c) + " --threads 1 -o '" + oneThread + "'");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  d = test::runGlint("diff '" + oneThread + "' '" + image + "' --fail 0");
  EXPECT_EQ(d.exitCode, 0) << "1 and 2 threads rendered different images:\n" << d.out;
}

INSTANTIATE_TEST_SUITE_P(Scenes, ImageReference, testing::ValuesIn(manifest().cases),
                         [](const testing::TestParamInfo<ReferenceCase>& p) {
                           return p.param.name;
                         });

// Every reference holds what the comparison needs, at the manifest's size and spp.
TEST(ImageReferenceFiles, CarryVarianceAtTheStatedSpp) {
  std::ifstream in(imagesDir() + "/references.json");
  const int factor = nlohmann::json::parse(in).at("reference_spp_factor");
  for (const ReferenceCase& c : manifest().cases) {
    Image image = readImage(imagesDir() + "/references/" + c.name + ".exr");
    EXPECT_EQ(image.width, c.width) << c.name;
    EXPECT_EQ(image.height, c.height) << c.name;
    EXPECT_EQ(image.meta.spp, factor * c.spp) << c.name;
    for (const char* channel : {"R", "G", "B", "variance.R", "variance.G", "variance.B"})
      EXPECT_GE(image.channel(channel), 0) << c.name << " has no " << channel;
  }
}

// Renders case `name` with `edit` applied to its scene text, in `dir`, and compares it with the
// case's reference.
test::CommandResult editedCase(const std::string& name, const std::string& dir,
                               const std::function<std::string(const std::string&)>& edit,
                               bool json = false) {
  auto found = std::find_if(manifest().cases.begin(), manifest().cases.end(),
                            [&](const ReferenceCase& c) { return c.name == name; });
  EXPECT_NE(found, manifest().cases.end()) << name;
  if (found == manifest().cases.end()) return {};
  ReferenceCase c = *found;
  std::string text = test::slurp(imagesDir() + "/" + c.scene);
  std::string changed = edit(text);
  EXPECT_NE(changed, text);
  // The copy lives elsewhere: paths relative to the scene's folder become absolute.
  std::string sceneDir = fs::path(imagesDir() + "/" + c.scene).parent_path().string();
  changed = std::regex_replace(changed, std::regex("\"\\.\\./"), "\"" + sceneDir + "/../");
  c.scene = dir + "/" + name + ".json";
  { std::ofstream(dir + "/" + name + ".json") << changed; }
  std::string image = dir + "/" + name + ".exr";
  test::CommandResult r = test::runGlint("render " + renderArgs(c) + " -o '" + image + "'");
  EXPECT_EQ(r.exitCode, 0) << r.err;
  return statisticalDiff(image, imagesDir() + "/references/" + name + ".exr", json);
}

// The comparison must be able to fail: one sphere of the CSG scene slightly larger.
TEST(ImageReferenceThresholds, AVisibleChangeFails) {
  test::CommandResult r =
      editedCase("csg", test::scratchDir("reference_changed"), [](const std::string& text) {
        return std::regex_replace(text, std::regex("\"radius\": 0\\.75"), "\"radius\": 0.8");
      });
  EXPECT_EQ(r.exitCode, 1) << r.out << r.err;
}

// ... and a change no single pixel shows: the path-traced box's lamp 3 % dimmer is lost in
// each pixel's noise at the test's spp, but not in the global bias test.
TEST(ImageReferenceThresholds, AGlobalDarkeningFails) {
  test::CommandResult r = editedCase(
      "cornell_path", test::scratchDir("reference_darker"),
      [](const std::string& text) {
        return std::regex_replace(text, std::regex("\"intensity\": 10\\b"), "\"intensity\": 9.7");
      },
      /*json=*/true);
  ASSERT_EQ(r.exitCode, 1) << r.out << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j.at("biased").get<bool>()) << r.out;
  EXPECT_GE(j.at("pass_percent").get<double>(), manifest().minPassPercent) << r.out;
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
