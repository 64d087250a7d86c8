// Tests for building the render scene: instancing versus baking, image size, default camera,
// and which features a scene calls for.
#include "scenes/build.h"

#include <gtest/gtest.h>

#include "geometry/interaction.h"
#include "scenes/sidecar.h"

namespace glint {
namespace {

MeshDesc unitTriangle(int material = -1) {
  MeshDesc m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.normals.assign(3, {0, 0, 1});
  m.indices = {0, 1, 2};
  m.material = material;
  return m;
}

TEST(Build, MeshPlacedTwiceIsInstancedAndMeshPlacedOnceIsBaked) {
  SceneDescription d;
  d.meshes = {unitTriangle(), unitTriangle()};
  d.instances = {{0, Transform::translate({5, 0, 0}), "a", {}},
                 {0, Transform::translate({-5, 0, 0}), "b", {}},
                 {1, Transform::translate({0, 7, 0}), "c", {}}};
  RenderScene s = buildRenderScene(d);
  ASSERT_EQ(s.geometry().meshes.size(), 2u);  // the shared mesh is stored once
  ASSERT_EQ(s.geometry().instances.size(), 3u);
  EXPECT_FALSE(s.geometry().instances[0].worldFromObject.isIdentity());
  EXPECT_EQ(s.geometry().instances[0].mesh, s.geometry().instances[1].mesh);
  // The single placement is baked: identity transform, world-space positions.
  const Instance& baked = s.geometry().instances[2];
  EXPECT_TRUE(baked.worldFromObject.isIdentity());
  EXPECT_EQ(s.geometry().meshes[baked.mesh].positions[1], (Vec3f{1, 7, 0}));
  EXPECT_TRUE(s.features().has(Feature::Instancing));
  EXPECT_EQ(s.geometry().instancedTriangleCount(), 3u);
  EXPECT_EQ(s.geometry().uniqueTriangleCount(), 2u);
  // Both placements are hit where they are.
  Hit hit;
  EXPECT_TRUE(s.accel().closestHit(Ray{{5.2f, 0.2f, 1}, {0, 0, -1}}, &hit));
  EXPECT_TRUE(s.accel().closestHit(Ray{{-4.8f, 0.2f, 1}, {0, 0, -1}}, &hit));
  EXPECT_TRUE(s.accel().closestHit(Ray{{0.2f, 7.2f, 1}, {0, 0, -1}}, &hit));
}

TEST(Build, ImageSizeFollowsTheCameraAspect) {
  SceneDescription d;
  CameraDesc cam;
  cam.name = "wide";
  cam.aspectRatio = 2;
  d.cameras.push_back(cam);
  int w = 0, h = 0;
  resolveImageSize(d, &d.cameras[0], &w, &h);
  EXPECT_EQ(w, 640);
  EXPECT_EQ(h, 320);
  d.render.width = 100;
  resolveImageSize(d, &d.cameras[0], &w, &h);
  EXPECT_EQ(h, 50);
  d.render.width.reset();
  d.render.height = 30;
  resolveImageSize(d, &d.cameras[0], &w, &h);
  EXPECT_EQ(w, 60);
  d.render.width = 7;
  resolveImageSize(d, &d.cameras[0], &w, &h);
  EXPECT_EQ(w, 7);
  EXPECT_EQ(h, 30);
}

TEST(Build, DefaultCameraSeesEveryCornerOfTheBounds) {
  SceneDescription d;
  MeshDesc m = unitTriangle();
  m.positions = {{-3, 0, -1}, {4, 2, 1}, {0, 5, 0.5f}};
  d.meshes = {m};
  d.instances = {{0, Transform(), "m", {}}};
  d.render.width = 160;
  d.render.height = 90;
  RenderScene s = buildRenderScene(d);
  EXPECT_EQ(s.cameraName(), "default");
  Bounds3f b = s.geometry().bounds();
  Transform cameraFromWorld = s.camera().worldFromCamera().inverse();
  float tanY = std::tan(0.5f * 40.0f * kPi / 180.0f), tanX = tanY * 160.0f / 90.0f;
  float widest = 0;
  for (int i = 0; i < 8; ++i) {
    Vec3f c =
        cameraFromWorld.point({(i & 1) ? b.upper.x : b.lower.x, (i & 2) ? b.upper.y : b.lower.y,
                               (i & 4) ? b.upper.z : b.lower.z});
    ASSERT_LT(c.z, 0) << "corner behind the camera";
    float x = std::abs(c.x / -c.z) / tanX, y = std::abs(c.y / -c.z) / tanY;
    EXPECT_LE(x, 1.0f);
    EXPECT_LE(y, 1.0f);
    widest = std::max({widest, x, y});
  }
  EXPECT_GT(widest, 0.9f) << "the bounds should fill the frame, not float in it";
}

TEST(Build, FeaturesFollowWhatTheSceneUses) {
  SceneDescription d;
  MaterialDesc eye;
  eye.type = MaterialType::Eyelight;
  d.materials = {eye};
  d.meshes = {unitTriangle(0)};
  d.instances = {{0, Transform(), "m", {}}};
  LightDesc light;
  d.lights = {light};
  RenderScene s = buildRenderScene(d);
  // Only eyelight surfaces: the light casts no shadows anyone could see.
  EXPECT_FALSE(s.features().has(Feature::Shadows));
  EXPECT_FALSE(s.features().has(Feature::Textures));
  EXPECT_FALSE(s.features().has(Feature::DefaultLight));

  d.materials[0].type = MaterialType::Lambert;
  d.meshes[0].colors.assign(3, {1, 0, 0, 1});
  s = buildRenderScene(d);
  EXPECT_TRUE(s.features().has(Feature::Shadows));
  EXPECT_TRUE(s.features().has(Feature::VertexColors));

  d.materials[0].emissive = {1, 1, 1};
  EXPECT_TRUE(buildRenderScene(d).features().has(Feature::Emission));
}

TEST(Build, PhongThatReflectsMoreThanItReceivesIsRejected) {
  SceneDescription d;
  MaterialDesc phong;
  phong.name = "Hot";
  phong.type = MaterialType::Phong;
  phong.baseColor = {0.8f, 0.8f, 0.8f};
  phong.specular = {0.5f, 0.1f, 0.1f};
  phong.where = {"scene.glint.json", "/materials/0"};
  d.materials = {phong};
  d.meshes = {unitTriangle(0)};
  d.instances = {{0, Transform(), "m", {}}};
  try {
    buildRenderScene(d);
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.where().pointer, "/materials/0");
  }
}

// Shading takes a static shape's placement from the scene (made once, with the accelerator)
// instead of making it at every hit; a moving shape is placed at the ray's time and a mesh has
// none. The surface details must be those of a placement made for the hit itself.
TEST(Build, StaticShapesArePlacedOnceAndShadeAsPlacedPerHit) {
  SceneDescription d;
  d.file = "scene.json";
  applySceneJsonText(R"({
    "render": {"integrator": "whitted", "camera": "c"},
    "cameras": [{"name": "c", "position": [0, 1, 6], "look_at": [0, 0, 0], "yfov_degrees": 50,
                 "shutter": [0, 0.5]}],
    "materials": [{"name": "m", "type": "lambert", "diffuse": [0.6, 0.5, 0.4]}],
    "objects": [
      {"name": "cut", "type": "csg", "material": "m",
       "transform": [{"rotate": {"axis": [1, 1, 0], "degrees": 37}}, {"translate": [-1.5, 0, 0]}],
       "tree": {"op": "difference", "children": [
         {"type": "box", "min": [-0.8, -0.8, -0.8], "max": [0.8, 0.8, 0.8]},
         {"type": "cylinder", "radius": 0.5, "height": 2,
          "transform": [{"translate": [0, -1, 0]}, {"rotate": {"axis": [0, 0, 1], "degrees": 90}}]}]}},
      {"name": "ball", "type": "sphere", "radius": 0.7, "material": "m",
       "transform": [{"scale": [1, 0.5, 1.5]}, {"rotate": {"axis": [0, 1, 0], "degrees": 20}},
                     {"translate": [1.5, 0, 0]}]},
      {"name": "mover", "type": "sphere", "center": [0, 1.5, 0], "radius": 0.3, "material": "m",
       "animation": {"translation": {"keys": [[0, [0, 0, 0]], [1, [0, 0.4, 0]]]}}},
      {"type": "plane", "point": [0, -1, 0], "normal": [0, 1, 0], "material": "m"}]})",
                     d.file, SceneJsonKind::Scene, &d);
  d.meshes = {unitTriangle()};
  d.instances = {{0, Transform::translate({0, 0, -3}), "tri", {}}};
  const RenderScene s = buildRenderScene(d);
  int placed = 0, moving = 0;
  for (uint32_t i = 0; i < s.geometry().instances.size(); ++i) {
    const Instance& inst = s.geometry().instances[i];
    EXPECT_EQ(s.placedShape(i) != nullptr, inst.isShape() && !inst.moves()) << "instance " << i;
    placed += s.placedShape(i) != nullptr;
    moving += inst.isShape() && inst.moves();
  }
  EXPECT_EQ(placed, 3);  // the CSG tree, the ball and the plane
  EXPECT_EQ(moving, 1);

  // Rays through a grid over the picture: every shape hit shades the same either way.
  int shapeHits = 0;
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 32; ++x) {
      const Vec3f target{-3 + 6 * (x + 0.5f) / 32, 2 - 3.5f * (y + 0.5f) / 24, 0};
      const Ray ray{{0, 1, 6}, target - Vec3f{0, 1, 6}, 0, kInfinity, 0.3f};
      Hit hit;
      if (!s.accel().closestHit(ray, &hit)) continue;
      const PlacedShape* p = s.placedShape(hit.instance);
      if (!p) continue;
      ++shapeHits;
      const SurfaceInteraction a = computeSurfaceInteraction(s.geometry(), ray, hit, {}, p);
      const SurfaceInteraction b = computeSurfaceInteraction(s.geometry(), ray, hit);
      EXPECT_EQ(a.p, b.p);
      EXPECT_EQ(a.pError, b.pError);
      EXPECT_EQ(a.ng, b.ng);
      EXPECT_EQ(a.uv, b.uv);
      EXPECT_EQ(a.dpdu, b.dpdu);
      EXPECT_EQ(a.materialSlot, b.materialSlot);
    }
  EXPECT_GT(shapeHits, 300);

  // A scene of meshes alone has no placed shapes.
  SceneDescription meshes;
  meshes.meshes = {unitTriangle()};
  meshes.instances = {{0, Transform::translate({1, 0, 0}), "a", {}},
                      {0, Transform::translate({-1, 0, 0}), "b", {}}};
  const RenderScene m = buildRenderScene(meshes);
  EXPECT_EQ(m.placedShape(0), nullptr);
  EXPECT_EQ(m.placedShape(1), nullptr);
}

}  // namespace
}  // namespace glint
