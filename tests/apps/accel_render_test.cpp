// Every backend renders the same image: `glint render --accel NAME` against `--accel embree`
// on scenes with triangles (instanced and baked), analytic shapes, CSG and an infinite plane,
// compared with `glint diff` at the tolerance of the reference-image tests (backends may
// differ in the last bits of t, which moves a few edge samples).
#include <gtest/gtest.h>

#include <filesystem>
#include <ostream>
#include <string>

#include "geometry/accel/accelerator.h"
#include "test_support.h"

namespace glint {
namespace {

struct Case {
  const char* accel;
  const char* scene;  // relative to the source tree
};

// How ctest lists a case ("kdtree on tests/reference_images/scenes/csg.json"), not as raw bytes.
void PrintTo(const Case& c, std::ostream* os) { *os << c.accel << " on " << c.scene; }

class AccelRender : public testing::TestWithParam<Case> {};

TEST_P(AccelRender, MatchesEmbree) {
  const Case& c = GetParam();
  std::string scene = test::sourceDir() + "/" + c.scene;
  // One scratch folder per case: ctest runs cases in parallel, and a scratch folder starts empty.
  std::string name = std::string(c.accel) + "_" + std::filesystem::path(c.scene).stem().string();
  std::string dir = test::scratchDir("accel_render_" + name);
  std::string a = dir + "/" + c.accel + ".exr", b = dir + "/embree.exr";
  test::CommandResult r =
      test::runGlint("render '" + scene + "' --quiet --width 160 --height 120 --spp 4 --accel " +
                     c.accel + " -o '" + a + "'");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  r = test::runGlint("render '" + scene +
                     "' --quiet --width 160 --height 120 --spp 4 --accel embree -o '" + b + "'");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  r = test::runGlint("diff '" + a + "' '" + b + "' --fail 0.05 --failpercent 0.5");
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
}

std::vector<Case> cases() {
  std::vector<Case> out;
  for (const char* accel : {"kdtree", "kdtree-median"})
    for (const char* scene :
         {"scenes/demo/demo.gltf", "tests/reference_images/scenes/csg.json",
          "tests/reference_images/scenes/primitives.json", "tests/data/scenes/two_instances.gltf"})
      out.push_back({accel, scene});
  return out;
}

INSTANTIATE_TEST_SUITE_P(Backends, AccelRender, testing::ValuesIn(cases()),
                         [](const testing::TestParamInfo<Case>& p) {
                           std::string n =
                               std::string(p.param.accel) + "_" + std::to_string(p.index % 4);
                           for (char& ch : n)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return n;
                         });

TEST(AccelRender, EveryBackendIsOfferedOnTheCommandLine) {
  std::vector<std::string> names = acceleratorNames();
  for (const char* expected : {"embree", "kdtree", "kdtree-median"})
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
}

}  // namespace
}  // namespace glint
