// The two showcase animations (scenes/snowy, scenes/venus_garden) stay loadable and render
// finite images: a few frames of each across the whole animation, tiny and at 1 spp, through
// the command line as a user runs them, and `glint info --frames` names the effects each
// scene is there to show. Venus Garden needs the Stanford dragon from GLINT_ASSETS.
#include <gtest/gtest.h>

#include <cmath>
#include <ostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "image/diff.h"
#include "test_support.h"

namespace glint {
namespace {

struct Showcase {
  const char* name;
  const char* scene;                 // relative to the source tree
  const char* frames;                // a handful spread over the animation, rendered
  const char* infoFrames;            // the whole animation, every second
  std::vector<std::string> effects;  // exactly what `info --frames` must list
};

std::vector<Showcase> showcases() {
  return {
      {"snowy",
       "scenes/snowy/snowy.json",
       "0-671:134",
       "0-671:24",
       {"shadows", "emission", "analytic", "csg", "terrain", "transparency", "refraction", "bump",
        "procedural", "depth of field", "motion blur", "volumes", "area lights", "indirect light",
        "virtual point lights"}},
      {"venus_garden",
       "scenes/venus_garden/venus_garden.json",
       "0-360:120",
       "0-360:24",
       {"shadows", "instancing", "analytic", "bump", "procedural", "depth of field", "volumes",
        "projective light"}},
  };
}

// ctest prints each case's parameter: its name, not the struct's bytes.
void PrintTo(const Showcase& s, std::ostream* os) { *os << s.name; }

class ShowcaseScenes : public ::testing::TestWithParam<Showcase> {};

std::string scenePath(const Showcase& s) { return test::sourceDir() + "/" + s.scene; }

TEST_P(ShowcaseScenes, FramesRenderFinite) {
  const Showcase& s = GetParam();
  const std::string dir = test::scratchDir(std::string("showcase_") + s.name);
  const std::string shared = test::assetsDir();
  test::ScopedEnv assets("GLINT_ASSETS", shared.c_str());
  const test::CommandResult r =
      test::runGlint("render '" + scenePath(s) + "' --frames " + s.frames + " -o '" + dir +
                     "/f_####.exr' --width 48 --height 36 --spp 1 --quiet");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::vector<std::string> files = test::listFolder(dir);
  ASSERT_GE(files.size(), 3u) << "frames written";
  for (const std::string& f : files) {
    const Image image = readImage(dir + "/" + f);
    double sum = 0;
    size_t bad = 0;
    for (float v : image.pixels) {
      if (!std::isfinite(v)) ++bad;
      sum += v;
    }
    EXPECT_EQ(bad, 0u) << f;
    EXPECT_GT(sum / double(image.pixels.size()), 1e-4) << f << " is black";
  }
}

TEST_P(ShowcaseScenes, InfoListsTheEffectsTheSceneShows) {
  const Showcase& s = GetParam();
  const std::string shared = test::assetsDir();
  test::ScopedEnv assets("GLINT_ASSETS", shared.c_str());
  const test::CommandResult r =
      test::runGlint("info '" + scenePath(s) + "' --frames " + s.infoFrames);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const size_t over = r.out.find("effects over frames");
  ASSERT_NE(over, std::string::npos) << r.out;
  // One line per effect after the heading: "  NAME   frames A-B (...)".
  std::set<std::string> listed;
  std::istringstream lines(r.out.substr(over));
  std::string line;
  std::getline(lines, line);
  while (std::getline(lines, line)) {
    const size_t end = line.find(" frames ");
    if (line.rfind("  ", 0) != 0 || end == std::string::npos) continue;
    std::string name = line.substr(2, end - 2);
    name.erase(name.find_last_not_of(' ') + 1);
    listed.insert(name);
  }
  EXPECT_EQ(listed, std::set<std::string>(s.effects.begin(), s.effects.end())) << r.out;
}

INSTANTIATE_TEST_SUITE_P(Scenes, ShowcaseScenes, ::testing::ValuesIn(showcases()),
                         [](const auto& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace glint
