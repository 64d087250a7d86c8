// `glint info`: the names a sidecar addresses and the animation's frames as --frames takes them.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "test_support.h"

namespace glint {
namespace {

std::string quote(const std::string& s) { return "'" + s + "'"; }

// A sidecar material's "nodes" names glTF nodes that place a mesh; info lists them, each with
// its mesh, and the meshes by name.
TEST(CliInfo, ListsTheNodesASidecarMaterialAddressesAndTheMeshNames) {
  const std::string scene = test::dataDir() + "/scenes/two_instances.gltf";
  test::CommandResult r = test::runGlint("info " + quote(scene));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("meshes:     1 (12 triangles stored, 24 placed in the world): Cube\n"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("nodes:      2 with a mesh (names for a sidecar material's \"nodes\"): "
                       "'CubeLeft' (mesh 'Cube'), 'CubeRight' (mesh 'Cube')\n"),
            std::string::npos)
      << r.out;

  // The names listed are the ones the sidecar accepts.
  const std::string dir = test::scratchDir("CliInfo.ListsTheNodes");
  std::ofstream(dir + "/red.json") << R"({"materials": [{"name": "red", "type": "lambert",
    "diffuse": [0.8, 0.1, 0.1], "nodes": ["CubeLeft"]}]})";
  r = test::runGlint("info " + quote(scene) + " --sidecar " + quote(dir + "/red.json"));
  EXPECT_EQ(r.exitCode, 0) << r.err;
  // A glint .json scene places no glTF nodes: no line.
  std::ofstream(dir + "/ball.json") << R"({"objects": [{"type": "sphere", "radius": 1}]})";
  r = test::runGlint("info " + quote(dir + "/ball.json"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(r.out.find("nodes:"), std::string::npos) << r.out;
}

// The frames covering the keys, as whole frames: from the last frame at or before the first key
// to the first at or after the last one.
TEST(CliInfo, AnimationFramesAreWholeFrames) {
  const std::string dir = test::scratchDir("CliInfo.AnimationFramesAreWholeFrames");
  auto infoOf = [&](const std::string& keys, const std::string& render) {
    const std::string scene = dir + "/anim.json";
    std::ofstream(scene) << R"({"render": {)" << render << R"(},
      "objects": [{"name": "ball", "type": "sphere", "radius": 1,
                   "animation": {"translation": {"keys": )"
                         << keys << "}}}]}";
    test::CommandResult r = test::runGlint("info " + quote(scene));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return r.out;
  };
  // 0.5 s to 1.3 s at 24 fps: frames 12 to 31.2.
  std::string out = infoOf("[[0.5, [0, 0, 0]], [1.3, [4, 0, 0]]]", "");
  EXPECT_NE(out.find("animation:  1 animated node, keys from 0.5 s to 1.3 s (frames 12-32 at 24 "
                     "fps)\n"),
            std::string::npos)
      << out;
  // 1/24 s is not exactly 1/24 s as a float: still frame 1, not 1-2 or 0-1.
  out = infoOf("[[0.0416666667, [0, 0, 0]], [2, [4, 0, 0]]]", "");
  EXPECT_NE(out.find("(frames 1-48 at 24 fps)\n"), std::string::npos) << out;
  out = infoOf("[[0, [0, 0, 0]], [1, [4, 0, 0]]]", R"("fps": 30)");
  EXPECT_NE(out.find("(frames 0-30 at 30 fps)\n"), std::string::npos) << out;
}

}  // namespace
}  // namespace glint
