// Tests for RenderScene (renderer/scene.h): its constructor refuses parts that disagree (a
// mesh without a material, an index past the materials, a table of the wrong length), and
// each change re-derives what it moves: new lights are preprocessed and sampled beside the
// emitting surfaces' lights; a new material makes those again (no light keeps reading a
// material that is gone); a new camera or material re-detects the features.
#include "renderer/scene.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "materials/basic_materials.h"
#include "renderer/area_lights.h"
#include "scenes/build.h"
#include "scenes/sidecar.h"
#include "tests/test_support.h"

namespace glint {
namespace {

// One triangle placed once, one grey Lambert material, one point light.
SceneParts triangleParts() {
  SceneParts p;
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.indices = {0, 1, 2};
  p.geometry.meshes.push_back(std::move(mesh));
  p.geometry.instances.push_back(Instance{0, Transform{}});
  p.objectFromWorld.push_back(Transform{});
  p.materials.push_back(
      std::make_unique<LambertMaterial>(ColorParam{{0.5f, 0.5f, 0.5f}}, ColorParam{{0, 0, 0}}));
  p.meshMaterial = {0};
  p.lights.push_back(std::make_unique<PointLight>(Vec3f{0, 0, 2}, Rgb{1, 1, 1}, 0.0f, true));
  p.camera = Camera::perspective(AnimatedTransform(Transform::translate({0, 0, 3})), 0.8f, 8, 8,
                                 0, kInfinity);
  return p;
}

void expectRefused(SceneParts parts, const std::string& what) {
  try {
    RenderScene scene(std::move(parts), SceneAssembly{});
    ADD_FAILURE() << "accepted parts with " << what;
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("RenderScene"), std::string::npos) << e.what();
  }
}

TEST(RenderScene, AcceptsPartsThatAgreeAndDerivesTheRest) {
  RenderScene scene(triangleParts(), SceneAssembly{});
  ASSERT_NE(scene.lightSampler(), nullptr);
  EXPECT_TRUE(scene.infiniteLights().empty());
  EXPECT_TRUE(scene.features().has(Feature::Shadows));
  EXPECT_FALSE(scene.features().has(Feature::Lens));
  // The accelerator was built over the triangle: a ray down the axis hits it.
  Hit hit;
  EXPECT_TRUE(scene.accel().closestHit(Ray{{0.2f, 0.2f, 1}, {0, 0, -1}, 0, kInfinity, 0}, &hit));
  EXPECT_EQ(scene.materialIndex(hit), 0u);
}

TEST(RenderScene, RefusesPartsThatDisagree) {
  {
    SceneParts p = triangleParts();
    p.meshMaterial.clear();
    expectRefused(std::move(p), "a mesh without a material");
  }
  {
    SceneParts p = triangleParts();
    p.meshMaterial = {1};
    expectRefused(std::move(p), "a material index past the materials");
  }
  {
    SceneParts p = triangleParts();
    p.objectFromWorld.clear();
    expectRefused(std::move(p), "no object frame for the instance");
  }
  {
    SceneParts p = triangleParts();
    p.objectFromWorld.push_back(Transform{});
    expectRefused(std::move(p), "two object frames for one instance");
  }
  {
    SceneParts p = triangleParts();
    p.materials[0].reset();
    expectRefused(std::move(p), "a null material");
  }
  {
    SceneParts p = triangleParts();
    p.lights.push_back(nullptr);
    expectRefused(std::move(p), "a null light");
  }
}

// An emitting sphere (a surface light) beside a point light.
RenderScene glowingBall() {
  SceneDescription d;
  d.file = "scene.json";
  applySceneJsonText(R"({
    "render": {"width": 8, "height": 8, "camera": "c"},
    "cameras": [{"name": "c", "position": [0, 0, 4], "look_at": [0, 0, 0]}],
    "lights": [{"type": "point", "position": [0, 3, 0], "intensity": 2}],
    "materials": [{"name": "glow", "type": "lambert", "emissive": [2, 2, 2]},
                  {"name": "grey", "type": "lambert", "diffuse": [0.5, 0.5, 0.5]}],
    "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "material": "glow"},
                {"type": "quad", "corner": [-2, -1, -2], "edge_u": [4, 0, 0],
                 "edge_v": [0, 0, 4], "material": "grey"}]})",
                     d.file, SceneJsonKind::Scene, &d);
  return buildRenderScene(d);
}

// The light a ray straight down the camera's axis finds on the ball, or null.
const Light* ballLight(const RenderScene& scene) {
  Hit hit;
  EXPECT_TRUE(scene.accel().closestHit(Ray{{0, 0, 4}, {0, 0, -1}, 0, kInfinity, 0}, &hit));
  return scene.areaLight(hit);
}

TEST(RenderScene, NewLightsAreSampledBesideTheEmittingSurfaces) {
  RenderScene scene = glowingBall();
  // The point light, then the ball's.
  ASSERT_EQ(scene.lights().size(), 2u);
  ASSERT_EQ(scene.instanceLight().size(), 2u);
  EXPECT_EQ(scene.instanceLight()[0], 1);
  EXPECT_EQ(scene.instanceLight()[1], -1);
  EXPECT_EQ(ballLight(scene), scene.lights()[1].get());
  EXPECT_TRUE(scene.features().has(Feature::AreaLights));
  EXPECT_FALSE(scene.features().has(Feature::Environment));

  std::vector<std::unique_ptr<Light>> lights;
  lights.push_back(std::make_unique<UniformEnvironmentLight>(Rgb{0.5f, 0.5f, 0.5f}));
  scene.setLights(std::move(lights));
  ASSERT_EQ(scene.lights().size(), 2u);  // the environment, then the ball
  ASSERT_EQ(scene.infiniteLights().size(), 1u);
  EXPECT_EQ(scene.infiniteLights()[0], scene.lights()[0].get());
  EXPECT_EQ(ballLight(scene), scene.lights()[1].get());
  ASSERT_NE(scene.lightSampler(), nullptr);
  EXPECT_TRUE(scene.features().has(Feature::Environment));
  EXPECT_TRUE(scene.features().has(Feature::AreaLights));
  // The environment learnt the scene's extent: its power is finite and not zero.
  const Rgb phi = scene.lights()[0]->phi();
  EXPECT_GT(phi.x, 0);
  EXPECT_TRUE(isFinite(phi));

  scene.addLight(std::make_unique<PointLight>(Vec3f{0, 3, 0}, Rgb{1, 1, 1}, 0.0f, true));
  ASSERT_EQ(scene.lights().size(), 3u);  // the environment, the point, the ball
  EXPECT_EQ(ballLight(scene), scene.lights()[2].get());
  EXPECT_EQ(scene.infiniteLights().size(), 1u);

  scene.setLights({});
  ASSERT_EQ(scene.lights().size(), 1u);
  EXPECT_EQ(ballLight(scene), scene.lights()[0].get());
  EXPECT_FALSE(scene.features().has(Feature::Environment));
}

TEST(RenderScene, ANewMaterialMakesTheSurfaceLightsAgain) {
  RenderScene scene = glowingBall();
  const uint32_t glow = scene.shapeMaterials(0)[0];
  // Brighter: the ball's light reads the new material, not the one it replaced.
  scene.replaceMaterial(glow, std::make_unique<LambertMaterial>(ColorParam{{0.5f, 0.5f, 0.5f}},
                                                                ColorParam{{8, 8, 8}}));
  const auto* light = dynamic_cast<const AreaLight*>(ballLight(scene));
  ASSERT_NE(light, nullptr);
  EXPECT_EQ(light->emission().material, scene.materials()[glow].get());
  // Dark: the ball is no light at all.
  scene.replaceMaterial(glow, std::make_unique<LambertMaterial>(ColorParam{{0.5f, 0.5f, 0.5f}},
                                                                ColorParam{{0, 0, 0}}));
  EXPECT_EQ(ballLight(scene), nullptr);
  EXPECT_TRUE(scene.instanceLight().empty());
  EXPECT_EQ(scene.lights().size(), 1u);
  EXPECT_FALSE(scene.features().has(Feature::Emission));
  EXPECT_FALSE(scene.features().has(Feature::AreaLights));
}

TEST(RenderScene, ANewCameraIsDetectedAgainAndMaterialsAreReplacedInRange) {
  RenderScene scene = glowingBall();
  EXPECT_FALSE(scene.features().has(Feature::Lens));
  Camera lens = scene.camera();
  lens.setLens({0.1f, 4});
  scene.setCamera(lens, "lens");
  EXPECT_TRUE(scene.features().has(Feature::Lens));
  EXPECT_EQ(scene.cameraName(), "lens");
  // An override lasts until the next change.
  scene.setFeature(Feature::Lens, false);
  EXPECT_FALSE(scene.features().has(Feature::Lens));
  scene.setCamera(lens, "lens");
  EXPECT_TRUE(scene.features().has(Feature::Lens));

  EXPECT_THROW(scene.replaceMaterial(uint32_t(scene.materials().size()),
                                     std::make_unique<LambertMaterial>(ColorParam{},
                                                                       ColorParam{})),
               std::logic_error);
}

}  // namespace
}  // namespace glint
