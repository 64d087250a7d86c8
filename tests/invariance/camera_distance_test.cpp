// The invariance net's camera distance part (issue 49, item 4): a thin feature looks the same
// from 1, 300 and 10,000 units away when the field of view narrows to keep the framing.
//
// Four features 4e-5 thick: a closed CSG shell (a box minus the same box 4e-5 smaller on every
// side) with a light inside, a plain box slab with a lit box hidden behind it, the same slab as
// a triangle mesh (a glTF file), and a tinted glass pane in front of a white unlit plane. Each
// stands face-on on the camera's axis, its front face in the plane z = 0 of its own frame, and the
// camera looks down -z from `distance` with tan(yfov / 2) = kHalfFrame / distance. From anywhere on
// the axis a camera sees only that front face (and, through the pane, the plane behind it, which is
// the same everywhere), and a face-on view of a plane is the same similarity of it at every
// distance: the images must agree pixel for pixel (the net's comparison: 0.03 squeezed plus 3
// sigma, edges within 1 pixel, the mean within 0.5%). A lost wall or a leak shows the lit inside,
// the lit box behind the slab, or the white plane untinted. Each setup is seen as written (rays
// nearly along the coordinate axes) and turned as a whole about a random axis (no ray along an
// axis).
//
// Item 2 of the issue was this failure: the shell's near wall lost from 300 units (the inside
// showed with radiance 5), fixed by CsgShape::reoriginate (0e753a4). From 1e4 units the plain
// slab, the mesh slab and the pane failed too (the slab's front face shadowed, a third of the
// mean radiance gone; the pane's inside skipped, the mean 60% too bright): t's rounding at 1e4
// is some 25 times the wall. Fixed by PlacedShape::toObject moving far origins to the shape's
// box, and for meshes by refineFarHit (geometry/accel/accelerator.h). The negative controls at
// the end show that the comparison sees a removed wall, a real gap and a missing pane.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "invariance.h"
#include "test_support.h"

namespace glint {
namespace {

using invariance::Json;
using invariance::Tolerance;

constexpr double kHalfFrame = 0.36;  // half the frame's height at the front faces
constexpr const char* kWall = "4e-05";

// The render block, the camera placeholder and the lights every scene shares: Whitted, 96 x 96,
// 4 samples; a light in front of the features, to the upper right.
Json baseScene() {
  return Json::parse(R"({
    "render": {"width": 96, "height": 96, "spp": 4, "seed": 1, "camera": "c",
               "integrator": {"type": "whitted"}, "background": [0.3, 0.35, 0.4]},
    "cameras": [{"name": "c", "position": [0, 0, 1], "look_at": [0, 0, 0], "yfov_degrees": 40}],
    "lights": [{"name": "front", "type": "point", "position": [0.5, 0.7, 1.2], "intensity": 2}],
    "materials": [{"name": "white", "type": "lambert", "diffuse": [0.8, 0.8, 0.8]},
                  {"name": "tinted", "type": "glass", "ior": 1.5, "color": [0.2, 0.9, 0.3]},
                  {"name": "backdrop", "type": "unlit", "color": [1, 1, 1]}],
    "objects": []})");
}

Json box(const std::string& lo, const std::string& hi, const char* material) {
  return Json::parse(R"({"type": "box", "min": )" + lo + R"(, "max": )" + hi +
                     R"(, "material": ")" + material + "\"}");
}

// The shell: [-0.25, 0.25]^2 x [-0.5, 0] minus the same box 4e-5 smaller on every side, with a
// light at its centre. `frontWall` false: the inner box reaches through the front face (the
// control's lost wall).
Json shellScene(bool frontWall = true) {
  Json s = baseScene();
  const std::string w = kWall;
  const std::string innerFront = frontWall ? "-" + w : "0.01";
  Json tree = Json::parse(R"({"op": "difference", "children": []})");
  tree["children"].push_back(
      Json::parse(R"({"type": "box", "min": [-0.25, -0.25, -0.5], "max": [0.25, 0.25, 0]})"));
  tree["children"].push_back(Json::parse(
      R"({"type": "box", "min": [-0.24996, -0.24996, -0.49996], "max": [0.24996, 0.24996, )" +
      innerFront + "]}"));
  s["objects"].push_back(
      {{"name", "shell"}, {"type", "csg"}, {"material", "white"}, {"tree", tree}});
  s["lights"].push_back(Json::parse(
      R"({"name": "inside", "type": "point", "position": [0, 0, -0.25], "intensity": 2})"));
  return s;
}

// The slab: a plain box [-0.25, 0.25]^2 x [-4e-5, 0], a box behind it (hidden from every
// distance: its front face, 0.1 behind, is smaller than the slab) lit by a light between the two.
// `gap` > 0: the slab in two halves that far apart (the control's real gap).
Json slabScene(double gap = 0) {
  Json s = baseScene();
  const std::string w = kWall;
  if (gap > 0) {
    const std::string h = std::to_string(gap / 2);
    s["objects"].push_back(box("[-0.25, -0.25, -" + w + "]", "[-" + h + ", 0.25, 0]", "white"));
    s["objects"].push_back(box("[" + h + ", -0.25, -" + w + "]", "[0.25, 0.25, 0]", "white"));
  } else {
    s["objects"].push_back(box("[-0.25, -0.25, -" + w + "]", "[0.25, 0.25, 0]", "white"));
  }
  s["objects"].push_back(box("[-0.15, -0.15, -0.4]", "[0.15, 0.15, -0.1]", "white"));
  s["lights"].push_back(Json::parse(
      R"({"name": "behind", "type": "point", "position": [0, 0, -0.05], "intensity": 2})"));
  return s;
}

// The mesh slab: slabScene's slab as a triangle mesh in a glTF file (12 triangles, a white
// diffuse double-sided material: single-sided, the back face is culled and cannot come
// first), written once into the test's scratch directory.
std::string meshSlabFile() {
  const std::string dir = test::scratchDir("invariance_camera_distance_mesh");
  const float lo[3] = {-0.25f, -0.25f, -4e-5f}, hi[3] = {0.25f, 0.25f, 0};
  std::vector<float> positions;
  for (int i = 0; i < 8; ++i)
    for (int a = 0; a < 3; ++a) positions.push_back((i >> a & 1) ? hi[a] : lo[a]);
  // Two triangles per face, wound outward: -x, +x, -y, +y, -z, +z.
  const uint16_t indices[36] = {0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5, 0, 1, 5, 0, 5, 4,
                                2, 6, 7, 2, 7, 3, 0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6};
  {
    std::ofstream bin(dir + "/slab.bin", std::ios::binary);
    bin.write(reinterpret_cast<const char*>(positions.data()),
              std::streamsize(positions.size() * 4));
    bin.write(reinterpret_cast<const char*>(indices), sizeof indices);
  }
  std::ofstream(dir + "/slab.gltf") << R"({
    "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
    "materials": [{"doubleSided": true,
                   "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0}}],
    "buffers": [{"uri": "slab.bin", "byteLength": 168}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 96},
                    {"buffer": 0, "byteOffset": 96, "byteLength": 72}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3",
                   "min": [-0.25, -0.25, -4e-05], "max": [0.25, 0.25, 0]},
                  {"bufferView": 1, "componentType": 5123, "count": 36, "type": "SCALAR"}]})";
  return std::filesystem::absolute(dir + "/slab.gltf").string();
}

// slabScene with the mesh slab instead of the box (no gap).
Json meshSlabScene() {
  Json s = slabScene();
  s["objects"].erase(0);
  s["gltf"] = Json::array({meshSlabFile()});
  return s;
}

// The pane: tinted glass [-0.25, 0.25]^2 x [-4e-5, 0] before a white unlit plane at z = -0.3
// (the same radiance from every point of it, so what shows through the pane does not depend on
// the distance). `pane` false: the control's missing pane.
Json paneScene(bool pane = true) {
  Json s = baseScene();
  if (pane)
    s["objects"].push_back(
        box("[-0.25, -0.25, -" + std::string(kWall) + "]", "[0.25, 0.25, 0]", "tinted"));
  s["objects"].push_back(Json::parse(
      R"({"type": "plane", "point": [0, 0, -0.3], "normal": [0, 0, 1], "material": "backdrop"})"));
  return s;
}

// `scene` seen from `distance` units on its axis with the framing kept, as it is (`turned`
// false: the camera's rays then run nearly along the coordinate axes, which is how a thin mesh
// wall was lost) or turned as a whole about a random axis (fixed seed).
Json fromDistance(Json scene, double distance, bool turned = true) {
  Json& cam = scene["cameras"][0];
  cam["position"] = Json::array({0, 0, distance});
  cam["yfov_degrees"] = 2 * std::atan(kHalfFrame / distance) * 180 / std::numbers::pi;
  if (!turned) return scene;
  const std::string file = test::scratchDir("invariance_camera_distance_rewrite") + "/scene.json";
  std::vector<std::string> notes;
  return invariance::transformScene(scene, invariance::randomRotation(5),
                                    invariance::Placement::Root,
                                    invariance::sceneFacts(scene, file), &notes);
}

Tolerance tolerance() {
  Tolerance t;
  t.pixel = 0.03;
  t.sigmas = 3;
  t.radius = 1;
  t.mean = 0.005;
  return t;
}

struct DistanceCase {
  const char* name;
  Json (*scene)();
};

Json shell() { return shellScene(); }
Json slab() { return slabScene(); }
Json meshSlab() { return meshSlabScene(); }
Json pane() { return paneScene(); }

void PrintTo(const DistanceCase& c, std::ostream* os) { *os << c.name; }

class InvarianceCameraDistance : public testing::TestWithParam<DistanceCase> {};

TEST_P(InvarianceCameraDistance, AThinFeatureLooksTheSameFromNearAndFar) {
  const DistanceCase& c = GetParam();
  const std::string dir = test::scratchDir(std::string("invariance_camera_distance_") + c.name);
  const std::string file = dir + "/scene.json";
  for (bool turned : {false, true}) {
    const Json nearScene = fromDistance(c.scene(), 1, turned);
    const Film nearFilm = invariance::renderScene(nearScene, file);
    const std::string how = turned ? "turned" : "axis-aligned";
    for (double distance : {300.0, 1e4}) {
      const Json farScene = fromDistance(c.scene(), distance, turned);
      const Film farFilm = invariance::renderScene(farScene, file);
      const invariance::Comparison cmp = invariance::compareFilms(nearFilm, farFilm, tolerance());
      std::printf("[ camera distance ] %s (%s) from %g: %s\n", c.name, how.c_str(), distance,
                  cmp.summary().c_str());
      if (!cmp.passes(tolerance())) {
        const std::string tag = how + "_from_" + std::to_string(int(distance));
        invariance::writeFilm(dir + "/" + how + "_from_1", nearFilm);
        invariance::writeFilm(dir + "/" + tag, farFilm);
        invariance::writeMask(dir + "/" + tag + ".bad.png", nearFilm, cmp.badMask);
        std::ofstream(dir + "/" + tag + ".json") << farScene.dump(1);
        ADD_FAILURE() << c.name << " (" << how << ") from " << distance
                      << " units: " << cmp.summary() << "\n  first bad pixels:" << cmp.where
                      << "\n  images: " << dir;
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    ThinFeatures, InvarianceCameraDistance,
    testing::Values(DistanceCase{"csg_shell", shell}, DistanceCase{"box_slab", slab},
                    DistanceCase{"mesh_slab", meshSlab}, DistanceCase{"glass_pane", pane}),
    [](const testing::TestParamInfo<DistanceCase>& p) { return std::string(p.param.name); });

// The comparison sees what the check is for: the near view of each feature against a far view
// of the feature broken (the shell without its front wall, the slab with a real gap of 0.03 in
// the middle, the pane gone) fails.
TEST(InvarianceCameraDistanceControls, ALostWallARealGapAndAMissingPaneFail) {
  const std::string file = test::scratchDir("invariance_camera_distance_controls") + "/scene.json";
  struct Control {
    const char* name;
    Json intact, broken;
  };
  const Control controls[] = {{"shell without its front wall", shellScene(true), shellScene(false)},
                              {"slab with a 0.03 gap", slabScene(), slabScene(0.03)},
                              {"pane removed", paneScene(true), paneScene(false)}};
  for (const Control& c : controls) {
    const invariance::Comparison cmp = invariance::compareFilms(
        invariance::renderScene(fromDistance(c.intact, 1), file),
        invariance::renderScene(fromDistance(c.broken, 300), file), tolerance());
    std::printf("[ control ] %s, from 300: %s\n", c.name, cmp.summary().c_str());
    EXPECT_FALSE(cmp.pixelsPass()) << c.name;
    EXPECT_GT(cmp.bad, 20) << c.name;
  }
}

}  // namespace
}  // namespace glint
