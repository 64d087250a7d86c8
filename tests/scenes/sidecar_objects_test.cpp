// glint tests — the sidecar's "objects": primitives, transforms (with shear), CSG trees in
// JSON and in .csg files, terrain; and the errors for bad ones, each naming its JSON pointer.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "geometry/shapes/box.h"
#include "geometry/shapes/cone.h"
#include "geometry/shapes/cylinder.h"
#include "geometry/shapes/disk.h"
#include "geometry/shapes/plane.h"
#include "geometry/shapes/sphere.h"
#include "scene_error_support.h"
#include "scenes/build.h"
#include "scenes/sidecar.h"
#include "test_support.h"

namespace glint {
namespace {

using test::errorFrom;

constexpr const char* kFile = "objects.json";
const std::string kMaterials =
    R"("materials": [{"name": "red", "type": "lambert", "diffuse": [1, 0, 0]},
                     {"name": "blue", "type": "lambert", "diffuse": [0, 0, 1]}])";

SceneDescription applyObjects(const std::string& objects, const std::string& file = kFile) {
  SceneDescription scene;
  applySceneJsonText("{" + kMaterials + ", \"objects\": " + objects + "}", file,
                     SceneJsonKind::Scene, &scene);
  return scene;
}

SceneError applyError(const std::string& objects) {
  return errorFrom([&] { applyObjects(objects); });
}

TEST(SidecarObjects, ReadsEveryPrimitive) {
  SceneDescription s = applyObjects(R"([
    {"name": "a", "type": "sphere", "center": [1, 2, 3], "radius": 0.5, "material": "red"},
    {"type": "box", "min": [0, 0, 0], "max": [1, 2, 3]},
    {"type": "cylinder", "radius": 1, "height": 2, "capped": false},
    {"type": "cone", "radius": 1, "height": 2},
    {"type": "plane", "point": [0, -1, 0], "normal": [0, 2, 0], "uv_scale": 4},
    {"type": "disk", "radius": 3},
    {"type": "quad", "corner": [0, 0, 0], "edge_u": [1, 0, 0], "edge_v": [0, 1, 0]}
  ])");
  ASSERT_EQ(s.objects.size(), 7u);
  EXPECT_EQ(s.objects[0].name, "a");
  EXPECT_STREQ(s.objects[0].shape->typeName(), "sphere");
  EXPECT_EQ(test::shapeAs<Sphere>(s.objects[0].shape).center(), (Vec3f{1, 2, 3}));
  EXPECT_EQ(s.objects[0].material, 0);
  EXPECT_EQ(s.objects[0].where.pointer, "/objects/0");
  EXPECT_EQ(test::shapeAs<Box>(s.objects[1].shape).upper(), (Vec3f{1, 2, 3}));
  EXPECT_FALSE(test::shapeAs<Cylinder>(s.objects[2].shape).capped());
  EXPECT_TRUE(test::shapeAs<Cone>(s.objects[3].shape).capped());
  EXPECT_EQ(test::shapeAs<Plane>(s.objects[4].shape).normal(), (Vec3f{0, 1, 0}));  // normalised
  EXPECT_EQ(test::shapeAs<Plane>(s.objects[4].shape).uvScale(), 4.0f);
  EXPECT_EQ(test::shapeAs<Disk>(s.objects[5].shape).radius(), 3.0f);
  EXPECT_STREQ(s.objects[6].shape->typeName(), "quad");
  EXPECT_EQ(s.objects[6].material, -1);
}

TEST(SidecarObjects, ReadsTransformsWithShear) {
  SceneDescription s = applyObjects(R"([{"type": "box", "min": [0, 0, 0], "max": [1, 1, 1],
    "transform": [{"shear": {"xy": 0.5}}, {"translate": [0, 0, 2]}]}])");
  Vec3f p = s.objects[0].worldFromObject.point({0, 1, 0});
  EXPECT_FLOAT_EQ(p.x, 0.5f);  // x' = x + 0.5 y
  EXPECT_FLOAT_EQ(p.z, 2.0f);
}

TEST(SidecarObjects, ReadsANestedCsgTree) {
  SceneDescription s = applyObjects(R"([{"type": "csg", "material": "blue", "tree":
    {"op": "difference", "children": [
      {"type": "box", "min": [-1, -1, -1], "max": [1, 1, 1]},
      {"op": "union", "transform": [{"translate": [0, 1, 0]}], "children": [
        {"type": "sphere", "radius": 0.5, "material": "red"},
        {"type": "cylinder", "radius": 0.2, "height": 3}]}]}}])");
  const CsgTreeDesc& t = s.objects[0].csg;
  ASSERT_EQ(s.objects[0].kind, ObjectKind::Csg);
  ASSERT_EQ(t.nodes.size(), 5u);
  const CsgNodeDesc& root = t.nodes[size_t(t.root)];
  EXPECT_EQ(root.op, CsgOp::Difference);
  ASSERT_EQ(root.children.size(), 2u);
  EXPECT_STREQ(t.nodes[size_t(root.children[0])].shape->typeName(), "box");
  const CsgNodeDesc& u = t.nodes[size_t(root.children[1])];
  EXPECT_EQ(u.op, CsgOp::Union);
  EXPECT_EQ(u.parentFromNode.point({0, 0, 0}), (Vec3f{0, 1, 0}));
  EXPECT_EQ(t.nodes[size_t(u.children[0])].material, 0);
  EXPECT_EQ(s.objects[0].material, 1);
}

TEST(SidecarObjects, ReadsACsgFileBesideTheScene) {
  std::string dir = test::scratchDir("sidecar_csg_file");
  {
    std::ofstream f(dir + "/thing.csg");
    f << "# a box with a hole\n"
         "box min -1 -1 -1 max 1 1 1 material red\n"
         "sphere center 0 0 0 radius 1.2 material blue\n"
         "difference\n";
  }
  SceneDescription s =
      applyObjects(R"([{"type": "csg", "file": "thing.csg"}])", dir + "/scene.json");
  const CsgTreeDesc& t = s.objects[0].csg;
  ASSERT_EQ(t.nodes.size(), 3u);
  EXPECT_EQ(t.nodes[size_t(t.root)].op, CsgOp::Difference);
  EXPECT_EQ(t.nodes[0].material, 0);  // names resolved against the scene's materials
  EXPECT_EQ(t.nodes[1].material, 1);
}

TEST(SidecarObjects, CsgFileErrorsNameTheFileAndLine) {
  std::string dir = test::scratchDir("sidecar_csg_file_errors");
  {
    std::ofstream f(dir + "/bad.csg");
    f << "sphere center 0 0 0 radius 1\n"
         "union\n";
  }
  SceneError e =
      errorFrom([&] { applyObjects(R"([{"type": "csg", "file": "bad.csg"}])", dir + "/s.json"); });
  EXPECT_NE(std::string(e.what()).find("bad.csg:2"), std::string::npos) << e.what();
  {
    std::ofstream f(dir + "/material.csg");
    f << "sphere center 0 0 0 radius 1 material green\n";
  }
  e = errorFrom(
      [&] { applyObjects(R"([{"type": "csg", "file": "material.csg"}])", dir + "/s.json"); });
  EXPECT_NE(std::string(e.what()).find("material.csg:1"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("no material named 'green'"), std::string::npos);
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "csg", "file": "nowhere.csg"}])"), kFile,
                     "/objects/0/file", "file not found");
}

TEST(SidecarObjects, ReadsTerrain) {
  SceneDescription s =
      applyObjects(R"([{"type": "terrain", "size": 50, "depth": 3, "roughness": 0.4,
    "peak": [5, -5], "height": 10, "seed": 9, "material": "red"}])");
  ASSERT_EQ(s.objects[0].kind, ObjectKind::Terrain);
  EXPECT_EQ(s.objects[0].terrain.depth, 3);
  EXPECT_EQ(s.objects[0].terrain.peak, (Vec2f{5, -5}));
  EXPECT_EQ(s.objects[0].terrain.seed, 9u);
}

TEST(SidecarObjects, RejectsBadPrimitives) {
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "sphere", "radius": 0}])"), kFile, "/objects/0/radius",
                     "must be > 0");
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "sphere", "radius": -2}])"), kFile,
                     "/objects/0/radius", "must be > 0");
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "sphere", "radius": 1e39}])"), kFile,
                     "/objects/0/radius", "finite");
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "sphere"}])"), kFile, "/objects/0",
                     "missing required key 'radius'");
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "sphere", "radius": 1, "radius2": 3}])"), kFile,
                     "/objects/0/radius2", "unknown key");
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "spere", "radius": 1}])"), kFile, "/objects/0/type",
                     "did you mean 'sphere'");
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "box", "min": [0, 0, 0], "max": [1, 0, 1]}])"), kFile,
                     "/objects/0/max", "greater than 'min'");
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "cylinder", "radius": 1, "height": -1}])"), kFile,
                     "/objects/0/height", "must be > 0");
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "plane", "normal": [0, 0, 0]}])"), kFile,
                     "/objects/0/normal", "must not be zero");
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "quad", "corner": [0, 0, 0], "edge_u": [1, 0, 0],
                                     "edge_v": [2, 0, 0]}])"),
                     kFile, "/objects/0/edge_v", "parallel");
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "sphere", "radius": 1, "material": "rd"}])"), kFile,
                     "/objects/0/material", "did you mean 'red'");
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "terrain", "depth": 12}])"), kFile, "/objects/0/depth",
                     "must be >= 0 and <= 10");
}

TEST(SidecarObjects, RejectsSingularTransforms) {
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "sphere", "radius": 1,
                                     "transform": [{"scale": [1, 0, 1]}]}])"),
                     kFile, "/objects/0/transform/0/scale", "must not be zero");
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "sphere", "radius": 1,
                                     "transform": [{"shear": {"xy": 1, "yx": 1}}]}])"),
                     kFile, "/objects/0/transform/0/shear", "singular");
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "sphere", "radius": 1,
                                     "transform": [[1,0,0,0],[0,1,0,0],[0,0,0,0],[0,0,0,1]]}])"),
                     kFile, "/objects/0/transform", "singular");
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "box", "min": [0,0,0], "max": [1,1,1],
                                     "transform": [{"shear": {"xq": 1}}]}])"),
                     kFile, "/objects/0/transform/0/shear/xq", "unknown key");
}

TEST(SidecarObjects, RejectsBadCsgTrees) {
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "csg", "tree": {"op": "union", "children": [
                                     {"type": "sphere", "radius": 1}]}}])"),
                     kFile, "/objects/0/tree/children", "at least two children");
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "csg", "tree": {"op": "union", "children": [
                                     {"type": "sphere", "radius": 1},
                                     {"type": "disk", "radius": 1}]}}])"),
                     kFile, "/objects/0/tree/children/1/type", "must be solids");
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "csg", "tree": {"op": "union", "children": [
                                     {"type": "sphere", "radius": 1},
                                     {"type": "cylinder", "radius": 1, "height": 1,
                                      "capped": false}]}}])"),
                     kFile, "/objects/0/tree/children/1/type", "must be solids");
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "csg", "tree": {"op": "xor", "children": []}}])"),
                     kFile, "/objects/0/tree/op", "xor");
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "csg", "tree": {"op": "union", "type": "sphere"}}])"),
                     kFile, "/objects/0/tree", "either 'op'");
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "csg"}])"), kFile, "/objects/0", "either 'tree'");
  EXPECT_SCENE_ERROR(applyError(R"([{"type": "csg", "tree": {"type": "sphere", "radius": 1}}])"),
                     kFile, "/objects/0/tree", "operation at its root");
}

// A nested JSON CSG tree `levels` deep: each operation's first child is the next operation.
std::string nestedCsgTree(int levels) {
  const std::string leaf = R"({"type": "sphere", "radius": 1})";
  std::string tree = leaf;
  for (int i = 1; i < levels; ++i)
    tree = R"({"op": "union", "children": [)" + tree + ", " + leaf + "]}";
  return tree;
}

TEST(SidecarObjects, CsgTreesDeeperThanTheLimitAreErrors) {
  // Issue 8: reading a nested tree recursed once per level, so a 50 000-level tree overflowed
  // the stack; the limit also keeps building and intersecting the tree within the stack.
  SceneDescription scene =
      applyObjects(R"([{"type": "csg", "tree": )" + nestedCsgTree(kMaxCsgDepth) + "}]");
  ASSERT_EQ(scene.objects.size(), 1u);
  EXPECT_EQ(scene.objects[0].csg.nodes.size(), size_t(2 * kMaxCsgDepth - 1));
  std::string pointer = "/objects/0/tree";
  for (int level = 1; level <= kMaxCsgDepth; ++level) pointer += "/children/0";
  EXPECT_SCENE_ERROR(
      applyError(R"([{"type": "csg", "tree": )" + nestedCsgTree(kMaxCsgDepth + 1) + "}]"), kFile,
      pointer, "CSG tree nested more than 1000 levels deep");
}

TEST(SidecarObjects, BuildPlacesShapesAndSetsEffects) {
  SceneDescription s = applyObjects(R"([
    {"type": "plane", "material": "red"},
    {"type": "sphere", "radius": 1, "center": [0, 1, 0], "material": "blue"},
    {"type": "csg", "tree": {"op": "intersection", "children": [
      {"type": "sphere", "radius": 1}, {"type": "box", "min": [0, 0, 0], "max": [2, 2, 2],
                                        "material": "blue"}]}},
    {"type": "terrain", "depth": 2}
  ])");
  RenderScene scene = buildRenderScene(s);
  EXPECT_EQ(scene.geometry().shapeInstanceCount(), 3u);
  EXPECT_EQ(scene.geometry().instancedTriangleCount(), 32u);  // 2 * 4^2
  std::vector<std::string> effects = scene.features().names();
  for (const char* e : {"analytic", "csg", "terrain"})
    EXPECT_NE(std::find(effects.begin(), effects.end(), e), effects.end()) << e;
  // The CSG's two leaves: the object's default material and blue.
  ASSERT_EQ(scene.geometry().shapes.size(), 3u);
  ASSERT_EQ(scene.shapeMaterials(2).size(), 2u);
  EXPECT_NE(scene.shapeMaterials(2)[0], scene.shapeMaterials(2)[1]);
  EXPECT_EQ(scene.shapeMaterials(1)[0], scene.shapeMaterials(2)[1]);  // both blue
  // A ray down onto the sphere finds it above the plane.
  Hit hit;
  ASSERT_TRUE(scene.accel().closestHit(Ray{{0, 5, 0.01f}, {0, -1, 0}}, &hit));
  EXPECT_NEAR(hit.t, 3.0f, 1e-4f);
}

TEST(SidecarObjects, SceneWithoutObjectsHasNoAnalyticEffects) {
  SceneDescription s = applyObjects("[]");
  EXPECT_TRUE(s.objects.empty());
}

}  // namespace
}  // namespace glint
