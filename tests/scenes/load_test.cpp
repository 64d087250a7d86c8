// glint tests — loadScene: picking the loader, finding the sidecar, glint .json scenes with
// glTF files (tests/data/sidecar).
#include "scenes/load.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "scene_error_support.h"
#include "test_support.h"

namespace glint {
namespace {

using test::errorFrom;

namespace fs = std::filesystem;

std::string data(const std::string& name) { return test::dataDir() + "/sidecar/" + name; }

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

// A scratch folder holding a copy of triangle.gltf (named `gltfName`).
std::string scratchWithTriangle(const std::string& test, const std::string& gltfName) {
  std::string dir = test::scratchDir("load_" + test);
  fs::copy_file(data("triangle.gltf"), dir + "/" + gltfName);
  return dir;
}

const CameraDesc* findCamera(const SceneDescription& s, const std::string& name) {
  for (const CameraDesc& c : s.cameras)
    if (c.name == name) return &c;
  return nullptr;
}

const MaterialDesc* findMaterial(const SceneDescription& s, const std::string& name) {
  for (const MaterialDesc& m : s.materials)
    if (m.name == name) return &m;
  return nullptr;
}

// ---------------------------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------------------------

TEST(Load, MissingSceneFileIsNamed) {
  std::string path = data("does_not_exist.gltf");
  EXPECT_SCENE_ERROR(errorFrom([&] { loadScene(path); }), path, "", "not found");
}

TEST(Load, UnknownExtensionIsRejected) {
  std::string dir = test::scratchDir("load_unknown_extension");
  writeFile(dir + "/model.stl", "solid empty\nendsolid empty\n");
  EXPECT_SCENE_ERROR(errorFrom([&] { loadScene(dir + "/model.stl"); }), dir + "/model.stl", "",
                     "unknown scene format '.stl'");
}

TEST(Load, MissingExplicitSidecarIsAnError) {
  std::string sidecar = data("missing.glint.json");
  EXPECT_SCENE_ERROR(errorFrom([&] { loadScene(data("triangle.gltf"), sidecar); }), sidecar, "",
                     "sidecar file not found");
}

TEST(Load, SidecarOptionWithAJsonSceneIsRejected) {
  std::string sidecar = data("override.glint.json");
  EXPECT_SCENE_ERROR(errorFrom([&] { loadScene(data("no_gltf.json"), sidecar); }), sidecar, "",
                     "a sidecar applies to a .gltf/.glb scene");
}

TEST(Load, SidecarErrorsNameTheSidecarFile) {
  std::string sidecar = data("bad_intensity.glint.json");
  EXPECT_SCENE_ERROR(errorFrom([&] { loadScene(data("triangle.gltf"), sidecar); }), sidecar,
                     "/lights/1/intensity", "must be >= 0");
}

TEST(Load, SidecarSyntaxErrorReportsLineAndColumn) {
  std::string dir = scratchWithTriangle("syntax", "demo.gltf");
  writeFile(dir + "/demo.glint.json", "{\n  \"render\": {\"spp\": 4,,}\n}\n");
  SceneError e = errorFrom([&] { loadScene(dir + "/demo.gltf"); });
  EXPECT_EQ(e.where().file, dir + "/demo.glint.json:2:23") << e.what();
  EXPECT_NE(e.message().find("syntax error"), std::string::npos) << e.what();
}

TEST(Load, UnknownRenderCameraListsTheGltfCameras) {
  std::string dir = scratchWithTriangle("unknown_camera", "demo.gltf");
  writeFile(dir + "/demo.glint.json", R"({"render": {"camera": "Front"}})");
  EXPECT_SCENE_ERROR(errorFrom([&] { loadScene(dir + "/demo.gltf"); }), dir + "/demo.glint.json",
                     "/render/camera", "no camera named 'Front'; available: 'Main', 'Side'");
}

TEST(Load, JsonSceneWithAMissingGltfReportsThePointer) {
  std::string scene = data("missing_gltf.json");
  EXPECT_SCENE_ERROR(errorFrom([&] { loadScene(scene); }), scene, "/gltf/1/file", "file not found");
}

// ---------------------------------------------------------------------------------------------
// glTF with a sidecar
// ---------------------------------------------------------------------------------------------

TEST(Load, GltfWithoutASidecarKeepsTheDefaults) {
  SceneDescription s = loadScene(data("triangle.gltf"));
  EXPECT_EQ(s.file, data("triangle.gltf"));
  EXPECT_EQ(s.render.spp, RenderSettings().spp);
  EXPECT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.cameras.size(), 2u);
}

TEST(Load, SidecarIsDetectedNextToTheGltf) {
  std::string dir = scratchWithTriangle("auto_sidecar", "demo.gltf");
  writeFile(dir + "/demo.glint.json", R"({"render": {"spp": 3, "width": 100, "camera": "Side"}})");
  SceneDescription s = loadScene(dir + "/demo.gltf");
  EXPECT_EQ(s.file, dir + "/demo.gltf");
  EXPECT_EQ(s.render.spp, 3);
  EXPECT_EQ(s.render.width, 100);
  EXPECT_EQ(s.render.camera, "Side");
}

TEST(Load, ExplicitSidecarIsUsedInsteadOfTheAutomaticOne) {
  std::string dir = scratchWithTriangle("explicit_sidecar", "demo.gltf");
  writeFile(dir + "/demo.glint.json", R"({"render": {"spp": 3}})");
  writeFile(dir + "/other.json", R"({"render": {"spp": 5}})");
  SceneDescription s = loadScene(dir + "/demo.gltf", dir + "/other.json");
  EXPECT_EQ(s.render.spp, 5);
}

TEST(Load, SidecarReplacesGltfCameraByName) {
  SceneDescription s = loadScene(data("triangle.gltf"), data("override.glint.json"));
  ASSERT_EQ(s.cameras.size(), 3u);  // Main replaced, Side kept, Top added
  const CameraDesc* main = findCamera(s, "Main");
  ASSERT_NE(main, nullptr);
  EXPECT_EQ(main->type, CameraType::Orthographic);
  EXPECT_FLOAT_EQ(main->xmag, 2);
  EXPECT_EQ(main->where.file, data("override.glint.json"));
  EXPECT_EQ(main->where.pointer, "/cameras/0");
  EXPECT_NEAR(main->worldFromCamera.point({0, 0, 0}).z, 10, 1e-5f);
  const CameraDesc* side = findCamera(s, "Side");
  ASSERT_NE(side, nullptr);
  EXPECT_NEAR(side->yfov, 0.7f, 1e-6f);
  EXPECT_NE(findCamera(s, "Top"), nullptr);
  EXPECT_EQ(s.render.camera, "Main");
  EXPECT_EQ(s.render.width, 320);
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].name, "Key");
}

TEST(Load, SidecarMaterialOverrideKeepsTheGltfTexture) {
  SceneDescription s = loadScene(data("triangle.gltf"), data("override.glint.json"));
  const MaterialDesc* red = findMaterial(s, "Red");
  ASSERT_NE(red, nullptr);
  EXPECT_EQ(red->type, MaterialType::Phong);
  EXPECT_GE(red->baseColorTexture, 0);
  EXPECT_NEAR(red->baseColor.y, 0.5f, 1e-6f);  // glTF baseColorFactor kept
  EXPECT_FLOAT_EQ(red->shininess, 40);
  EXPECT_EQ(red->specular, (Rgb{0.3f, 0.3f, 0.3f}));
  const MaterialDesc* floor = findMaterial(s, "Floor");
  ASSERT_NE(floor, nullptr);
  EXPECT_EQ(floor->type, MaterialType::Lambert);
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.materials[size_t(s.meshes[0].material)].name, "Red");
}

// ---------------------------------------------------------------------------------------------
// glint .json scenes
// ---------------------------------------------------------------------------------------------

TEST(Load, JsonSceneLoadsItsGltfFilesWithTransforms) {
  SceneDescription s = loadScene(data("scene.json"));
  EXPECT_EQ(s.file, data("scene.json"));
  ASSERT_EQ(s.instances.size(), 2u);
  Bounds3f first = s.instances[0].worldFromObject.bounds({{0, 0, 0}, {1, 1, 0}});
  Bounds3f second = s.instances[1].worldFromObject.bounds({{0, 0, 0}, {1, 1, 0}});
  EXPECT_NEAR(first.lower.y, 0, 1e-6f);
  EXPECT_NEAR(second.lower.y, 1, 1e-6f);  // translated by [0, 1, 0]
  EXPECT_NEAR(second.upper.y, 2, 1e-6f);
  EXPECT_EQ(s.render.camera, "Side");
  EXPECT_EQ(s.render.spp, 8);
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].type, LightType::Directional);
}

TEST(Load, JsonSceneMayHoldNoGltf) {
  SceneDescription s = loadScene(data("no_gltf.json"));
  EXPECT_TRUE(s.meshes.empty());
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_EQ(s.render.camera, "Only");
  EXPECT_EQ(s.render.width, 64);
}

TEST(Load, JsonSceneResolvesGltfPathsAgainstItsFolder) {
  std::string dir = scratchWithTriangle("relative", "model.gltf");
  fs::create_directories(dir + "/scenes");
  writeFile(dir + "/scenes/a.json", R"({"gltf": ["../model.gltf"]})");
  SceneDescription s = loadScene(dir + "/scenes/a.json");
  EXPECT_EQ(s.meshes.size(), 1u);
}

}  // namespace
}  // namespace glint
