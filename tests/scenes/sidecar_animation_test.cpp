// glint tests — time in the sidecar: keyframed values evaluated at the scene time, render time
// and fps, the thin lens and shutter of cameras, and "animation" on objects, cameras and
// lights; every bad input with its pointer.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "scene_error_support.h"
#include "scenes/sidecar.h"

namespace glint {
namespace {

using test::errorFrom;

constexpr const char* kFile = "anim.glint.json";

SceneDescription applyAt(const std::string& text, std::optional<double> time,
                         SceneDescription scene = {}) {
  SceneJsonOptions options;
  options.time = time;
  applySceneJsonText(text, kFile, SceneJsonKind::Sidecar, &scene, options);
  return scene;
}

SceneError errorAt(const std::string& text, std::optional<double> time = 0.0) {
  return errorFrom([&] { applyAt(text, time); });
}

void expectNear(Vec3f a, Vec3f b, float tolerance = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tolerance) << "x";
  EXPECT_NEAR(a.y, b.y, tolerance) << "y";
  EXPECT_NEAR(a.z, b.z, tolerance) << "z";
}

const std::string kLight = R"({"lights": [{"type": "point", "position": [0, 0, 0], "intensity": )";

// ---------------------------------------------------------------------------------------------
// Keyframed values
// ---------------------------------------------------------------------------------------------

TEST(SidecarKeyframes, NumbersAreEvaluatedAtTheSceneTime) {
  std::string linear = kLight + R"({"keys": [[0, 10], [2, 30], [3, 0]]}}]})";
  EXPECT_FLOAT_EQ(applyAt(linear, 0.0).lights[0].intensity, 10);
  EXPECT_FLOAT_EQ(applyAt(linear, 1.0).lights[0].intensity, 20);
  EXPECT_FLOAT_EQ(applyAt(linear, 2.0).lights[0].intensity, 30);  // exactly on a key
  EXPECT_FLOAT_EQ(applyAt(linear, 2.5).lights[0].intensity, 15);
  EXPECT_FLOAT_EQ(applyAt(linear, -1.0).lights[0].intensity, 10);  // before the first key
  EXPECT_FLOAT_EQ(applyAt(linear, 9.0).lights[0].intensity, 0);    // after the last
  std::string step = kLight + R"({"keys": [[0, 10], [2, 30]], "interpolation": "step"}}]})";
  EXPECT_FLOAT_EQ(applyAt(step, 1.99).lights[0].intensity, 10);
  EXPECT_FLOAT_EQ(applyAt(step, 2.0).lights[0].intensity, 30);
  // Smooth through 0, 10, 0 at 0, 1, 2: 10 * 0.625 at t = 0.5 (see Track.SmoothIs...).
  std::string smooth =
      kLight + R"({"keys": [[0, 0], [1, 10], [2, 0]], "interpolation": "smooth"}}]})";
  EXPECT_FLOAT_EQ(applyAt(smooth, 0.5).lights[0].intensity, 6.25f);
  EXPECT_EQ(applyAt(smooth, 0.5).render.time, 0.5);
}

TEST(SidecarKeyframes, VectorsColoursAndMaterialParameters) {
  std::string text = R"({
    "cameras": [{"name": "C", "position": {"keys": [[0, [0, 0, 5]], [1, [2, 0, 5]]]},
                 "look_at": [0, 0, 0], "aperture": 0.1,
                 "focus_distance": {"keys": [[0, 2], [1, 4]]}}],
    "lights": [{"type": "directional", "direction": {"keys": [[0, [0, -1, 0]], [1, [1, -1, 0]]]},
                "color": {"keys": [[0, [1, 1, 1]], [1, [1, 0, 0]]]}}],
    "materials": [{"name": "M", "type": "phong", "diffuse": {"keys": [[0, [0, 0, 0]], [1, [0.5, 0.5, 0.5]]]},
                   "shininess": {"keys": [[0, 10], [1, 50]]}}]})";
  SceneDescription s = applyAt(text, 0.5);
  expectNear(s.cameras[0].worldFromCamera.point({}), {1, 0, 5});
  EXPECT_FLOAT_EQ(s.cameras[0].focusDistance, 3);
  expectNear(s.lights[0].color, {1, 0.5f, 0.5f});
  expectNear(normalize(s.lights[0].worldFromLight.vector({0, 0, -1})),
             normalize(Vec3f{0.5f, -1, 0}));
  expectNear(s.materials[0].baseColor, {0.25f, 0.25f, 0.25f});
  EXPECT_FLOAT_EQ(s.materials[0].shininess, 30);
}

TEST(SidecarKeyframes, RenderTimeComesFromTheFileUnlessGiven) {
  std::string text = R"({"render": {"time": 2, "fps": 25}, "lights": [{"type": "point",
    "position": [0, 0, 0], "intensity": {"keys": [[0, 0], [4, 40]]}}]})";
  SceneDescription fromFile = applyAt(text, std::nullopt);
  EXPECT_EQ(fromFile.render.time, 2);
  EXPECT_EQ(fromFile.render.fps, 25);
  EXPECT_FLOAT_EQ(fromFile.lights[0].intensity, 20);
  SceneDescription given = applyAt(text, 3.0);
  EXPECT_EQ(given.render.time, 3);
  EXPECT_FLOAT_EQ(given.lights[0].intensity, 30);
}

TEST(SidecarKeyframes, BadKeyframesNameTheirPointer) {
  auto light = [](const std::string& intensity) { return kLight + intensity + "}]}"; };
  EXPECT_SCENE_ERROR(errorAt(light(R"({"keys": [[0, 1], [2, 3], [1, 4]]})")), kFile,
                     "/lights/0/intensity/keys/2/0", "must increase strictly");
  EXPECT_SCENE_ERROR(errorAt(light(R"({"keys": [[1, 1], [1, 2]]})")), kFile,
                     "/lights/0/intensity/keys/1/0", "must increase strictly");
  EXPECT_SCENE_ERROR(errorAt(light(R"({"keys": [[0, "bright"]]})")), kFile,
                     "/lights/0/intensity/keys/0/1", "expected number, got string");
  EXPECT_SCENE_ERROR(errorAt(light(R"({"keys": [[0, 1]], "interpolation": "cubic"})")), kFile,
                     "/lights/0/intensity/interpolation", "'cubic' is not one of");
  EXPECT_SCENE_ERROR(errorAt(light(R"({"keys": [[0, 1]], "interp": "step"})")), kFile,
                     "/lights/0/intensity/interp", "unknown key 'interp'");
  EXPECT_SCENE_ERROR(errorAt(light(R"({"keys": []})")), kFile, "/lights/0/intensity/keys",
                     "at least one key");
  EXPECT_SCENE_ERROR(errorAt(light(R"({"keys": [[0, 1, 2]]})")), kFile,
                     "/lights/0/intensity/keys/0", "[time, value]");
  // Every key obeys the value's range, whatever the time.
  EXPECT_SCENE_ERROR(errorAt(light(R"({"keys": [[0, 1], [5, -1]]})")), kFile,
                     "/lights/0/intensity/keys/1/1", "must be >= 0");
  // A smooth curve may overshoot between keys: checked at the time evaluated.
  std::string overshoot =
      R"({"keys": [[0, 0], [1, 0], [2, 10], [3, 10]], "interpolation": "smooth"})";
  EXPECT_SCENE_ERROR(errorAt(light(overshoot), 0.5), kFile, "/lights/0/intensity",
                     "smooth curve overshoots");
  // Keys on something that is not a number or vector.
  EXPECT_SCENE_ERROR(
      errorAt(
          R"({"lights": [{"type": "point", "position": [0, 0, 0], "name": {"keys": [[0, 1]]}}]})"),
      kFile, "/lights/0/name", "only allowed on numbers and vectors");
  EXPECT_SCENE_ERROR(errorAt(R"({"render": {"spp": {"keys": [[0, 1]]}}})"), kFile, "/render/spp",
                     "only allowed on numbers and vectors");
  EXPECT_SCENE_ERROR(errorAt(R"({"render": {"time": {"keys": [[0, 1]]}}})", std::nullopt), kFile,
                     "/render/time", "cannot be keyframed");
  EXPECT_SCENE_ERROR(errorAt(R"({"objects": [{"type": "sphere", "radius": 1, "transform":
      [{"translate": {"keys": [[0, [0, 0, 0]]]}}]}]})"),
                     kFile, "/objects/0/transform/0/translate", "");
  EXPECT_SCENE_ERROR(errorAt(R"({"render": {"fps": 0}})"), kFile, "/render/fps", "must be > 0");
}

// ---------------------------------------------------------------------------------------------
// Camera lens and shutter
// ---------------------------------------------------------------------------------------------

TEST(SidecarCamera, ThinLensAndShutter) {
  SceneDescription s = applyAt(R"({"cameras": [
    {"name": "A", "position": [0, 0, 10], "look_at": [0, 0, 4], "aperture": 0.05,
     "blades": 6, "blade_rotation": 30, "shutter": [-0.01, 0.01]},
    {"name": "B", "transform": [], "aperture": 0.1, "focus_distance": 3},
    {"name": "C", "position": [0, 0, 1], "look_at": [0, 0, 0]}]})",
                               0.0);
  const CameraDesc& a = s.cameras[0];
  EXPECT_FLOAT_EQ(a.apertureRadius, 0.05f);
  EXPECT_FLOAT_EQ(a.focusDistance, 6);  // the look_at distance
  EXPECT_EQ(a.apertureBlades, 6);
  EXPECT_FLOAT_EQ(a.apertureRotation, kPi / 6);
  EXPECT_FLOAT_EQ(a.shutterOpen, -0.01f);
  EXPECT_FLOAT_EQ(a.shutterClose, 0.01f);
  EXPECT_FLOAT_EQ(s.cameras[1].focusDistance, 3);
  EXPECT_EQ(s.cameras[2].apertureRadius, 0);  // a pinhole by default
  EXPECT_EQ(s.cameras[2].shutterOpen, s.cameras[2].shutterClose);
}

TEST(SidecarCamera, LensOnAnExistingCameraKeepsItsPlacementAndAnimation) {
  SceneDescription base;
  CameraDesc gltf;
  gltf.name = "FromGltf";
  gltf.yfov = 0.5f;
  gltf.worldFromCamera = Transform::translate({1, 2, 3});
  gltf.transformNode = 0;
  base.cameras.push_back(gltf);
  NodeDesc node;
  node.translation = {1, 2, 3};
  base.nodes.push_back(node);
  SceneDescription s = applyAt(
      R"({"cameras": [{"name": "FromGltf", "aperture": 0.2, "focus_distance": 7}]})", 0.0, base);
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_FLOAT_EQ(s.cameras[0].apertureRadius, 0.2f);
  EXPECT_FLOAT_EQ(s.cameras[0].focusDistance, 7);
  EXPECT_FLOAT_EQ(s.cameras[0].yfov, 0.5f);
  EXPECT_EQ(s.cameras[0].transformNode, 0);
  expectNear(s.cameras[0].worldFromCamera.point({}), {1, 2, 3});
}

TEST(SidecarCamera, BadLensValuesNameTheirPointer) {
  auto cam = [](const std::string& extra) {
    return R"({"cameras": [{"position": [0, 0, 1], "look_at": [0, 0, 0], )" + extra + "}]}";
  };
  EXPECT_SCENE_ERROR(errorAt(cam(R"("aperture": -1)")), kFile, "/cameras/0/aperture",
                     "must be >= 0");
  EXPECT_SCENE_ERROR(errorAt(cam(R"("focus_distance": 0)")), kFile, "/cameras/0/focus_distance",
                     "must be > 0");
  EXPECT_SCENE_ERROR(errorAt(cam(R"("blades": 2)")), kFile, "/cameras/0/blades", ">= 3");
  EXPECT_SCENE_ERROR(errorAt(cam(R"("shutter": [0.5, 0.1])")), kFile, "/cameras/0/shutter",
                     "open <= close");
  EXPECT_SCENE_ERROR(errorAt(R"({"cameras": [{"transform": [], "aperture": 0.1}]})"), kFile,
                     "/cameras/0/aperture", "needs 'focus_distance'");
}

// render.shutter replaces the camera's; a closed-before-open one names its pointer.
TEST(SidecarRender, ShutterIsReadAndChecked) {
  SceneDescription s = applyAt(R"({"render": {"shutter": [-0.01, 0.02]}})", 0.0);
  ASSERT_TRUE(s.render.shutter.has_value());
  EXPECT_NEAR((*s.render.shutter)[0], -0.01, 1e-7);
  EXPECT_NEAR((*s.render.shutter)[1], 0.02, 1e-7);
  EXPECT_FALSE(applyAt("{}", 0.0).render.shutter.has_value());
  EXPECT_SCENE_ERROR(errorAt(R"({"render": {"shutter": [0.5, 0.1]}})"), kFile, "/render/shutter",
                     "open <= close");
}

// ---------------------------------------------------------------------------------------------
// "animation": objects, cameras, lights
// ---------------------------------------------------------------------------------------------

TEST(SidecarAnimation, SphereMovesFromItsStartToItsEndPosition) {
  std::string text = R"({"objects": [{"name": "ball", "type": "sphere", "radius": 1,
    "transform": [{"scale": 2}],
    "animation": {"translation": {"keys": [[0, [0, 0, 0]], [1, [4, 0, 0]]]}}}]})";
  SceneDescription s = applyAt(text, 0.25);
  ASSERT_EQ(s.objects.size(), 1u);
  const ObjectDesc& ball = s.objects[0];
  ASSERT_GE(ball.transformNode, 0);
  EXPECT_EQ(s.nodes[size_t(ball.transformNode)].name, "ball");
  // world(t) = T(t) · transform: the scale applies first, then the move.
  auto at = [&](double t) {
    return worldFromNode(s.nodes, ball.transformNode, t) * ball.nodeFromObject;
  };
  expectNear(at(0).point({1, 0, 0}), {2, 0, 0});
  expectNear(at(0.5).point({1, 0, 0}), {4, 0, 0});
  expectNear(at(1).point({1, 0, 0}), {6, 0, 0});
  expectNear(ball.worldFromObject.point({1, 0, 0}), {3, 0, 0});  // the scene time, 0.25
  auto range = animationRange(s.nodes);
  EXPECT_EQ(range.first, 0);
  EXPECT_EQ(range.second, 1);
}

TEST(SidecarAnimation, RotationByAxisAndDegreesOrQuaternionsAndScale) {
  std::string text = R"({"objects": [
    {"type": "box", "min": [-1, -1, -1], "max": [1, 1, 1],
     "animation": {"rotation": {"axis": [0, 1, 0], "keys": [[0, 0], [1, 720]]},
                   "scale": {"keys": [[0, 1], [1, [1, 3, 1]]]}}},
    {"type": "box", "min": [-1, -1, -1], "max": [1, 1, 1],
     "animation": {"rotation": {"keys": [[0, [0, 0, 0, 1]], [1, [0, 0, 0.70710678, 0.70710678]]],
                                "interpolation": "step"}}}]})";
  SceneDescription s = applyAt(text, 0.0);
  int spin = s.objects[0].transformNode, flip = s.objects[1].transformNode;
  // 720 degrees over one second: at 0.375 s it has turned 270 degrees (x -> z), which slerp
  // between the end keys could never give.
  expectNear(worldFromNode(s.nodes, spin, 0.375).vector({1, 0, 0}), {0, 0, 1}, 1e-5f);
  expectNear(worldFromNode(s.nodes, spin, 0.5).vector({0, 1, 0}), {0, 2, 0}, 1e-5f);
  expectNear(worldFromNode(s.nodes, flip, 0.9).vector({1, 0, 0}), {1, 0, 0});
  expectNear(worldFromNode(s.nodes, flip, 1.0).vector({1, 0, 0}), {0, 1, 0}, 1e-5f);
}

TEST(SidecarAnimation, CamerasAndLightsMoveTheSameWay) {
  std::string text = R"({
    "cameras": [{"name": "Dolly", "position": [0, 0, 5], "look_at": [0, 0, 0],
                 "animation": {"translation": {"keys": [[0, [0, 0, 0]], [2, [0, 0, -2]]]}}}],
    "lights": [{"type": "point", "position": [1, 0, 0],
                "animation": {"rotation": {"axis": [0, 0, 1], "keys": [[0, 0], [1, 90]]}}}]})";
  SceneDescription s = applyAt(text, 1.0);
  const CameraDesc& c = s.cameras[0];
  ASSERT_GE(c.transformNode, 0);
  expectNear(c.worldFromCamera.point({}), {0, 0, 4});
  expectNear((worldFromNode(s.nodes, c.transformNode, 2.0) * c.nodeFromCamera).point({}),
             {0, 0, 3});
  const LightDesc& l = s.lights[0];
  ASSERT_GE(l.transformNode, 0);
  expectNear(l.worldFromLight.point({}), {0, 1, 0}, 1e-5f);
}

TEST(SidecarAnimation, BadAnimationsNameTheirPointer) {
  auto obj = [](const std::string& animation) {
    return R"({"objects": [{"type": "sphere", "radius": 1, "animation": )" + animation + "}]}";
  };
  EXPECT_SCENE_ERROR(errorAt(obj("{}")), kFile, "/objects/0/animation", "needs 'translation'");
  EXPECT_SCENE_ERROR(errorAt(obj(R"({"move": {"keys": [[0, [0, 0, 0]]]}})")), kFile,
                     "/objects/0/animation/move", "unknown key 'move'");
  EXPECT_SCENE_ERROR(errorAt(obj(R"({"translation": [1, 2, 3]})")), kFile,
                     "/objects/0/animation/translation", "expected object");
  EXPECT_SCENE_ERROR(errorAt(obj(R"({"translation": {"keys": [[1, [0, 0, 0]], [0, [1, 1, 1]]]}})")),
                     kFile, "/objects/0/animation/translation/keys/1/0", "increase strictly");
  EXPECT_SCENE_ERROR(errorAt(obj(R"({"translation": {"keys": [[0, 5]]}})")), kFile,
                     "/objects/0/animation/translation/keys/0/1", "expected an array of 3");
  EXPECT_SCENE_ERROR(errorAt(obj(R"({"rotation": {"axis": [0, 0, 0], "keys": [[0, 5]]}})")), kFile,
                     "/objects/0/animation/rotation/axis", "must not be zero");
  EXPECT_SCENE_ERROR(errorAt(obj(R"({"rotation": {"keys": [[0, [0, 0, 0, 0]]]}})")), kFile,
                     "/objects/0/animation/rotation/keys/0/1", "must not be zero");
  EXPECT_SCENE_ERROR(errorAt(obj(R"({"scale": {"keys": [[0, [1, 0, 1]]]}})")), kFile,
                     "/objects/0/animation/scale/keys/0/1", "must not be zero");
  EXPECT_SCENE_ERROR(errorAt(obj(R"({"scale": {"keys": [[0, 1]], "interpolation": "bouncy"}})")),
                     kFile, "/objects/0/animation/scale/interpolation", "'bouncy' is not one of");
}

}  // namespace
}  // namespace glint
