// glint tests — keyframe tracks (every interpolation, clamping, exact keys), the node
// hierarchy, glTF animations (Khronos BoxAnimated and AnimatedTriangle against hand-computed
// keyframe values, and one malformed input per error), and the loader's per-frame API.
#include "scenes/animation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "geometry/shapes/sphere.h"
#include "scene_error_support.h"
#include "scenes/gltf_loader.h"
#include "scenes/load.h"
#include "test_support.h"

namespace glint {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::errorFrom;

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

template <class T>
Track<T> track(Interpolation interpolation, std::vector<float> times, std::vector<T> values) {
  Track<T> t;
  t.interpolation = interpolation;
  t.times = std::move(times);
  t.values = std::move(values);
  return t;
}

void expectNear(Vec3f a, Vec3f b, float tolerance = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tolerance) << "x";
  EXPECT_NEAR(a.y, b.y, tolerance) << "y";
  EXPECT_NEAR(a.z, b.z, tolerance) << "z";
}

// Quaternions q and -q are the same rotation.
void expectSameRotation(const Quaternion& a, const Quaternion& b, float tolerance = 1e-5f) {
  EXPECT_NEAR(std::abs(dot(a, b)), 1.0f, tolerance)
      << "(" << a.x << ", " << a.y << ", " << a.z << ", " << a.w << ") vs (" << b.x << ", " << b.y
      << ", " << b.z << ", " << b.w << ")";
}

Quaternion aboutAxis(Vec3f axis, float degrees) {
  Vec3f a = normalize(axis);
  float h = degrees * kPi / 360.0f;
  return {a.x * std::sin(h), a.y * std::sin(h), a.z * std::sin(h), std::cos(h)};
}

// ---------------------------------------------------------------------------------------------
// Tracks
// ---------------------------------------------------------------------------------------------

TEST(Track, StepHoldsTheLastKeyAtOrBeforeTheTime) {
  auto t = track<float>(Interpolation::Step, {0, 1, 2}, {0, 10, 20});
  EXPECT_EQ(evaluate(t, 0.5), 0);
  EXPECT_EQ(evaluate(t, 1.0), 10);
  EXPECT_EQ(evaluate(t, 1.999), 10);
  EXPECT_EQ(evaluate(t, 2.0), 20);
}

TEST(Track, ClampsBeforeTheFirstAndAfterTheLastKey) {
  for (Interpolation i : {Interpolation::Step, Interpolation::Linear, Interpolation::Smooth}) {
    auto t = track<float>(i, {1, 2, 4}, {3, 7, -5});
    EXPECT_EQ(evaluate(t, -10.0), 3) << interpolationName(i);
    EXPECT_EQ(evaluate(t, 0.999), 3) << interpolationName(i);
    EXPECT_EQ(evaluate(t, 4.0), -5) << interpolationName(i);
    EXPECT_EQ(evaluate(t, 100.0), -5) << interpolationName(i);
  }
  // CubicSpline clamps to the key *value* (the middle of in-tangent, value, out-tangent).
  auto c = track<float>(Interpolation::CubicSpline, {1, 2}, {100, 3, 200, 300, 7, 400});
  EXPECT_EQ(evaluate(c, 0.0), 3);
  EXPECT_EQ(evaluate(c, 9.0), 7);
}

TEST(Track, EveryInterpolationGivesTheKeyExactlyOnAKey) {
  for (Interpolation i : {Interpolation::Step, Interpolation::Linear, Interpolation::Smooth}) {
    auto t = track<float>(i, {0, 0.3f, 1.7f, 2}, {0.1f, 7.3f, -2.9f, 4});
    EXPECT_EQ(evaluate(t, double(0.3f)), 7.3f) << interpolationName(i);
    EXPECT_EQ(evaluate(t, double(1.7f)), -2.9f) << interpolationName(i);
  }
  auto q = track<Quaternion>(
      Interpolation::Linear, {0, 1, 2},
      {aboutAxis({0, 0, 1}, 0), aboutAxis({1, 2, 3}, 100), aboutAxis({0, 1, 0}, 50)});
  Quaternion k = evaluate(q, 1.0);
  EXPECT_EQ(k.x, q.values[1].x);
  EXPECT_EQ(k.w, q.values[1].w);
}

TEST(Track, LinearInterpolatesFloatsAndVectors) {
  auto f = track<float>(Interpolation::Linear, {0, 2}, {1, 5});
  EXPECT_FLOAT_EQ(evaluate(f, 0.5), 2);
  EXPECT_FLOAT_EQ(evaluate(f, 1.5), 4);
  auto v = track<Vec3f>(Interpolation::Linear, {1, 3}, {{0, 0, 0}, {2, -4, 6}});
  expectNear(evaluate(v, 2.0), {1, -2, 3});
  expectNear(evaluate(v, 2.5), {1.5f, -3, 4.5f});
  auto v2 = track<Vec2f>(Interpolation::Linear, {0, 1}, {{0, 1}, {1, 3}});
  EXPECT_FLOAT_EQ(evaluate(v2, 0.25).y, 1.5f);
}

TEST(Track, LinearRotationsAreSlerpedAlongTheShorterArc) {
  auto q = track<Quaternion>(Interpolation::Linear, {0, 1},
                             {aboutAxis({0, 0, 1}, 0), aboutAxis({0, 0, 1}, 90)});
  expectSameRotation(evaluate(q, 0.5), aboutAxis({0, 0, 1}, 45));
  expectSameRotation(evaluate(q, 0.25), aboutAxis({0, 0, 1}, 22.5f));
  // Not the chord: a normalised lerp would give 45.0 at 0.5 as well, but not 22.5 at 0.25
  // (it gives about 24.1 degrees).
  Quaternion nlerp = normalize({0, 0, 0.75f * 0 + 0.25f * aboutAxis({0, 0, 1}, 90).z,
                                0.75f + 0.25f * aboutAxis({0, 0, 1}, 90).w});
  EXPECT_GT(std::abs(evaluate(q, 0.25).z - nlerp.z), 1e-3f);
  // The second key stored as -q: still the short way (from 0 to 90 degrees, not round 270).
  Quaternion far = aboutAxis({0, 0, 1}, 90);
  auto flipped = track<Quaternion>(Interpolation::Linear, {0, 1},
                                   {aboutAxis({0, 0, 1}, 0), {-far.x, -far.y, -far.z, -far.w}});
  expectSameRotation(evaluate(flipped, 0.5), aboutAxis({0, 0, 1}, 45));
}

TEST(Track, CubicSplineIsGltfHermiteWithTangentsScaledByTheKeyInterval) {
  // Keys at 0 and 2: key 0 = (in 9, value 1, out 3), key 1 = (in -1, value 5, out 9).
  // p(s) = (2s^3 - 3s^2 + 1) 1 + 2 (s^3 - 2s^2 + s) 3 + (-2s^3 + 3s^2) 5 + 2 (s^3 - s^2) (-1).
  auto c = track<float>(Interpolation::CubicSpline, {0, 2}, {9, 1, 3, -1, 5, 9});
  // s = 0.5: 0.5 + 0.75 + 2.5 + 0.25.
  EXPECT_FLOAT_EQ(evaluate(c, 1.0), 4.0f);
  // s = 0.25: 0.84375 + 0.84375 + 0.78125 + 0.09375.
  EXPECT_FLOAT_EQ(evaluate(c, 0.5), 2.5625f);
  // Tangents equal to the chord's slope (2 per second) reproduce the straight line.
  auto line = track<Vec3f>(Interpolation::CubicSpline, {1, 3},
                           {{2, 2, 2}, {0, 0, 0}, {2, 2, 2}, {2, 2, 2}, {4, 4, 4}, {2, 2, 2}});
  expectNear(evaluate(line, 1.7), {1.4f, 1.4f, 1.4f});
  // Quaternions are renormalised.
  Quaternion a = aboutAxis({0, 1, 0}, 0), b = aboutAxis({0, 1, 0}, 90);
  auto q = track<Quaternion>(Interpolation::CubicSpline, {0, 1}, {{}, a, {}, {}, b, {}});
  Quaternion mid = evaluate(q, 0.5);
  EXPECT_NEAR(dot(mid, mid), 1.0f, 1e-6f);
  expectSameRotation(mid, aboutAxis({0, 1, 0}, 45));  // symmetric, zero tangents
}

TEST(Track, SmoothIsCatmullRomThroughTheKeys) {
  // Keys 0, 1, 0 at t = 0, 1, 2. Tangents (per second): one-sided 1 at t = 0, central 0 at
  // t = 1. At t = 0.5: h10 * 1 + h01 * 1 = 0.125 + 0.5.
  auto t = track<float>(Interpolation::Smooth, {0, 1, 2}, {0, 1, 0});
  EXPECT_FLOAT_EQ(evaluate(t, 0.5), 0.625f);
  EXPECT_FLOAT_EQ(evaluate(t, 1.5), 0.625f);  // mirror image
  // A straight line stays straight, even with unevenly spaced keys.
  auto line = track<float>(Interpolation::Smooth, {0, 1, 3, 4}, {0, 2, 6, 8});
  for (double x : {0.3, 1.2, 2.9, 3.5}) EXPECT_NEAR(evaluate(line, x), 2 * x, 1e-5) << x;
  // C1 at a key: the slopes just before and after agree.
  auto bumpy = track<float>(Interpolation::Smooth, {0, 1, 2, 4}, {0, 3, 1, 2});
  double h = 1e-3;
  double left = (evaluate(bumpy, 2.0) - evaluate(bumpy, 2.0 - h)) / h;
  double right = (evaluate(bumpy, 2.0 + h) - evaluate(bumpy, 2.0)) / h;
  EXPECT_NEAR(left, right, 2e-2);
  // Quaternions: renormalised, and a key stored as -q does not make it turn the long way.
  Quaternion q1 = aboutAxis({0, 1, 0}, 60);
  auto q = track<Quaternion>(
      Interpolation::Smooth, {0, 1, 2},
      {aboutAxis({0, 1, 0}, 0), {-q1.x, -q1.y, -q1.z, -q1.w}, aboutAxis({0, 1, 0}, 120)});
  Quaternion mid = evaluate(q, 1.5);
  EXPECT_NEAR(dot(mid, mid), 1.0f, 1e-6f);
  expectSameRotation(mid, aboutAxis({0, 1, 0}, 90), 1e-4f);
}

// ---------------------------------------------------------------------------------------------
// Nodes
// ---------------------------------------------------------------------------------------------

TEST(Node, LocalTransformIsTranslationRotationScaleFromTracksOrRestValues) {
  NodeDesc n;
  n.translation = {1, 2, 3};
  n.scale = {2, 2, 2};
  n.rotationTrack = track<Quaternion>(Interpolation::Linear, {0, 1},
                                      {aboutAxis({0, 0, 1}, 0), aboutAxis({0, 0, 1}, 90)});
  // Rest translation and scale, rotation from the track: (1,0,0) -> scale 2 -> turn 90 -> +t.
  expectNear(n.localAt(1.0).point({1, 0, 0}), {1, 4, 3});
  n.translationTrack = track<Vec3f>(Interpolation::Step, {0, 2}, {{0, 0, 0}, {5, 0, 0}});
  expectNear(n.localAt(3.0).point({1, 0, 0}), {5, 2, 0});
  // Axis-angle tracks turn by the written amount (here 270 degrees between two keys).
  NodeDesc spin;
  spin.rotationAxis = {0, 1, 0};
  spin.angleTrack = track<float>(Interpolation::Linear, {0, 1}, {0, 360});
  expectNear(spin.localAt(0.75).point({1, 0, 0}), {0, 0, 1}, 1e-5f);
  // A matrix node ignores the rest values.
  NodeDesc m;
  m.hasMatrix = true;
  m.matrix = Transform::translate({0, 7, 0});
  m.translation = {100, 0, 0};
  expectNear(m.localAt(0).point({0, 0, 0}), {0, 7, 0});
}

TEST(Node, WorldTransformFollowsTheParentChain) {
  std::vector<NodeDesc> nodes(3);
  nodes[0].translation = {10, 0, 0};
  nodes[1].parent = 0;
  nodes[1].rotationTrack = track<Quaternion>(Interpolation::Linear, {1, 2},
                                             {aboutAxis({0, 1, 0}, 0), aboutAxis({0, 1, 0}, 90)});
  nodes[2].parent = 1;
  nodes[2].translation = {0, 0, -1};
  // Node 2 sits 1 in front of node 1, which turns about Y under a parent moved by +10 in x.
  expectNear(worldFromNode(nodes, 2, 0.0).point({0, 0, 0}), {10, 0, -1});
  expectNear(worldFromNode(nodes, 2, 2.0).point({0, 0, 0}), {9, 0, 0});
  expectNear(worldFromNode(nodes, -1, 2.0).point({1, 2, 3}), {1, 2, 3});
  EXPECT_FALSE(isAnimated(nodes, 0));
  EXPECT_TRUE(isAnimated(nodes, 1));
  EXPECT_TRUE(isAnimated(nodes, 2));
  EXPECT_FALSE(isAnimated(nodes, -1));
  auto range = animationRange(nodes);
  EXPECT_EQ(range.first, 1.0);
  EXPECT_EQ(range.second, 2.0);
  EXPECT_EQ(animationRange(std::vector<NodeDesc>{}), (std::pair<double, double>{0.0, 0.0}));
}

// ---------------------------------------------------------------------------------------------
// glTF: the Khronos samples
// ---------------------------------------------------------------------------------------------

std::string sample(const std::string& model, const std::string& variant) {
  std::string file = model + (variant == "glTF-Binary" ? ".glb" : ".gltf");
  std::string path = test::assetsDir() + "/gltf/" + model + "/" + variant + "/" + file;
  EXPECT_TRUE(fs::is_regular_file(path))
      << path << " is missing: set GLINT_ASSETS to the shared asset folder "
      << "(e.g. GLINT_ASSETS=/work/shared/assets)";
  return path;
}

const InstanceDesc* instanceOfNode(const SceneDescription& s, const std::string& node) {
  for (const InstanceDesc& i : s.instances)
    if (i.node == node) return &i;
  ADD_FAILURE() << "no instance on " << node;
  return nullptr;
}

Transform worldAt(const SceneDescription& s, const InstanceDesc& i, double t) {
  return worldFromNode(s.nodes, i.transformNode, t) * i.nodeFromObject;
}

// BoxAnimated's keyframes, read from BoxAnimated0.bin (accessors 6 to 9) with a few lines of
// Python (struct.unpack over the bufferView ranges the .gltf gives):
//   node 2 rotation, LINEAR: t = 1.25 -> (-0, -0, -0, -1) (identity), t = 2.5 -> (1, 0, 0,
//     4.49e-11) (180 degrees about X); slerp takes the short way, through +90 degrees about X.
//   node 0 translation, LINEAR: t = 0, 1.25, 2.5, 3.70833 -> y = 0, 2.52, 2.52, 0.
// Node 0 -> node 1 -> node 2 (mesh 0, the inner box); node 3 (mesh 1) is static.
TEST(GltfAnimation, BoxAnimatedMatchesItsKeyframes) {
  for (const char* variant : {"glTF", "glTF-Binary", "glTF-Embedded"}) {
    SCOPED_TRACE(variant);
    SceneDescription s;
    loadGltf(sample("BoxAnimated", variant), &s);
    ASSERT_EQ(s.nodes.size(), 3u);  // nodes 0, 1, 2: the animated chain; node 3 is not kept
    const InstanceDesc* box = instanceOfNode(s, "node 2");
    const InstanceDesc* still = instanceOfNode(s, "node 3");
    ASSERT_TRUE(box && still);
    EXPECT_EQ(still->transformNode, -1);
    ASSERT_GE(box->transformNode, 0);
    EXPECT_TRUE(box->nodeFromObject.isIdentity());
    EXPECT_TRUE(isAnimated(s.nodes, box->transformNode));

    Vec3f o{0, 0, 0}, y{0, 1, 0};
    // t = 0: translation key 0, rotation before its first key (identity).
    expectNear(worldAt(s, *box, 0).point(y), {0, 1, 0});
    expectNear(box->worldFromObject.point(y), {0, 1, 0});  // the static field holds t = 0
    // t = 0.625: halfway up the first translation segment.
    expectNear(worldAt(s, *box, 0.625).point(o), {0, 1.26f, 0});
    // t = 1.875: at the top, turned 90 degrees about +X (y -> z).
    expectNear(worldAt(s, *box, 1.875).point(o), {0, 2.52f, 0});
    expectNear(worldAt(s, *box, 1.875).vector(y), {0, 0, 1});
    // t = 3.1: coming down, 0.6 s into the last 1.20833 s segment; turned 180 degrees.
    float down = 2.52f * (1 - 0.6f / (3.708329916f - 2.5f));
    expectNear(worldAt(s, *box, 3.1).point(o), {0, down, 0}, 1e-4f);
    expectNear(worldAt(s, *box, 3.1).vector(y), {0, -1, 0});
    // After the last key everything holds.
    expectNear(worldAt(s, *box, 10).point(o), {0, 0, 0});
    auto range = animationRange(s.nodes);
    EXPECT_EQ(range.first, 0.0);
    EXPECT_NEAR(range.second, 3.70833, 1e-5);
  }
}

// AnimatedTriangle: one LINEAR rotation channel on node 0, read from animation.bin:
//   t = 0, 0.25, 0.5, 0.75, 1 -> (0,0,0,1), (0,0,.707,.707), (0,0,1,0), (0,0,.707,-.707),
//   (0,0,0,1): 0, 90, 180, 270 (stored as -90's negation) and 360 degrees about Z.
TEST(GltfAnimation, AnimatedTriangleTurnsOnceAboutZ) {
  for (const char* variant : {"glTF", "glTF-Embedded"}) {
    SCOPED_TRACE(variant);
    SceneDescription s;
    loadGltf(sample("AnimatedTriangle", variant), &s);
    ASSERT_EQ(s.instances.size(), 1u);
    const InstanceDesc& tri = s.instances[0];
    ASSERT_GE(tri.transformNode, 0);
    auto turned = [&](double t) { return worldAt(s, tri, t).vector({1, 0, 0}); };
    float r = std::sqrt(0.5f);
    expectNear(turned(0), {1, 0, 0});
    expectNear(turned(0.125), {r, r, 0}, 1e-4f);
    expectNear(turned(0.25), {0, 1, 0}, 1e-4f);
    expectNear(turned(0.5), {-1, 0, 0}, 1e-4f);
    expectNear(turned(0.625), {-r, -r, 0}, 1e-4f);  // 225: keeps turning the same way
    expectNear(turned(0.875), {r, -r, 0}, 1e-4f);   // 315
    expectNear(turned(5), {1, 0, 0}, 1e-4f);
  }
}

// ---------------------------------------------------------------------------------------------
// glTF: hand-made files (a data-URI buffer of times and values)
// ---------------------------------------------------------------------------------------------

std::string base64(const std::string& bytes) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    uint32_t v = uint32_t(uint8_t(bytes[i])) << 16 | uint32_t(uint8_t(bytes[i + 1])) << 8 |
                 uint8_t(bytes[i + 2]);
    for (int s = 18; s >= 0; s -= 6) out += k[(v >> s) & 63];
  }
  if (i < bytes.size()) {
    uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
    if (i + 1 < bytes.size()) v |= uint32_t(uint8_t(bytes[i + 1])) << 8;
    out += k[(v >> 18) & 63];
    out += k[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? k[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

template <class T>
std::string bytesOf(const std::vector<T>& v) {
  std::string s(v.size() * sizeof(T), '\0');
  std::memcpy(s.data(), v.data(), s.size());
  return s;
}

// A parent node (0) with a child camera node (1) and a static node (2), and one animation on
// node 0 whose sampler reads `times` (accessor 0) and `values` (accessor 1, `type`).
json animatedDoc(const std::vector<float>& times, const std::string& valueBytes,
                 const std::string& type, int componentType, size_t valueCount,
                 const std::string& path, const std::string& interpolation = "LINEAR") {
  std::string timeBytes = bytesOf(times);
  std::string all = timeBytes + valueBytes;
  json doc = {
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0, 2}}}}},
      {"nodes",
       {{{"name", "Parent"}, {"children", {1}}, {"translation", {0, 0, 9}}},
        {{"name", "Eye"}, {"camera", 0}, {"translation", {1, 0, 0}}},
        {{"name", "Still"}, {"camera", 0}}}},
      {"cameras", {{{"type", "perspective"}, {"perspective", {{"yfov", 0.7}, {"znear", 0.1}}}}}},
      {"buffers",
       {{{"byteLength", all.size()},
         {"uri", "data:application/octet-stream;base64," + base64(all)}}}},
      {"bufferViews",
       {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", timeBytes.size()}},
        {{"buffer", 0}, {"byteOffset", timeBytes.size()}, {"byteLength", valueBytes.size()}}}},
      {"accessors",
       {{{"bufferView", 0}, {"componentType", 5126}, {"count", times.size()}, {"type", "SCALAR"}},
        {{"bufferView", 1},
         {"componentType", componentType},
         {"normalized", componentType != 5126},
         {"count", valueCount},
         {"type", type}}}},
      {"animations",
       {{{"name", "Move"},
         {"samplers", {{{"input", 0}, {"output", 1}, {"interpolation", interpolation}}}},
         {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", path}}}}}}}}}};
  if (componentType == 5126) doc["accessors"][1].erase("normalized");
  return doc;
}

json translationDoc() {
  return animatedDoc({0, 1, 2}, bytesOf(std::vector<float>{0, 0, 0, 2, 0, 0, 2, 4, 0}), "VEC3",
                     5126, 3, "translation");
}

std::string writeDoc(const json& doc, const std::string& name) {
  std::string path = test::scratchDir("animation_" + name) + "/" + name + ".gltf";
  std::ofstream(path) << doc.dump(1);
  return path;
}

SceneDescription loadDoc(const json& doc, const std::string& name) {
  SceneDescription s;
  loadGltf(writeDoc(doc, name), &s);
  return s;
}

const CameraDesc& cameraNamed(const SceneDescription& s, const std::string& name) {
  for (const CameraDesc& c : s.cameras)
    if (c.name == name) return c;
  ADD_FAILURE() << "no camera " << name;
  return s.cameras.front();
}

TEST(GltfAnimation, CamerasBelowAnAnimatedNodeFollowIt) {
  SceneDescription s = loadDoc(translationDoc(), "camera_follows");
  const CameraDesc& eye = cameraNamed(s, "Eye");
  const CameraDesc& still = cameraNamed(s, "Still");
  EXPECT_EQ(still.transformNode, -1);
  ASSERT_GE(eye.transformNode, 0);
  EXPECT_EQ(s.nodes[size_t(eye.transformNode)].name, "Eye");
  auto at = [&](double t) {
    return (worldFromNode(s.nodes, eye.transformNode, t) * eye.nodeFromCamera).point({});
  };
  expectNear(at(0), {1, 0, 0});  // the channel replaces the rest translation (0, 0, 9)
  expectNear(at(0.5), {2, 0, 0});
  expectNear(at(1.5), {3, 2, 0});
  expectNear(eye.worldFromCamera.point({}), {1, 0, 0});
}

TEST(GltfAnimation, RootTransformOfAJsonSceneEntryIsAboveTheAnimatedNodes) {
  SceneDescription s;
  loadGltf(writeDoc(translationDoc(), "root_transform"), &s, Transform::translate({0, 100, 0}));
  const CameraDesc& eye = cameraNamed(s, "Eye");
  expectNear(worldFromNode(s.nodes, eye.transformNode, 1.0).point({}), {3, 100, 0});
  expectNear(eye.worldFromCamera.point({}), {1, 100, 0});
}

TEST(GltfAnimation, StepAndCubicSplineSamplers) {
  SceneDescription step =
      loadDoc(animatedDoc({0, 1, 2}, bytesOf(std::vector<float>{0, 0, 0, 2, 0, 0, 2, 4, 0}), "VEC3",
                          5126, 3, "translation", "STEP"),
              "step");
  const CameraDesc& e = cameraNamed(step, "Eye");
  expectNear(worldFromNode(step.nodes, e.transformNode, 1.9).point({}), {3, 0, 0});
  // CUBICSPLINE: keys at 0 and 2 with x: (in 0, value 0, out 3), (in -1, value 8, out 0).
  // At t = 1: 0.5 * 0 + 0.125 * 2 * 3 + 0.5 * 8 - 0.125 * 2 * -1 = 5, plus the child's 1.
  std::vector<float> v = {0, 0, 0, 0, 0, 0, 3, 0, 0, -1, 0, 0, 8, 0, 0, 0, 0, 0};
  SceneDescription cubic = loadDoc(
      animatedDoc({0, 2}, bytesOf(v), "VEC3", 5126, 6, "translation", "CUBICSPLINE"), "cubic");
  const CameraDesc& c = cameraNamed(cubic, "Eye");
  expectNear(worldFromNode(cubic.nodes, c.transformNode, 1.0).point({}), {6, 0, 0});
}

TEST(GltfAnimation, NormalizedShortQuaternionsAreDecoded) {
  // 90 degrees about Z as normalized SHORT: (0, 0, 23170, 23170) / 32767.
  std::vector<int16_t> q = {0, 0, 0, 32767, 0, 0, 23170, 23170};
  SceneDescription s =
      loadDoc(animatedDoc({0, 1}, bytesOf(q), "VEC4", 5122, 2, "rotation"), "short_quaternion");
  const CameraDesc& e = cameraNamed(s, "Eye");
  // The camera node sits at +1 in x under the parent (rest translation (0, 0, 9)), which
  // turns to 90 degrees about Z.
  expectNear(worldFromNode(s.nodes, e.transformNode, 1.0).point({}), {0, 1, 9}, 1e-4f);
}

TEST(GltfAnimation, WeightsOfANodeWithoutMorphTargetsAreAWarningNotAnError) {
  json doc = translationDoc();
  doc["accessors"].push_back(
      {{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "SCALAR"}});
  doc["animations"][0]["samplers"].push_back({{"input", 0}, {"output", 2}});
  doc["animations"][0]["channels"].push_back(
      {{"sampler", 1}, {"target", {{"node", 2}, {"path", "weights"}}}});
  SceneDescription s = loadDoc(doc, "weights");
  ASSERT_FALSE(s.warnings.empty());
  EXPECT_NE(s.warnings.back().find("/animations/0/channels/1"), std::string::npos);
  EXPECT_NE(s.warnings.back().find("has no mesh with morph targets"), std::string::npos);
  EXPECT_EQ(cameraNamed(s, "Still").transformNode, -1);
}

TEST(GltfAnimation, TwoAnimationsPlayTogether) {
  json doc = translationDoc();
  json second = doc["animations"][0];
  second["name"] = "Other";
  second["channels"][0]["target"]["node"] = 2;
  doc["animations"].push_back(second);
  SceneDescription s = loadDoc(doc, "two_animations");
  EXPECT_GE(cameraNamed(s, "Eye").transformNode, 0);
  const CameraDesc& still = cameraNamed(s, "Still");
  ASSERT_GE(still.transformNode, 0);
  expectNear(worldFromNode(s.nodes, still.transformNode, 2.0).point({}), {2, 4, 0});
}

// One malformed input per check, with the pointer the error must name.
struct BadAnimation {
  const char* name;
  std::function<void(json&)> edit;
  const char* pointer;
  const char* phrase;
};

TEST(GltfAnimation, MalformedAnimationsNameTheirPointer) {
  std::vector<float> unsortedValues = {0, 0, 0, 1, 0, 0, 2, 0, 0};
  const BadAnimation cases[] = {
      {"bad_interpolation",
       [](json& d) { d["animations"][0]["samplers"][0]["interpolation"] = "SPLINE"; },
       "/animations/0/samplers/0/interpolation", "unknown interpolation 'SPLINE'"},
      {"bad_path", [](json& d) { d["animations"][0]["channels"][0]["target"]["path"] = "color"; },
       "/animations/0/channels/0/target/path", "unknown path 'color'"},
      {"bad_node", [](json& d) { d["animations"][0]["channels"][0]["target"]["node"] = 7; },
       "/animations/0/channels/0/target/node", "node 7 does not exist"},
      {"bad_sampler", [](json& d) { d["animations"][0]["channels"][0]["sampler"] = 1; },
       "/animations/0/channels/0/sampler", "sampler 1 does not exist"},
      {"no_channels", [](json& d) { d["animations"][0]["channels"] = json::array(); },
       "/animations/0/channels", "must not be empty"},
      {"missing_target", [](json& d) { d["animations"][0]["channels"][0].erase("target"); },
       "/animations/0/channels/0", "missing required property 'target'"},
      {"input_not_scalar", [](json& d) { d["animations"][0]["samplers"][0]["input"] = 1; },
       "/animations/0/samplers/0/input", "keyframe times must be SCALAR of FLOAT"},
      {"wrong_output_type",
       [](json& d) { d["animations"][0]["channels"][0]["target"]["path"] = "rotation"; },
       "/animations/0/samplers/0/output", "needs VEC4"},
      {"wrong_output_count", [](json& d) { d["accessors"][1]["count"] = 2; },
       "/animations/0/samplers/0/output", "needs 3"},
      {"cubic_count",
       [](json& d) { d["animations"][0]["samplers"][0]["interpolation"] = "CUBICSPLINE"; },
       "/animations/0/samplers/0/output", "needs 9"},
      {"matrix_node",
       [](json& d) {
         d["nodes"][0].erase("translation");
         d["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
       },
       "/animations/0/channels/0/target/node", "has a matrix"},
      {"duplicate_target",
       [](json& d) { d["animations"][0]["channels"].push_back(d["animations"][0]["channels"][0]); },
       "/animations/0/channels/1", "already animated by /animations/0/channels/0"},
  };
  for (const BadAnimation& c : cases) {
    SCOPED_TRACE(c.name);
    json doc = translationDoc();
    c.edit(doc);
    std::string path = writeDoc(doc, c.name);
    SceneDescription s;
    EXPECT_SCENE_ERROR(errorFrom([&] { loadGltf(path, &s); }), path, c.pointer, c.phrase);
  }
}

TEST(GltfAnimation, KeyframeDataIsChecked) {
  {
    json doc = animatedDoc({0, 2, 1}, bytesOf(std::vector<float>(9, 1.0f)), "VEC3", 5126, 3,
                           "translation");
    std::string path = writeDoc(doc, "unsorted_times");
    SceneDescription s;
    EXPECT_SCENE_ERROR(errorFrom([&] { loadGltf(path, &s); }), path,
                       "/animations/0/samplers/0/input", "times must increase strictly");
    EXPECT_TRUE(s.nodes.empty());  // nothing half-loaded
  }
  {
    json doc = animatedDoc({0, 1}, bytesOf(std::vector<float>{1, 1, 1, 0, 1, 1}), "VEC3", 5126, 2,
                           "scale");
    std::string path = writeDoc(doc, "zero_scale");
    SceneDescription s;
    EXPECT_SCENE_ERROR(errorFrom([&] { loadGltf(path, &s); }), path,
                       "/animations/0/samplers/0/output", "zero component");
  }
  {
    json doc = animatedDoc({0, 1}, bytesOf(std::vector<float>{0, 0, 0, 0, 0, 0, 0, 1}), "VEC4",
                           5126, 2, "rotation");
    std::string path = writeDoc(doc, "zero_quaternion");
    SceneDescription s;
    EXPECT_SCENE_ERROR(errorFrom([&] { loadGltf(path, &s); }), path,
                       "/animations/0/samplers/0/output", "zero quaternion");
  }
  {
    // Integer quaternions must be normalized.
    json doc = animatedDoc({0, 1}, bytesOf(std::vector<int16_t>{0, 0, 0, 1, 0, 0, 0, 1}), "VEC4",
                           5122, 2, "rotation");
    doc["accessors"][1].erase("normalized");
    std::string path = writeDoc(doc, "unnormalized_short");
    SceneDescription s;
    EXPECT_SCENE_ERROR(errorFrom([&] { loadGltf(path, &s); }), path,
                       "/animations/0/samplers/0/output", "normalized");
  }
}

// ---------------------------------------------------------------------------------------------
// SceneLoader: the glTF is read once, the sidecar applied per time
// ---------------------------------------------------------------------------------------------

TEST(SceneLoader, AppliesTheSidecarAtEachTimeWithoutRereadingTheGltf) {
  std::string dir = test::scratchDir("animation_scene_loader");
  std::string gltf = dir + "/move.gltf";
  std::ofstream(gltf) << translationDoc().dump();
  std::ofstream(dir + "/move.glint.json") << R"({
    "render": {"time": 0.5, "fps": 30},
    "lights": [{"type": "point", "position": [0, 5, 0],
                "intensity": {"keys": [[0, 10], [1, 30]]}}]})";
  SceneLoader loader(gltf);
  // The glTF file is gone: frames come from what the constructor loaded.
  fs::remove(gltf);
  SceneDescription first = loader.at();  // render.time from the sidecar
  EXPECT_EQ(first.render.time, 0.5);
  EXPECT_EQ(first.render.fps, 30);
  ASSERT_EQ(first.lights.size(), 1u);
  EXPECT_FLOAT_EQ(first.lights[0].intensity, 20);
  expectNear(cameraNamed(first, "Eye").worldFromCamera.point({}), {2, 0, 0});
  SceneDescription later = loader.at(1.5);
  EXPECT_EQ(later.render.time, 1.5);
  EXPECT_FLOAT_EQ(later.lights[0].intensity, 30);
  // The static placement of animated items follows the time.
  expectNear(cameraNamed(later, "Eye").worldFromCamera.point({}), {3, 2, 0});
  EXPECT_EQ(later.nodes.size(), first.nodes.size());  // nodes are not added per frame
  // loadScene with a time is the same thing.
  std::ofstream(gltf) << translationDoc().dump();
  EXPECT_FLOAT_EQ(loadScene(gltf, std::nullopt, 0.25).lights[0].intensity, 15);
  EXPECT_FLOAT_EQ(loadScene(gltf).lights[0].intensity, 20);
}

TEST(SceneLoader, JsonSceneLoadsItsGltfOnce) {
  std::string dir = test::scratchDir("animation_scene_loader_json");
  std::ofstream(dir + "/move.gltf") << translationDoc().dump();
  std::ofstream(dir + "/scene.json") << R"({
    "gltf": ["move.gltf"],
    "objects": [{"type": "sphere", "radius": {"keys": [[0, 1], [2, 3]]}}]})";
  SceneLoader loader(dir + "/scene.json");
  fs::remove(dir + "/move.gltf");
  SceneDescription s = loader.at(1.0);
  EXPECT_FLOAT_EQ(test::shapeAs<Sphere>(s.objects.at(0).shape).radius(), 2);
  EXPECT_EQ(s.cameras.size(), 2u);
  expectNear(cameraNamed(s, "Eye").worldFromCamera.point({}), {3, 0, 0});
}

}  // namespace
}  // namespace glint
