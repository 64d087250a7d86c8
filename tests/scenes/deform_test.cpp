// glint tests — skinning and morph targets (scenes/deform.h) on tests/data/gltf/skin_morph.gltf,
// whose poses have closed forms (see make_gltf_inputs.py), and on the Khronos samples.
#include "scenes/deform.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>

#include "scenes/build.h"
#include "scenes/load.h"
#include "test_support.h"

namespace glint {
namespace {

SceneDescription skinMorph() { return loadScene(test::dataDir() + "/gltf/skin_morph.gltf"); }

void expectPositions(const MeshDesc& m, std::initializer_list<Vec3f> expected,
                     float tolerance = 1e-6f) {
  ASSERT_EQ(m.positions.size(), expected.size());
  size_t i = 0;
  for (Vec3f e : expected) {
    EXPECT_NEAR(m.positions[i].x, e.x, tolerance) << "vertex " << i;
    EXPECT_NEAR(m.positions[i].y, e.y, tolerance) << "vertex " << i;
    EXPECT_NEAR(m.positions[i].z, e.z, tolerance) << "vertex " << i;
    ++i;
  }
}

TEST(Deform, TheLoaderKeepsTargetsWeightsAndTheSkin) {
  SceneDescription s = skinMorph();
  ASSERT_EQ(s.instances.size(), 4u);
  const MeshDesc& morphed = s.meshes[size_t(s.instances[0].mesh)];
  ASSERT_EQ(morphed.targets.size(), 2u);
  EXPECT_EQ(morphed.weights, (std::vector<float>{0.5f, 0.25f}));
  EXPECT_EQ(s.instances[1].morphWeights, (std::vector<float>{1, 0}));
  ASSERT_EQ(s.instances[2].weightTracks.size(), 2u);
  ASSERT_EQ(s.skins.size(), 1u);
  EXPECT_EQ(s.instances[3].skin, 0);
  // The skinned node's own translation (100, 0, 0) is ignored, as glTF says.
  EXPECT_TRUE(s.instances[3].worldFromObject.isIdentity());
  EXPECT_EQ(s.skins[0].joints.size(), 2u);
  EXPECT_LT(s.skins[0].joints[0].node, 0);  // static joint
  EXPECT_GE(s.skins[0].joints[1].node, 0);  // animated joint
  EXPECT_TRUE(deformationAnimated(s, s.instances[2]));
  EXPECT_TRUE(deformationAnimated(s, s.instances[3]));
  EXPECT_FALSE(deformationAnimated(s, s.instances[0]));
  // The weights animation counts as animation (0 to 1 s).
  EXPECT_EQ(animationRange(s), (std::pair<double, double>{0.0, 1.0}));
}

TEST(Deform, MorphTargetsBlendByTheMeshNodeAndAnimatedWeights) {
  SceneDescription s = skinMorph();
  // Mesh weights [0.5, 0.25]: T0 lifts by 0.5, T1 moves vertex 1 by 0.25 along x.
  expectPositions(posedMesh(s, s.instances[0], 0), {{0, 0, 0.5f}, {1.25f, 0, 0.5f}, {0, 1, 0.5f}});
  // Node weights [1, 0] replace them.
  expectPositions(posedMesh(s, s.instances[1], 0), {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}});
  // Animated [0, 0] -> [1, 2] over a second; held outside it.
  expectPositions(posedMesh(s, s.instances[2], 0.5), {{0, 0, 0.5f}, {2, 0, 0.5f}, {0, 1, 0.5f}});
  expectPositions(posedMesh(s, s.instances[2], -1), {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  expectPositions(posedMesh(s, s.instances[2], 7), {{0, 0, 1}, {3, 0, 1}, {0, 1, 1}});
  // Normals stay unit length (the targets have no normal displacements here).
  for (Vec3f n : posedMesh(s, s.instances[2], 0.5).normals) EXPECT_NEAR(length(n), 1, 1e-6f);
}

TEST(Deform, LinearBlendSkinningFollowsTheJoints) {
  SceneDescription s = skinMorph();
  const InstanceDesc& skinned = s.instances[3];
  // At rest the joints sit where their inverse bind matrices undo them: the bind pose.
  expectPositions(posedMesh(s, skinned, 0), {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}});
  // Joint 1 turned 90 degrees about z around (0, 1, 0): vertex 1 follows it, vertex 2 halfway.
  const MeshDesc turned = posedMesh(s, skinned, 1);
  expectPositions(turned, {{0, 0, 0}, {1, 2, 0}, {-0.5f, 1.5f, 0}}, 1e-5f);
  // Normals (all +x at rest) turn with the inverse transpose of each vertex's blend: +x stays
  // for vertex 0; vertex 1 turns to +y; vertex 2's blend 0.5 (I + R) takes it to 45 degrees.
  const float h = std::sqrt(0.5f);
  const Vec3f normals[] = {{1, 0, 0}, {0, 1, 0}, {h, h, 0}};
  ASSERT_EQ(turned.normals.size(), 3u);
  for (int i = 0; i < 3; ++i)
    EXPECT_LT(length(turned.normals[size_t(i)] - normals[i]), 1e-5f) << "normal " << i;
  // At 45 degrees (slerp halfway).
  const float c = std::sqrt(0.5f);
  expectPositions(posedMesh(s, skinned, 0.5),
                  {{0, 0, 0}, {std::sqrt(2.0f), 1, 0}, {-c / 2, (3 + c) / 2, 0}}, 1e-5f);
}

TEST(Deform, TheBuilderPosesAtTheFrameTimeAndFramesTheWholeAnimation) {
  SceneDescription s = skinMorph();
  s.render.time = 1;
  RenderScene scene = buildRenderScene(s);
  // The skinned triangle, baked into the world: its vertex 1 is at (1, 2, 0) at t = 1.
  bool found = false;
  for (const TriangleMesh& m : scene.geometry().meshes)
    for (Vec3f p : m.positions) found = found || length(p - Vec3f{1, 2, 0}) < 1e-5f;
  EXPECT_TRUE(found);
  // Not at the ignored node translation.
  EXPECT_LT(scene.geometry().bounds().upper.x, 50);
}

// Deformation blur: with a shutter open over the animation, a pose that changes inside it gets
// time steps; one that does not, or no shutter, gets none.
SceneDescription skinMorphWithShutter(float open, float close) {
  SceneDescription s = skinMorph();
  CameraDesc cam;
  cam.name = "shutter";
  cam.worldFromCamera = Transform::lookAt({0, 0, 20}, {0, 0, 0}, {0, 1, 0});
  cam.shutterOpen = open;
  cam.shutterClose = close;
  s.cameras.push_back(cam);
  return s;
}

TEST(Deform, APoseThatChangesInsideTheShutterGetsTimeSteps) {
  SceneDescription s = skinMorphWithShutter(0, 1);
  RenderScene scene = buildRenderScene(s);
  ASSERT_EQ(scene.geometry().instances.size(), 4u);
  auto meshOf = [&](size_t i) -> const TriangleMesh& {
    return scene.geometry().meshes[scene.geometry().instances[i].mesh];
  };
  // Static weights: no steps.
  EXPECT_FALSE(meshOf(0).deforms());
  EXPECT_FALSE(meshOf(1).deforms());
  EXPECT_TRUE(scene.features().has(Feature::MotionBlur));
  // Weights keyed linearly over the shutter: a linear deformation, three steps are exact.
  const TriangleMesh& morph = meshOf(2);
  ASSERT_EQ(morph.positionSteps.size(), 3u);
  ASSERT_EQ(morph.normalSteps.size(), 3u);
  // Baked into the world at the node's translation (10, 0, 0); vertex 1 goes from x = 1 to 3.
  EXPECT_NEAR(morph.positionSteps[0][1].x, 11, 1e-5f);
  EXPECT_NEAR(morph.positionSteps[2][1].x, 13, 1e-5f);
  EXPECT_EQ(morph.positions, morph.positionSteps[1]);
  // The joint turning through 90 degrees: an arc, refined until the blend of the steps stays
  // within a thousandth of the mesh's size of the pose at every time.
  const TriangleMesh& skinned = meshOf(3);
  ASSERT_GT(skinned.positionSteps.size(), 3u);
  EXPECT_EQ(skinned.positionSteps.size() % 2, 1u);
  EXPECT_EQ(skinned.positions, skinned.positionSteps[skinned.positionSteps.size() / 2]);
  const float size = length(skinned.bounds().upper - skinned.bounds().lower);
  for (int i = 0; i <= 200; ++i) {
    const float t = float(i) / 200;
    const std::vector<Vec3f> exact = posedPositions(s, s.instances[3], t);
    const TriangleMesh::StepBlend b = skinned.stepAt(t);
    for (uint32_t v = 0; v < exact.size(); ++v)
      EXPECT_LT(length(skinned.positionAt(v, b) - exact[v]), 1.5e-3f * size) << "t " << t;
  }
  // No shutter: posed at the frame's time, no steps.
  RenderScene still = buildRenderScene(skinMorphWithShutter(0, 0));
  for (const TriangleMesh& m : still.geometry().meshes) EXPECT_FALSE(m.deforms());
  EXPECT_FALSE(still.features().has(Feature::MotionBlur));
}

// render.shutter (--shutter) gives the automatic camera a shutter, and replaces a camera's.
TEST(Deform, TheRenderShutterBlursWithTheAutomaticCameraToo) {
  SceneDescription s = skinMorph();
  ASSERT_TRUE(s.cameras.empty());
  EXPECT_FALSE(buildRenderScene(s).geometry().hasMotion());
  s.render.shutter = std::array<double, 2>{0, 1};
  RenderScene blurred = buildRenderScene(s);
  EXPECT_TRUE(blurred.features().has(Feature::MotionBlur));
  size_t deforming = 0;
  for (const TriangleMesh& m : blurred.geometry().meshes) deforming += m.deforms();
  EXPECT_EQ(deforming, 2u);
  // A closed render shutter overrides the camera's open one.
  SceneDescription closed = skinMorphWithShutter(0, 1);
  closed.render.shutter = std::array<double, 2>{0, 0};
  EXPECT_FALSE(buildRenderScene(closed).geometry().hasMotion());
}

// The Khronos samples: skinned (CesiumMan, RiggedSimple, RiggedFigure) and morphed
// (SimpleMorph, AnimatedMorphCube) models pose to finite, changing, bounded meshes.
TEST(Deform, KhronosSkinnedAndMorphedSamplesPoseOverTheirAnimation) {
  for (const char* model :
       {"CesiumMan", "RiggedSimple", "RiggedFigure", "SimpleMorph", "AnimatedMorphCube"}) {
    SCOPED_TRACE(model);
    const std::string dir = test::assetsDir() + "/gltf/" + model + "/glTF";
    ASSERT_TRUE(std::filesystem::is_directory(dir)) << dir;
    std::string file;
    for (const auto& e : std::filesystem::directory_iterator(dir))
      if (e.path().extension() == ".gltf") file = e.path().string();
    SceneDescription s = loadScene(file);
    const auto [t0, t1] = animationRange(s);
    ASSERT_GT(t1, t0);
    bool anyDeforms = false, changes = false;
    for (const InstanceDesc& inst : s.instances) {
      if (!deforms(s, inst)) continue;
      anyDeforms = true;
      const MeshDesc a = posedMesh(s, inst, t0), b = posedMesh(s, inst, 0.5 * (t0 + t1));
      for (size_t i = 0; i < a.positions.size(); ++i) {
        ASSERT_TRUE(isFinite(a.positions[i]) && isFinite(b.positions[i]));
        changes = changes || length(a.positions[i] - b.positions[i]) > 1e-4f;
      }
      for (Vec3f n : b.normals) ASSERT_NEAR(length(n), 1, 1e-4f);
    }
    EXPECT_TRUE(anyDeforms);
    EXPECT_TRUE(changes);
  }
}

}  // namespace
}  // namespace glint
