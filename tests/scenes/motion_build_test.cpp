// Tests for how the scene builder turns animation into motion over the shutter: which
// placements get time steps, at which times, and that a scene that does not move during the
// shutter builds nothing for motion.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/shapes/sphere.h"
#include "scenes/build.h"

namespace glint {
namespace {

// A unit sphere object placed by node 0, whose translation is keyed linearly along x.
SceneDescription movingSphere(std::vector<float> times, std::vector<Vec3f> positions,
                              float shutterOpen, float shutterClose) {
  SceneDescription d;
  NodeDesc node;
  node.name = "mover";
  node.translationTrack.times = std::move(times);
  node.translationTrack.values = std::move(positions);
  d.nodes.push_back(node);
  ObjectDesc ball;
  ball.name = "ball";
  ball.kind = ObjectKind::Shape;
  ball.shape = std::make_shared<Sphere>(Vec3f{0, 0, 0}, 0.5f);
  ball.transformNode = 0;
  d.objects.push_back(ball);
  CameraDesc cam;
  cam.name = "cam";
  cam.worldFromCamera = Transform::lookAt({0, 0, 10}, {0, 0, 0}, {0, 1, 0});
  cam.shutterOpen = shutterOpen;
  cam.shutterClose = shutterClose;
  d.cameras.push_back(cam);
  d.render.width = 32;
  d.render.height = 32;
  return d;
}

Vec3f origin(const Transform& xf) { return xf.point({0, 0, 0}); }

TEST(MotionBuild, StaticSceneBuildsNoMotion) {
  SceneDescription d = movingSphere({0, 1}, {{0, 0, 0}, {2, 0, 0}}, 0, 0);
  RenderScene s = buildRenderScene(d);
  ASSERT_EQ(s.geometry().instances.size(), 1u);
  EXPECT_FALSE(s.geometry().instances[0].motion.isAnimated());
  EXPECT_FALSE(s.features().has(Feature::MotionBlur));
  // Without a shutter the object is where the animation puts it at the frame's time.
  d.render.time = 0.5;
  RenderScene half = buildRenderScene(d);
  EXPECT_NEAR(origin(half.geometry().instances[0].worldFromObject).x, 1.0f, 1e-6f);
  EXPECT_FALSE(half.features().has(Feature::MotionBlur));
}

TEST(MotionBuild, LinearMotionAcrossTheShutterIsOneSegment) {
  SceneDescription d = movingSphere({0, 1}, {{0, 0, 0}, {2, 0, 0}}, 0, 1);
  RenderScene s = buildRenderScene(d);
  const Instance& inst = s.geometry().instances[0];
  ASSERT_TRUE(inst.motion.isAnimated());
  ASSERT_EQ(inst.motion.keyCount(), 2u);
  EXPECT_NEAR(origin(inst.motion.key(0)).x, 0.0f, 1e-6f);
  EXPECT_NEAR(origin(inst.motion.key(1)).x, 2.0f, 1e-6f);
  EXPECT_NEAR(origin(inst.motion.at(0.25f)).x, 0.5f, 1e-6f);
  EXPECT_TRUE(s.features().has(Feature::MotionBlur));
  EXPECT_NE(std::find(s.features().names().begin(), s.features().names().end(), "motion blur"),
            s.features().names().end());
}

TEST(MotionBuild, ShutterShorterThanTheAnimationSamplesOnlyItsInterval) {
  // Keys span [0, 1]; the frame at t = 0.25 opens the shutter for 0.25 s.
  SceneDescription d = movingSphere({0, 1}, {{0, 0, 0}, {4, 0, 0}}, 0, 0.25f);
  d.render.time = 0.25;
  RenderScene s = buildRenderScene(d);
  const AnimatedTransform& m = s.geometry().instances[0].motion;
  ASSERT_TRUE(m.isAnimated());
  EXPECT_NEAR(origin(m.at(0)).x, 1.0f, 1e-5f);  // t = 0.25
  EXPECT_NEAR(origin(m.at(1)).x, 2.0f, 1e-5f);  // t = 0.5
  EXPECT_NEAR(origin(m.at(0.5f)).x, 1.5f, 1e-5f);
}

TEST(MotionBuild, KeysInsideTheShutterAreSampledAndHitExactly) {
  // Out and back: x = 0 -> 2 -> 0 over [0, 1]; a linear blend of the ends would not move.
  SceneDescription d = movingSphere({0, 0.5f, 1}, {{0, 0, 0}, {2, 0, 0}, {0, 0, 0}}, 0, 1);
  RenderScene s = buildRenderScene(d);
  const AnimatedTransform& m = s.geometry().instances[0].motion;
  ASSERT_TRUE(m.isAnimated());
  ASSERT_GT(m.keyCount(), 2u);
  ASSERT_EQ((m.keyCount() - 1) % 2, 0u) << "t = 0.5 must fall on a key";
  EXPECT_NEAR(origin(m.at(0.5f)).x, 2.0f, 1e-6f);
  EXPECT_NEAR(origin(m.at(0.25f)).x, 1.0f, 1e-5f);
  EXPECT_NEAR(origin(m.at(1)).x, 0.0f, 1e-6f);
}

TEST(MotionBuild, FullTurnIsSampledFinelyEnoughForSlerp) {
  // A full turn about +Y keyed every 120 degrees: slerp between far-apart keys would take the
  // short way round (and a 360-degree pair would not turn at all).
  SceneDescription d = movingSphere({0, 1}, {{0, 0, 0}, {0, 0, 0}}, 0, 1);
  NodeDesc& n = d.nodes[0];
  n.translationTrack = {};
  n.rotationTrack.times = {0, 1.0f / 3, 2.0f / 3, 1};
  for (float deg : {0.0f, 120.0f, 240.0f, 360.0f}) {
    float h = deg * kPi / 360.0f;
    n.rotationTrack.values.push_back({0, std::sin(h), 0, std::cos(h)});
  }
  d.objects[0].shape =
      std::make_shared<Sphere>(Vec3f{1, 0, 0}, 0.5f);  // off the axis, so the turn moves it
  RenderScene s = buildRenderScene(d);
  const AnimatedTransform& m = s.geometry().instances[0].motion;
  ASSERT_TRUE(m.isAnimated());
  for (size_t i = 1; i < m.keyCount(); ++i)
    EXPECT_GT(std::abs(dot(m.decomposedKey(i - 1).rotation, m.decomposedKey(i).rotation)), 0.7071f)
        << "step " << i << " turns by more than 90 degrees";
  // Half way the point (1, 0, 0) has turned 180 degrees to (-1, 0, 0).
  Vec3f p = m.at(0.5f).point({1, 0, 0});
  EXPECT_NEAR(p.x, -1.0f, 1e-3f);
  EXPECT_NEAR(p.z, 0.0f, 1e-3f);
}

TEST(MotionBuild, TheAutomaticCameraFramesTheWholeAnimationOnce) {
  // A ball travelling 8 units along x over 2 s, and no camera: every frame gets the camera that
  // frames the whole path, not one that follows (or zooms in on) the ball.
  SceneDescription d = movingSphere({0, 2}, {{-4, 0, 0}, {4, 0, 0}}, 0, 0);
  d.cameras.clear();
  std::vector<Vec3f> positions;
  for (double t : {0.0, 0.7, 2.0}) {
    d.render.time = t;
    const RenderScene s = buildRenderScene(d);
    positions.push_back(s.camera().position());
    // The ball is in view wherever it is: a ray from the camera to it hits it.
    const Vec3f ball{-4 + 4 * float(t), 0, 0};
    Ray ray{s.camera().position(), normalize(ball - s.camera().position())};
    Hit hit;
    EXPECT_TRUE(s.accel().closestHit(ray, &hit)) << t;
  }
  // The same camera to float precision (each frame's own bounds, padded by their rounding
  // error, join the swept ones; they may differ in the last bit).
  for (int i : {1, 2})
    EXPECT_LT(length(positions[i] - positions[0]), 1e-5f * length(positions[0])) << i;
  // Centred on the path, and far enough back to see both ends (from the front, +Z).
  EXPECT_NEAR(positions[0].x - 0.35f / 0.45f * positions[0].y, 0, 1.0f);
  EXPECT_GT(positions[0].z, 4);
}

TEST(MotionBuild, MovingMeshIsNotBakedAndStaticOneIs) {
  SceneDescription d = movingSphere({0, 1}, {{0, 0, 0}, {1, 0, 0}}, 0, 1);
  d.objects.clear();
  MeshDesc tri;
  tri.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  tri.indices = {0, 1, 2};
  d.meshes = {tri, tri};
  InstanceDesc moving{0, Transform::translate({0, 0, 0}), "moving", {}};
  moving.transformNode = 0;
  d.instances = {moving, {1, Transform::translate({0, 3, 0}), "still", {}}};
  RenderScene s = buildRenderScene(d);
  ASSERT_EQ(s.geometry().instances.size(), 2u);
  EXPECT_TRUE(s.geometry().instances[0].motion.isAnimated());
  EXPECT_EQ(s.geometry().meshes[s.geometry().instances[0].mesh].positions[1], (Vec3f{1, 0, 0}))
      << "a moving mesh keeps its object space";
  EXPECT_FALSE(s.geometry().instances[1].motion.isAnimated());
  EXPECT_TRUE(s.geometry().instances[1].worldFromObject.isIdentity()) << "the still one is baked";
}

TEST(MotionBuild, LightsArePlacedInTheMiddleOfTheShutter) {
  // The node moves x = 0 -> 10 over [0, 1]; the frame at t = 0.5 has its shutter open for
  // 0.5 s, so the light (5 above the node) is at x = 7.5 for the frame.
  SceneDescription d = movingSphere({0, 1}, {{0, 0, 0}, {10, 0, 0}}, 0, 0.5f);
  LightDesc bulb;
  bulb.type = LightType::Point;
  bulb.intensity = 1;
  bulb.transformNode = 0;
  bulb.nodeFromLight = Transform::translate({0, 5, 0});
  d.lights.push_back(bulb);
  d.render.time = 0.5;
  RenderScene s = buildRenderScene(d);
  ASSERT_EQ(s.lights().size(), 1u);
  EXPECT_TRUE(s.features().has(Feature::MotionBlur));
  EXPECT_FALSE(s.features().has(Feature::DefaultLight));
  // A point light's incident direction reveals its position.
  auto ls = s.lights()[0]->sampleLi(LightSampleContext::inMedium({7.5f, 0, 0}, 0), {0.5f, 0.5f});
  ASSERT_TRUE(ls.has_value());
  EXPECT_NEAR(ls->wi.x, 0.0f, 1e-5f);
  EXPECT_NEAR(ls->wi.y, 1.0f, 1e-5f);
}

TEST(MotionBuild, ObjectOffItsPivotFollowsTheArc) {
  // A sphere 3 units off the node's axis, the node turning 90 degrees about +Y: the linear blend
  // of two keys would cut the corner (radius 2.12 half way); the builder adds keys until the
  // path is within a thousandth of the arc.
  SceneDescription d = movingSphere({0, 1}, {{0, 0, 0}, {0, 0, 0}}, 0, 1);
  NodeDesc& n = d.nodes[0];
  n.translationTrack = {};
  n.rotationTrack.times = {0, 1};
  const float h = 90.0f * kPi / 360.0f;
  n.rotationTrack.values = {{0, 0, 0, 1}, {0, std::sin(h), 0, std::cos(h)}};
  d.objects[0].nodeFromObject = Transform::translate({3, 0, 0});
  RenderScene s = buildRenderScene(d);
  const AnimatedTransform& m = s.geometry().instances[0].motion;
  ASSERT_TRUE(m.isAnimated());
  EXPECT_GT(m.keyCount(), 2u);
  EXPECT_LE(m.keyCount(), kMaxMotionKeys);
  for (float t : {0.1f, 0.3f, 0.5f, 0.77f}) {
    Vec3f c = origin(m.at(t));
    EXPECT_NEAR(std::sqrt(c.x * c.x + c.z * c.z), 3.0f, 3e-3f) << "t " << t;
  }
}

TEST(MotionBuild, StepInsideTheShutterStaysWithinEmbreesTimeStepLimit) {
  // A step track jumps 180 degrees half way: no number of keys makes that smooth, so the
  // builder stops at Embree's limit instead of failing the build.
  SceneDescription d = movingSphere({0, 1}, {{0, 0, 0}, {0, 0, 0}}, 0, 1);
  NodeDesc& n = d.nodes[0];
  n.translationTrack = {};
  n.rotationTrack.interpolation = Interpolation::Step;
  n.rotationTrack.times = {0, 0.5f};
  n.rotationTrack.values = {{0, 0, 0, 1}, {0, 1, 0, 0}};
  d.objects[0].nodeFromObject = Transform::translate({1, 0, 0});
  RenderScene s = buildRenderScene(d);
  const AnimatedTransform& m = s.geometry().instances[0].motion;
  ASSERT_TRUE(m.isAnimated());
  EXPECT_LE(m.keyCount(), kMaxMotionKeys);
  EXPECT_NEAR(origin(m.at(0)).x, 1.0f, 1e-5f);
  EXPECT_NEAR(origin(m.at(1)).x, -1.0f, 1e-5f);
  Hit hit;  // and the accelerator was built
  EXPECT_TRUE(s.accel().closestHit(Ray{{-1, 0, 5}, {0, 0, -1}, 0, kInfinity, 1.0f}, &hit));
}

}  // namespace
}  // namespace glint
