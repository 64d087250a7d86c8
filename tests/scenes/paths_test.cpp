// Files a scene names: relative to the JSON file, absolute, or in the shared asset folder
// through "$GLINT_ASSETS/..." — and the error when an asset is missing.
#include "scenes/paths.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "scene_error_support.h"
#include "scenes/load.h"
#include "test_support.h"

namespace glint {
namespace {

TEST(ScenePaths, RelativeAbsoluteAndAssetPaths) {
  EXPECT_EQ(resolveScenePath("tex/wood.png", "/scenes/garden/garden.json"),
            std::filesystem::path("/scenes/garden/tex/wood.png"));
  EXPECT_EQ(resolveScenePath("/data/wood.png", "/scenes/garden/garden.json"),
            std::filesystem::path("/data/wood.png"));
  test::ScopedEnv assets("GLINT_ASSETS", "/farm/assets");
  EXPECT_EQ(sharedAssetsFolder(), "/farm/assets");
  EXPECT_EQ(resolveScenePath("$GLINT_ASSETS/stanford/dragon.glb", "/scenes/garden.json"),
            std::filesystem::path("/farm/assets/stanford/dragon.glb"));
  EXPECT_EQ(resolveScenePath("${GLINT_ASSETS}/stanford/dragon.glb", "garden.json"),
            std::filesystem::path("/farm/assets/stanford/dragon.glb"));
  // Only a whole leading component counts.
  EXPECT_EQ(resolveScenePath("$GLINT_ASSETSX/a.glb", "/s/g.json"),
            std::filesystem::path("/s/$GLINT_ASSETSX/a.glb"));
}

TEST(ScenePaths, AnEmptyVariableFallsBackToTheConfiguredFolder) {
  test::ScopedEnv assets("GLINT_ASSETS", "");
  EXPECT_FALSE(sharedAssetsFolder().empty());
}

// A scene that needs the shared assets says so, at the pointer of the path, when they are
// not where GLINT_ASSETS points.
TEST(ScenePaths, AMissingAssetNamesTheVariable) {
  const std::string dir = test::scratchDir("paths_missing_asset");
  const std::string scene = dir + "/statue.json";
  std::ofstream(scene) << R"({"gltf": ["plinth.gltf", "$GLINT_ASSETS/stanford/nowhere.glb"]})";
  std::ofstream(dir + "/plinth.gltf")
      << R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": []}], "scene": 0})";
  const std::string nowhere = dir + "/no-assets-here";
  test::ScopedEnv assets("GLINT_ASSETS", nowhere.c_str());
  const SceneError e = test::errorFrom([&] { loadScene(scene); });
  EXPECT_SCENE_ERROR(e, scene, "/gltf/1", "no-assets-here/stanford/nowhere.glb");
  EXPECT_NE(e.message().find("set GLINT_ASSETS"), std::string::npos) << e.what();
}

// And finds them when it does: the same reference loads the bunny from the shared folder.
TEST(ScenePaths, AnAssetPathLoadsTheMesh) {
  const std::string dir = test::scratchDir("paths_asset_loads");
  const std::string scene = dir + "/bunny.json";
  std::ofstream(scene) << R"({"gltf": ["$GLINT_ASSETS/stanford/bun_zipper.glb"]})";
  const std::string shared = test::assetsDir();
  test::ScopedEnv assets("GLINT_ASSETS", shared.c_str());
  const SceneDescription d = loadScene(scene);
  size_t triangles = 0;
  for (const MeshDesc& m : d.meshes) triangles += m.indices.size() / 3;
  EXPECT_EQ(triangles, 69451u);
}

}  // namespace
}  // namespace glint
