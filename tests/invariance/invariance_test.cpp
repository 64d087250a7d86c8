// The invariance net (issue 49, item 4): translation, scale, rotation and mirroring.
//
// Every reference scene of tests/reference_images/references.json and a small version of each
// showcase scene is rendered as it is and again with the whole scene moved by a similarity map,
// with the same seed, spp and size; the two images must agree (compareFilms in invariance.h: no
// pixel outside the range the other image has within `radius` pixels, by more than a
// tolerance, and the mean luminance within a bound). The maps:
//   translate-edit/1eK  every position-like key moved by (10^K, 10^K, -10^K), K = 3..6
//   translate-root/1eK  the same translation appended to every object's transform
//   scale/S             x S (1e-4, 1e-2, 1e2, 1e4), appended to every transform
//   rotate/N            a rotation about a random axis (seed N), appended to every transform
//   rotate-y            a rotation about +Y (scenes lit by an environment map or the studio,
//                       which can only turn about +Y)
//   mirror              a reflection in a plane through the origin (det -1)
// Cameras and lights are moved by their own keys (a camera placed by position/look_at becomes
// a matrix under the mirror); what else has to change so the image can stay the same is
// invariance.cpp's transformScene, which lists each adjustment it made (intensities x s^2,
// densities / s, world-space texture offsets, ...).
//
// The scenes that cannot be invariant under a map by design are in kExclusions below with the
// reason; the ones adapted so that the part that can be invariant is checked are in
// adaptForTurning and the scene list. Cases that fail today because of an open renderer bug
// are in kKnownOpen: printed as KNOWN-OPEN with their numbers, left out of the pass assertion
// (empty it as the bugs are fixed). Each comparison check is shown to fail a real change in
// the InvarianceControls tests at the end.
//
// GLINT_INVARIANCE_SWEEP=1 runs the longer sweep: images twice as wide and high, twice the
// samples, 8 rotations, offsets 1e2 and 3e4, 3e5 between the others, and every map of the
// Venus Garden. Images of a failing case stay in
// test_output/invariance_SCENE/ (original, transformed, mask of the bad pixels in red, and both
// JSON scenes).
#include "invariance.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <string>

#include "test_support.h"

namespace glint {
namespace {

namespace fs = std::filesystem;
using invariance::Json;
using invariance::Placement;
using invariance::Similarity;
using invariance::Tolerance;
using invariance::V3;

bool sweep() {
  const char* v = std::getenv("GLINT_INVARIANCE_SWEEP");
  return v && *v && std::string(v) != "0";
}

using test::sourceDir;
std::string imagesDir() { return sourceDir() + "/tests/reference_images"; }

Json readJson(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  return Json::parse(in);
}

// ---------------------------------------------------------------------------------------------
// The scenes
// ---------------------------------------------------------------------------------------------

struct SceneCase {
  std::string name;
  Json scene;        // a glint .json scene, already small
  std::string file;  // where it is read from: relative paths resolve against it
  std::map<std::string, Json> gltfVolumes;  // glTF materials with KHR_materials_volume
  // The maps this scene gets in the quick net (empty: all); the sweep runs all of them.
  std::set<std::string> quick;
  // Where the case's .vdb files are written (by glint_make_vdb_scenes) before it renders;
  // empty: none.
  std::string vdbFolder;
};

void PrintTo(const SceneCase& c, std::ostream* os) { *os << c.name; }

// Small size and spp for the net (and a larger one for the sweep).
void makeSmall(Json& scene, int width, int height, int spp) {
  Json& r = scene["render"];
  const double k = sweep() ? 2 : 1;
  r["width"] = int(width * k);
  r["height"] = int(height * k);
  r["spp"] = sweep() ? spp * 2 : spp;
  r.erase("tonemap");  // display only; the net compares scene-linear films
  r.erase("threads");
}

std::map<std::string, Json> volumesOf(const std::string& gltf) {
  std::map<std::string, Json> v;
  // A missing asset fails its test when the scene is loaded (with glint's message naming
  // GLINT_ASSETS), not the listing of the tests.
  if (fs::path(gltf).extension() != ".gltf" || !fs::exists(gltf)) return v;
  const Json g = readJson(gltf);
  if (g.contains("materials"))
    for (const Json& m : g["materials"])
      if (m.contains("extensions") && m["extensions"].contains("KHR_materials_volume"))
        v[m.value("name", "")] = m["extensions"]["KHR_materials_volume"];
  return v;
}

// A glTF file with a sidecar (or none) as a glint .json scene that lists it.
SceneCase gltfCase(const std::string& name, const std::string& gltf, const std::string& sidecar,
                   const std::string& fileForPaths) {
  SceneCase c;
  c.name = name;
  c.scene = sidecar.empty() ? Json::object() : readJson(sidecar);
  c.scene["gltf"] = Json::array({gltf});
  c.file = fileForPaths;
  c.gltfVolumes = volumesOf(gltf);
  return c;
}

std::vector<SceneCase> allScenes() {
  std::vector<SceneCase> cases;
  // Every reference scene, at its manifest size (48-96 px) with a quarter of its spp (at
  // least 4): the comparison needs the same samples in both images, not converged ones.
  const Json manifest = readJson(imagesDir() + "/references.json");
  for (const Json& m : manifest.at("cases")) {
    SceneCase c;
    const std::string name = m.at("name");
    if (m.contains("asset")) {
      c = gltfCase(name, test::assetsDir() + "/" + m["asset"].get<std::string>(),
                   imagesDir() + "/" + m["sidecar"].get<std::string>(),
                   imagesDir() + "/" + m["sidecar"].get<std::string>());
    } else {
      c.name = name;
      c.file = (fs::path(imagesDir()) / m["scene"].get<std::string>()).lexically_normal().string();
      c.scene = readJson(c.file);
    }
    if (m.contains("camera")) c.scene["render"]["camera"] = m["camera"];
    makeSmall(c.scene, m["size"][0], m["size"][1], std::max(4, m["spp"].get<int>() / 4));
    cases.push_back(c);
  }
  // The showcase scenes, small: Snowy and the Venus Garden at their hero frames, the demo, the
  // CSG reference scene, and the two glTF scenes lit by the studio (first_image,
  // material_extensions), given a camera here since the automatic camera frames the asset from
  // its front whichever way it is turned.
  const std::string scenes = sourceDir() + "/scenes";
  {
    SceneCase c{
        "snowy", readJson(scenes + "/snowy/snowy.json"), scenes + "/snowy/snowy.json", {}, {}};
    makeSmall(c.scene, 96, 72, 2);
    // Instant radiosity's 48 light paths leave ~55 VPLs, each bright enough that one landing
    // in a crease makes a splotch of radiance 3 or more, and the seed (or any change of
    // coordinates) decides where: 256 paths make each VPL about 5 times fainter, so that the
    // net sees the geometry rather than where the splotches fell.
    c.scene["render"]["integrator"]["vpl_paths"] = 256;
    cases.push_back(c);
  }
  {
    SceneCase c{"venus_garden",
                readJson(scenes + "/venus_garden/venus_garden.json"),
                scenes + "/venus_garden/venus_garden.json",
                {},
                {}};
    makeSmall(c.scene, 96, 72, 2);
    // Its two 200,000-triangle dragons make each render ~2 s: the quick net takes a few maps.
    c.quick = {"translate-edit/1e4", "translate-root/1e5", "scale/1e-4", "scale/1e4"};
    cases.push_back(c);
  }
  {
    SceneCase c = gltfCase("demo", scenes + "/demo/demo.gltf", scenes + "/demo/demo.glint.json",
                           scenes + "/demo/demo.glint.json");
    makeSmall(c.scene, 128, 72, 4);
    cases.push_back(c);
  }
  {
    SceneCase c{"csg_scene",
                readJson(scenes + "/csg/csg_scene.json"),
                scenes + "/csg/csg_scene.json",
                {},
                {}};
    makeSmall(c.scene, 128, 96, 4);
    cases.push_back(c);
  }
  // The VDB cloud and fire of scenes/volumes/ (their files written by the tool when the case
  // runs, into a folder of their own: each case's scratch folder is emptied as it starts).
  for (const char* name : {"cloud", "fire"}) {
    const fs::path folder =
        fs::path(test::testOutputDir()) / (std::string("invariance_vdb_files_") + name);
    SceneCase c{std::string("vdb_") + name,
                readJson(scenes + "/volumes/" + name + ".json"),
                (folder / (std::string(name) + ".json")).string(),
                {},
                {},
                folder.string()};
    makeSmall(c.scene, 128, 72, 4);
    cases.push_back(c);
  }
  for (const char* name : {"first_image", "material_extensions"}) {
    SceneCase c = gltfCase(name, scenes + "/" + name + "/" + name + ".gltf", "",
                           scenes + "/" + name + "/" + name + ".json");
    c.scene["cameras"] = Json::parse(
        R"([{"name": "front", "position": [1.2, 3.2, 12.5], "look_at": [0, 0.8, 0], "yfov_degrees": 38}])");
    c.scene["environment"] = Json::parse(R"({"preset": "studio"})");  // the default, explicit
    c.scene["render"] = Json::object();
    makeSmall(c.scene, 128, 72, 8);
    cases.push_back(c);
  }
  return cases;
}

const std::vector<SceneCase>& scenes() {
  static const std::vector<SceneCase> s = allScenes();
  return s;
}

// ---------------------------------------------------------------------------------------------
// The maps
// ---------------------------------------------------------------------------------------------

struct Family {
  std::string name;
  Similarity map;
  Placement mode = Placement::Root;
  Tolerance tolerance;
  double offset = 0;  // translations: the offset along each axis
};

// 1000 -> "1e3", 30000 -> "3e4", 0.01 -> "1e-2".
std::string power10(double v) {
  const int e = int(std::floor(std::log10(v) + 1e-9));
  char text[16];
  std::snprintf(text, sizeof text, "%de%d", int(std::lround(v / std::pow(10.0, e))), e);
  return text;
}

// The tolerances and why. Calibrated on the passing cases (docs/testing.md has the figures);
// each is shown to fail real changes by the InvarianceControls tests below.
//  * pixel 0.03 per channel in the squeezed domain v = y / (1 + y), y = radiance / (2 mean
//    luminance): a pixel of the image's mean brightness sits at v = 1/3, so 0.03 is about 15%
//    of its radiance there (more in the highlights, which the squeeze compresses). The
//    passing cases come within 0.011 of it at most (beyond their edges and noise), the
//    controls exceed it by 0.18 (a lost shadow) to 0.48 (a lost wall).
//  * sigmas 3: where a path diverges (a Russian roulette or a glass branch decided the other
//    way by a last-bit difference) the two pixels differ by noise; the allowance grows by 3
//    standard deviations of the difference, from the films' own variance.
//  * radius, how far an edge may move: a translation by T puts every coordinate on a grid of
//    ulp(T) (9.8e-4 at 1e4, 7.8e-3 at 1e5, 0.0625 at 1e6), camera and lights included, which
//    turns the view by up to ~ulp(T) / (distance to the target) and moves every silhouette and
//    shadow edge by up to ulp(T): 1 pixel up to 1e4, 2 at 1e5, 3 at 1e6 (the scenes' pixels
//    are 0.03-0.1 units wide at their subjects).
//  * mean: the same grid moves point lights by up to ~ulp(T) (0.054 at 1e6), which changes
//    their irradiance by 2 ulp(T) / d, 1-2% at 1e6 for lights 5-10 units away: 0.5% up to 1e4,
//    1% at 1e5, 2.5% at 1e6 (largest passing: 0.25%, 0.55%, 1.75%); scales, rotations and
//    mirrors, which move nothing onto a coarser grid, 0.25% (largest passing: 0.09%).
Tolerance toleranceFor(double offset) {
  Tolerance t;
  t.pixel = 0.03;
  t.sigmas = 3;
  t.radius = offset >= 1e6 ? 3 : offset >= 1e5 ? 2 : 1;
  if (sweep()) t.radius *= 2;  // images twice as wide: the same edge motion, twice the pixels
  t.mean = offset >= 1e6 ? 0.025 : offset >= 1e5 ? 0.01 : offset >= 1e3 ? 0.005 : 0.0025;
  return t;
}

// Rotations of a scene whose samples are drawn in frames that turn with it (the path
// tracer's bounces, area lights and environments sampled in a frame about an axis): the
// turned image's noise is independent of the original's, pixel by pixel as large as the
// signal at these sample counts. Such images are compared as 4 x 4 blocks, each allowed 4
// standard deviations of the difference of the two block means (from the films' variance),
// with 0.05 beyond (the largest passing excess is 0.036), and the mean 4 standard deviations
// of its own.
Tolerance independentNoise() {
  Tolerance t = toleranceFor(1);
  t.pixel = 0.05;
  t.block = 4;
  t.sigmas = 4;
  t.meanSigmas = 4;
  t.radius = 1;
  return t;
}

// Instant radiosity: its noise is the VPL set's, which the films' variance does not hold; it
// is measured as the differences from the next two seeds' images, whose root mean square over
// the window is the standard deviation of a difference of two draws. 4 of them (the largest
// excess of a passing case is 0.038 beyond; a removed block still fails).
Tolerance vplNoise() {
  Tolerance t = independentNoise();
  t.sigmas = 0;
  t.altSigmas = 4;
  t.meanSigmas = 3;
  return t;
}

std::vector<Family> families() {
  std::vector<Family> f;
  std::vector<double> offsets = {1e3, 1e4, 1e5, 1e6};
  if (sweep()) offsets = {1e2, 1e3, 1e4, 3e4, 1e5, 3e5, 1e6};
  for (const Placement mode : {Placement::Edit, Placement::Root})
    for (double k : offsets) {
      Family fam;
      fam.name =
          std::string(mode == Placement::Edit ? "translate-edit/" : "translate-root/") + power10(k);
      fam.map = invariance::translation({k, k, -k});
      fam.mode = mode;
      fam.offset = k;
      fam.tolerance = toleranceFor(k);
      f.push_back(fam);
    }
  for (double s : {1e-4, 1e-2, 1e2, 1e4}) {
    Family fam;
    fam.name = "scale/" + power10(s);
    fam.map = invariance::scaling(s);
    fam.tolerance = toleranceFor(1);
    f.push_back(fam);
  }
  const int rotations = sweep() ? 8 : 2;
  for (int seed = 1; seed <= rotations; ++seed) {
    Family fam;
    fam.name = "rotate/" + std::to_string(seed);
    fam.map = invariance::randomRotation(uint64_t(seed));
    fam.tolerance = toleranceFor(1);
    f.push_back(fam);
  }
  {
    Family fam;
    fam.name = "rotate-y";
    fam.map = invariance::rotation({0, 1, 0}, 117.5);
    fam.tolerance = toleranceFor(1);
    f.push_back(fam);
  }
  {
    Family fam;
    fam.name = "mirror";
    fam.map = invariance::reflection({0.267261, 0.534522, 0.801784});  // (1, 2, 3) / sqrt 14
    fam.tolerance = toleranceFor(1);
    f.push_back(fam);
  }
  for (Family& fam : f) fam.map.name = fam.name;
  return f;
}

// ---------------------------------------------------------------------------------------------
// What cannot be invariant, what is adapted, and what is open
// ---------------------------------------------------------------------------------------------

struct Exclusion {
  const char* scene;
  const char* family;  // a family name, or a prefix ending in '/' ("rotate/" = every rotation,
                       // "translate-" = both translation modes)
  const char* reason;
  double from = 0;  // translations: only offsets of at least this
};

// Scenes left out of a map by design. Every entry is printed when it applies.
const Exclusion kExclusions[] = {
    {"venus_garden", "rotate/",
     "its marble and wall textures are mapped in world space (DragonMarble, the fbm walls), and "
     "a world-space mapping has no rotation key; the dragons that use them are glTF meshes under "
     "their own transforms, so the mapping cannot be made object-space either"},
    {"venus_garden", "mirror", "as for rotate/: world-space textures cannot be mirrored"},
    // Features below two float steps of the offset: a translation by T puts every coordinate
    // on a grid of spacing ulp(T) (6.1e-5 at 1e3, 9.8e-4 at 1e4, 7.8e-3 at 1e5, 0.0625 at
    // 1e6), so two surfaces closer than about 2 ulp(T) can touch, cross or swap there.
    {"glass", "translate-",
     "the glass cone stands 0.001 above the floor (translate [1.1, 0.001, 0]): at 1e4 its base "
     "and the floor are one float step apart, and refracted rays leave the cone below the floor",
     1e4},
    {"cornell_path", "translate-",
     "the lamp hangs 0.01 below the ceiling: from 1e5 on (a float step of 0.0078) the two "
     "coincide",
     1e5},
    {"cornell_ir", "translate-", "as cornell_path: the lamp 0.01 below the ceiling", 1e5},
    {"area_lights", "translate-",
     "the bulb is a sphere light of radius 0.12: four float steps at 3e5 (0.031), two at 1e6, "
     "which change its shape and its power (the mean by 4% at 3e5)",
     3e5},
    {"snowy", "translate-",
     "the snow perturbs normals per object-space grain of 0.02-0.05 (and the snowmen's eyes are "
     "spheres of radius 0.035): at 1e6 the hit point itself is known to 0.06 only, so every "
     "grain lookup lands in another cell",
     1e6},
};

// Known failures of the renderer, by "scene/family": printed as KNOWN-OPEN with their numbers,
// not asserted either way. Empty this as the bugs are fixed (see issue 49; the findings with
// their reproductions were written to /tmp/inv-findings/FINDINGS.md while the net was built).
const std::set<std::string> kKnownOpen = {
    // At 1e6 one pixel of csg_scene (at the net's 128 x 96) stays 0.002 over the tolerance
    // (pixel (17, 61): 0.211 against 0.092), in the soft shadow on the floor between the blue
    // box, which stands on the floor plane, and the dice; 5-10 pixels of CSG acne before
    // 041a0f7. Still there after f87d730 (far rays); not traced further.
    "csg_scene/translate-edit/1e6",
    "csg_scene/translate-root/1e6",
};

// The same for the sweep only (GLINT_INVARIANCE_SWEEP=1): what its larger images, other
// offsets and rotations show beyond the quick net's list.
const std::set<std::string> kKnownOpenInSweep = {
    // Measured at b1b9ace, before a150da7 (camera packets lost far out, the black of
    // instanced glTF meshes) and 041a0f7 (offsets far out): TextureCoordinateTest's acne from
    // 1e4 at 192 x 144 (12 pixels), 38 at 3e4, 3060 at 3e5; the path-traced glTF scenes at 3e5
    // (2-3 black or firefly pixels, material_extensions' mean +2.2%). The quick net's 1e5 and
    // 1e6 cases of these scenes pass since; the sweep has not been run again (an hour): these
    // print 'passes now' when it is.
    "texture_coordinate_test/translate-edit/1e4",
    "texture_coordinate_test/translate-root/1e4",
    "texture_coordinate_test/translate-edit/3e4",
    "texture_coordinate_test/translate-root/3e4",
    "texture_coordinate_test/translate-edit/3e5",
    "texture_coordinate_test/translate-root/3e5",
    "demo/translate-edit/3e5",
    "demo/translate-root/3e5",
    "first_image/translate-edit/3e5",
    "first_image/translate-root/3e5",
    "material_extensions/translate-edit/3e5",
    "material_extensions/translate-root/3e5",
    // CSG acne far out, as above: csg.json at 1e6 (1 black pixel), csg_scene from 3e5.
    "csg/translate-root/1e6",
    "csg_scene/translate-edit/3e5",
    "csg_scene/translate-root/3e5",
    // NormalTangentTest's normal-mapped rings shade differently from 1e5 on (4 pixels at
    // 192 x 144; 195 at 384 x 288).
    "normal_tangent_test/translate-edit/1e5",
    "normal_tangent_test/translate-root/1e5",
    "normal_tangent_test/translate-edit/3e5",
    "normal_tangent_test/translate-root/3e5",
    "normal_tangent_test/translate-edit/1e6",
    "normal_tangent_test/translate-root/1e6",
    // Snowy's instant radiosity: some draws light the balls up (+534%), also at the origin
    // (seed 2023 of the unchanged scene: mean 1.26 where the others have 0.31). Not a weight
    // gone wrong: every VPL of a path carries the same flux (2,370 at the scene's 48 paths;
    // the two directional lights send theirs through a disk as wide as the whole terrain),
    // and one that lands beside a ball lights it with G clamped at 2 only (vpl_clamp). Any
    // change of coordinates redraws the VPLs. Open: light paths aimed at what the camera
    // sees, or a clamp that scales with the VPLs' flux.
    "snowy/rotate/1",
    "snowy/rotate/2",
    "snowy/rotate/3",
    "snowy/rotate/4",
    "snowy/rotate/5",
    "snowy/rotate/6",
    "snowy/rotate/7",
    "snowy/rotate/8",
    "snowy/translate-edit/3e5",
    "snowy/translate-root/3e5",
    // Open, marginal: at 1e6 the coin's shadow moves 3-4 pixels at 192 x 108 and a contact
    // line appears under the card (1 pixel, 0.011 over the tolerance).
    "primitives/translate-root/1e6",
    // Not the renderer: a VPL splotch in one 4 x 4 block that neither of the two other seeds
    // shows (0.045 over); the net's noise model for instant radiosity is a lower bound.
    "cornell_ir/rotate/4",
};

const Exclusion* exclusionFor(const std::string& scene, const Family& family) {
  for (const Exclusion& e : kExclusions) {
    const std::string f = e.family;
    const bool prefix = (f.back() == '/' || f.back() == '-') && family.name.rfind(f, 0) == 0;
    if (scene == e.scene && (family.name == f || prefix) && family.offset >= e.from) return &e;
  }
  return nullptr;
}

// Rotations and the mirror: a scene whose light or textures cannot turn with it is adapted so
// that the rest can be checked, in both the original and the turned render:
//  * an environment map or the studio (turns only about +Y) becomes a uniform sky with a sun
//    (a directional light, which turns with the scene); rotate-y keeps the real environment;
//  * a world-space texture used only by objects placed by the identity (a floor plane) is
//    mapped in object space instead, which is the same pattern on those objects and turns
//    with them;
//  * the mirror switches projective slides off (attenuation 0): the slide's frame is
//    right-handed, so a mirrored projector shows the mirror image of its slide.
Json adaptForTurning(Json scene, bool mirror, std::vector<std::string>* notes) {
  if (scene.contains("environment") && !scene["environment"].contains("color")) {
    scene["environment"] = Json::parse(R"({"color": [0.55, 0.6, 0.7]})");
    Json sun = Json::parse(R"({"name": "invariance sun", "type": "directional",
                               "direction": [-0.4, -1, -0.3], "intensity": 2.5})");
    if (!scene.contains("lights")) scene["lights"] = Json::array();
    scene["lights"].push_back(sun);
    notes->push_back("the environment map/studio replaced by a uniform sky and a sun");
  }
  if (scene.contains("textures"))
    for (Json& t : scene["textures"]) {
      if (!t.contains("mapping") || t["mapping"].value("space", "") != "world") continue;
      const std::string name = t.value("name", "");
      // Its users: materials naming it, and the objects with those materials.
      std::set<std::string> materials;
      if (scene.contains("materials"))
        for (const Json& m : scene["materials"])
          for (const auto& [key, value] : m.items())
            if ((value.is_string() && key != "name" && value == name) ||
                (value.is_object() && value.value("texture", "") == name))
              materials.insert(m.value("name", ""));
      bool identityPlaced = !scene.contains("gltf");
      if (scene.contains("objects"))
        for (const Json& o : scene["objects"]) {
          if (!materials.count(o.value("material", ""))) continue;
          const bool placed =
              (o.contains("transform") && !o["transform"].empty()) || o.contains("animation");
          const std::string type = o.value("type", "");
          identityPlaced = identityPlaced && !placed && type != "csg" && type != "terrain";
        }
      if (identityPlaced) {
        t["mapping"]["space"] = "object";
        notes->push_back(
            "texture '" + name +
            "': world-space mapping made object-space (its objects are placed by the identity)");
      }
    }
  if (scene.contains("media"))
    for (Json& m : scene["media"])
      if (!m.contains("region") && !m.contains("object") &&
          !(m.contains("density") && m["density"].value("type", "") == "vdb")) {
        // (A VDB medium fills its grids' box, placed by its transform: it turns as it is.)
        // The whole scene's medium fills the world-axis box around the scene, which a turned
        // scene changes: give it a region that turns with the scene, a sphere about the
        // camera's target through the camera and a half again.
        const Json& cam = scene["cameras"][0];
        const V3 target = invariance::toV3(cam["look_at"]), eye = invariance::toV3(cam["position"]);
        const double r = 1.5 * std::sqrt(invariance::dot(eye - target, eye - target));
        m["region"] = {{"type", "sphere"}, {"center", invariance::toJson(target)}, {"radius", r}};
        notes->push_back("medium '" + m.value("name", "") +
                         "': the whole scene's axis-aligned box replaced by a sphere about the "
                         "camera's target");
      }
  if (mirror && scene.contains("lights"))
    for (Json& l : scene["lights"])
      if (l.value("type", "") == "projective") {
        l["attenuation"] = 0;
        notes->push_back("projective light '" + l.value("name", "") +
                         "': slide off (attenuation 0) for the mirror");
      }
  return scene;
}

// ---------------------------------------------------------------------------------------------
// The net
// ---------------------------------------------------------------------------------------------

struct Outcome {
  std::string family;
  invariance::Comparison cmp;
  Tolerance tolerance;
  double seconds = 0;
};

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void writeCase(const std::string& dir, const std::string& tag, const Json& scene,
               const Film& film) {
  std::ofstream(dir + "/" + tag + ".json") << scene.dump(1);
  invariance::writeFilm(dir + "/" + tag, film);
}

class InvarianceNet : public testing::TestWithParam<SceneCase> {};

TEST_P(InvarianceNet, TheSceneMovedScaledTurnedAndMirroredRendersTheSameImage) {
  const SceneCase& c = GetParam();
  const std::string dir = test::scratchDir("invariance_" + c.name);
  std::printf("[ invariance ] %s\n", c.name.c_str());
  if (!c.vdbFolder.empty()) {
    fs::create_directories(c.vdbFolder);
    const std::string command =
        std::string("\"") + GLINT_MAKE_VDB_SCENES + "\" \"" + c.vdbFolder + "\" > /dev/null";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
  }

  // The scene as it is, twice: the same seed gives the same image, and the rewriting itself
  // (an identity map through transformScene) changes nothing.
  auto t0 = std::chrono::steady_clock::now();
  SceneFeatures features;
  Film original;
  try {
    original = invariance::renderScene(c.scene, c.file, &features);
  } catch (const std::exception& e) {
    FAIL() << c.name << " does not render: " << e.what() << " (shared assets from "
           << test::assetsDir() << "; set GLINT_ASSETS, see benchmarks/get_assets.sh)";
  }
  const bool turnsItsSamples = features.has(Feature::Indirect) ||
                               features.has(Feature::AreaLights) ||
                               features.has(Feature::Environment);
  const double originalSeconds = secondsSince(t0);
  invariance::SceneFacts facts = invariance::sceneFacts(c.scene, c.file);
  facts.gltfVolumes = c.gltfVolumes;
  {
    std::vector<std::string> notes;
    const Json same =
        invariance::transformScene(c.scene, invariance::identity(), Placement::Root, facts, &notes);
    const Film again = invariance::renderScene(same, c.file);
    size_t differ = 0;
    for (size_t i = 0; i < original.color.size(); ++i)
      differ += !(original.color[i] == again.color[i]);
    EXPECT_EQ(differ, 0u) << c.name << ": the identity map (or a second render) changed " << differ
                          << " pixels";
  }
  std::printf("[ invariance ]   original: %.2f s, %d x %d\n", originalSeconds, original.width,
              original.height);

  std::vector<Outcome> outcomes;
  std::map<bool, Json> turnable;  // the scene adapted for turning, without / with the mirror
  std::map<bool, Film> turnableFilm;
  // Instant radiosity lights the whole image with one random set of VPLs: a light path that
  // passes within a float step of a silhouette lands elsewhere once coordinates change, so the
  // moved scene's VPLs are another draw, and its image differs from the original as another
  // seed's does (a splotch moves). Such scenes are compared as independent noise, with that
  // noise measured: the original rendered with the next two seeds.
  const bool vpls = features.has(Feature::Vpls);
  auto withNextSeeds = [&](Json scene) {
    std::vector<Film> films;
    const uint64_t seed = scene["render"].value("seed", uint64_t(0));
    for (uint64_t k = 1; k <= 2; ++k) {
      scene["render"]["seed"] = seed + k;
      films.push_back(invariance::renderScene(scene, c.file));
    }
    return films;
  };
  std::map<bool, std::vector<Film>> alternates;  // by "turned scene": the next seeds' images
  if (vpls) alternates[false] = withNextSeeds(c.scene);
  for (const Family& fam : families()) {
    const std::string key = c.name + "/" + fam.name;
    if (!sweep() && !c.quick.empty() && !c.quick.count(fam.name)) {
      std::printf(
          "[ invariance ]   %-20s not in the quick net (GLINT_INVARIANCE_SWEEP=1 runs it)\n",
          fam.name.c_str());
      continue;
    }
    if (const Exclusion* e = exclusionFor(c.name, fam)) {
      std::printf("[ invariance ]   %-20s EXCLUDED: %s\n", fam.name.c_str(), e->reason);
      continue;
    }
    const bool turns = fam.map.turns();
    const bool mirror = fam.map.handedness() < 0;
    const bool aboutY = fam.name == "rotate-y";
    std::vector<std::string> notes;
    Json base = c.scene;
    const Film* reference = &original;
    if (turns && !aboutY) {
      if (!turnable.count(mirror)) {
        std::vector<std::string> adaptNotes;
        turnable[mirror] = adaptForTurning(c.scene, mirror, &adaptNotes);
        const std::vector<std::string> blockers = invariance::rotationBlockers(turnable[mirror]);
        for (const std::string& b : blockers)
          ADD_FAILURE()
              << c.name << " cannot be turned: " << b
              << "; adapt it in adaptForTurning or list it in kExclusions with the reason";
        if (!blockers.empty()) return;
        for (const std::string& n : adaptNotes)
          std::printf("[ invariance ]   adapted: %s\n", n.c_str());
        turnableFilm[mirror] = turnable[mirror] == c.scene
                                   ? original
                                   : invariance::renderScene(turnable[mirror], c.file);
      }
      base = turnable[mirror];
      reference = &turnableFilm[mirror];
      if (vpls && !alternates.count(true)) alternates[true] = withNextSeeds(base);
    } else if (aboutY) {
      // Only scenes whose light is an environment map or the studio: the others are covered
      // by the rotations about random axes.
      if (!c.scene.contains("environment") || c.scene["environment"].contains("color")) continue;
    }
    invariance::SceneFacts baseFacts = facts;
    if (base != c.scene) {
      baseFacts = invariance::sceneFacts(base, c.file);
      baseFacts.gltfVolumes = c.gltfVolumes;
    }
    Json moved;
    try {
      moved = invariance::transformScene(base, fam.map, fam.mode, baseFacts, &notes);
    } catch (const std::exception& e) {
      ADD_FAILURE() << key << ": cannot rewrite the scene: " << e.what();
      continue;
    }
    t0 = std::chrono::steady_clock::now();
    Film film;
    try {
      film = invariance::renderScene(moved, c.file);
    } catch (const std::exception& e) {
      ADD_FAILURE() << key << ": the moved scene does not render: " << e.what();
      std::ofstream(dir + "/" + fs::path(fam.name).filename().string() + ".json") << moved.dump(1);
      continue;
    }
    Tolerance tolerance = fam.tolerance;
    // Far out, a path-traced path that went another way at one bounce draws its next samples
    // in another frame, and more of them do the farther out: the mean gets its noise
    // allowance too.
    if (turnsItsSamples) tolerance.meanSigmas = 3;
    if (vpls || (turns && turnsItsSamples)) {
      tolerance = vpls ? vplNoise() : independentNoise();
      tolerance.mean = std::max(tolerance.mean, fam.tolerance.mean);
    }
    std::vector<const Film*> others;
    if (vpls)
      for (const Film& f : alternates[base != c.scene]) others.push_back(&f);
    Outcome o{fam.name, invariance::compareFilms(*reference, film, tolerance, others), tolerance,
              secondsSince(t0)};
    const bool pass = o.cmp.passes(o.tolerance);
    const bool open = kKnownOpen.count(key) > 0 || (sweep() && kKnownOpenInSweep.count(key) > 0);
    std::printf(
        "[ invariance ]   %-20s %s %5.2f s  bad %4d  excess %.3f  maxdiff %.3g (%.3g vs %.3g)  "
        "mean %+.3f%%  largest %.3f%s\n",
        fam.name.c_str(),
        pass   ? "ok  "
        : open ? "OPEN"
               : "FAIL",
        o.seconds, o.cmp.bad, o.cmp.worstExcess, o.cmp.maxDiff, o.cmp.maxDiffA, o.cmp.maxDiffB,
        100 * (o.cmp.meanB - o.cmp.meanA) / o.cmp.meanA, o.cmp.largestExcess,
        tolerance.block > 1 ? (vpls ? " (blocks, VPL noise)" : " (blocks, independent noise)")
                            : "");
    if (!pass) {
      std::string tag = fam.name;
      for (char& ch : tag)
        if (ch == '/') ch = '_';
      writeCase(dir, "original", base, *reference);
      writeCase(dir, tag, moved, film);
      invariance::writeMask(dir + "/" + tag + ".bad.png", *reference, o.cmp.badMask);
      std::string noteText;
      for (const std::string& n : notes) noteText += "\n    adjusted: " + n;
      if (open) {
        std::printf("[ invariance ]   KNOWN-OPEN %s: %s\n", key.c_str(), o.cmp.summary().c_str());
      } else {
        ADD_FAILURE() << key << ": " << o.cmp.summary() << "\n  first bad pixels:" << o.cmp.where
                      << "\n  tolerance " << o.tolerance.pixel << " (squeezed), edge radius "
                      << o.tolerance.radius << " px, mean " << 100 * o.tolerance.mean << "%"
                      << noteText << "\n  images and scenes: " << dir << "/{original," << tag
                      << "}.{png,exr,json}, " << tag << ".bad.png";
      }
    } else if (open) {
      std::printf("[ invariance ]   KNOWN-OPEN %s passes now: %s\n", key.c_str(),
                  o.cmp.summary().c_str());
    }
    outcomes.push_back(o);
  }
  EXPECT_FALSE(outcomes.empty());
}

INSTANTIATE_TEST_SUITE_P(Scenes, InvarianceNet, testing::ValuesIn(scenes()),
                         [](const testing::TestParamInfo<SceneCase>& p) { return p.param.name; });

// ---------------------------------------------------------------------------------------------
// Negative controls: each check of compareFilms fails a real change, with the net's tolerances
// ---------------------------------------------------------------------------------------------

// The reference scene `name` of the net, as the net renders it.
const SceneCase& sceneNamed(const std::string& name) {
  for (const SceneCase& c : scenes())
    if (c.name == name) return c;
  throw std::runtime_error("no scene " + name);
}

Json& objectNamed(Json& scene, const std::string& section, const std::string& name) {
  for (Json& o : scene[section])
    if (o.value("name", "") == name) return o;
  throw std::runtime_error("no " + section + " entry " + name);
}

void removeNamed(Json& scene, const std::string& section, const std::string& name) {
  Json& list = scene[section];
  for (size_t i = 0; i < list.size(); ++i)
    if (list[i].value("name", "") == name) {
      list.erase(i);
      return;
    }
  throw std::runtime_error("no " + section + " entry " + name);
}

// The control's comparison (a: the scene, b: the broken one), with the given tolerances.
invariance::Comparison control(const std::string& name, const Json& a, const Json& b,
                               const std::string& file, const Tolerance& tol,
                               const std::vector<const Film*>& alternates = {}) {
  const invariance::Comparison cmp = invariance::compareFilms(
      invariance::renderScene(a, file), invariance::renderScene(b, file), tol, alternates);
  std::printf("[ control ] %s: %s\n", name.c_str(), cmp.summary().c_str());
  return cmp;
}

// What the 9833da0 bug did at 1e6: a light's shadows gone (here the key light casts none),
// with the most lenient tolerances of the net (those of 1e6).
TEST(InvarianceControls, LostShadowsFail) {
  const SceneCase& c = sceneNamed("primitives");
  Json lost = c.scene;
  objectNamed(lost, "lights", "key")["cast_shadows"] = false;
  const invariance::Comparison cmp =
      control("shadows lost", c.scene, lost, c.file, toleranceFor(1e6));
  EXPECT_FALSE(cmp.pixelsPass());
  EXPECT_GT(cmp.bad, 10);
}

// An occluder removed (a small object and its shadow gone).
TEST(InvarianceControls, ARemovedOccluderFails) {
  const SceneCase& c = sceneNamed("primitives");
  Json removed = c.scene;
  removeNamed(removed, "objects", "coin");
  const invariance::Comparison cmp =
      control("coin removed", c.scene, removed, c.file, toleranceFor(1e6));
  EXPECT_FALSE(cmp.pixelsPass());
}

// A thin wall lost: a closed box shell with walls 1e-4 thick, lit from inside and outside;
// the control opens its front wall (the skin removed), so the lit inside shows.
TEST(InvarianceControls, AMissingThinSkinFails) {
  const std::string shell = R"({
    "render": {"width": 64, "height": 48, "spp": 4, "seed": 1, "camera": "c", "integrator": "whitted"},
    "cameras": [{"name": "c", "position": [0.6, 2.2, 6], "look_at": [0, 1.2, 0], "yfov_degrees": 35}],
    "lights": [{"name": "inside", "type": "point", "position": [0, 1.5, 0], "intensity": 20},
               {"name": "outside", "type": "point", "position": [3, 5, 4], "intensity": 40}],
    "objects": [{"type": "plane"},
      {"name": "shell", "type": "csg", "tree": {"op": "difference", "children": [
        {"type": "box", "min": [-1, 0.5, -1], "max": [1, 2.5, 1]},
        {"type": "box", "min": [-0.9999, 0.5001, -0.9999], "max": [0.9999, 2.4999, INNER_MAX_Z]}]}}]})";
  auto with = [&](const char* innerMaxZ) {
    std::string text = shell;
    text.replace(text.find("INNER_MAX_Z"), 11, innerMaxZ);
    return Json::parse(text);
  };
  const std::string file = test::scratchDir("invariance_controls") + "/shell.json";
  const invariance::Comparison cmp =
      control("1e-4 front wall removed", with("0.9999"), with("1.0001"), file, toleranceFor(1e6));
  EXPECT_FALSE(cmp.pixelsPass());
  EXPECT_GT(cmp.bad, 20);
}

// Acne: speckles of another colour on a lit floor. The control lays a dark quad on the
// floor quad, the same rectangle written from its other corner, so that which of the two a
// ray meets first is decided by rounding, pixel by pixel. Isolated speckles are not edges:
// each has no neighbour of its value in the original, and the comparison must say so.
TEST(InvarianceControls, ACoincidentDarkSurfaceFails) {
  const SceneCase& c = sceneNamed("primitives");
  Json floor = c.scene;
  removeNamed(floor, "objects", "ground");
  floor["objects"].push_back(Json::parse(
      R"({"name": "ground", "type": "quad", "corner": [-8, 0, -6], "edge_u": [16, 0, 0], "edge_v": [0, 0, 14], "material": "floor"})"));
  Json acne = floor;
  acne["materials"].push_back(
      Json::parse(R"({"name": "dark", "type": "lambert", "diffuse": [0.05, 0.05, 0.05]})"));
  acne["objects"].push_back(Json::parse(
      R"({"type": "quad", "corner": [8, 0, 8], "edge_u": [0, 0, -14], "edge_v": [-16, 0, 0], "material": "dark"})"));
  const invariance::Comparison cmp =
      control("coincident dark floor", floor, acne, c.file, toleranceFor(1e6));
  EXPECT_FALSE(cmp.pixelsPass());
  EXPECT_GT(cmp.bad, 10);
}

// The mean check alone: a key light slightly dimmer changes no pixel by the pixel tolerance,
// but the mean luminance by more than the bound: 1.5% dimmer against the bound up to 1e4
// (0.5%), 5% dimmer against the bound at 1e6 (2.5%).
TEST(InvarianceControls, ASlightlyDimmerLightFailsTheMean) {
  const SceneCase& c = sceneNamed("primitives");
  for (const auto& [factor, offset] : {std::pair{0.985, 1e4}, std::pair{0.95, 1e6}}) {
    Json dim = c.scene;
    Json& key = objectNamed(dim, "lights", "key");
    key["intensity"] = key["intensity"].get<double>() * factor;
    const invariance::Comparison cmp = control("key light x " + std::to_string(factor), c.scene,
                                               dim, c.file, toleranceFor(offset));
    EXPECT_TRUE(cmp.pixelsPass()) << "this control is for the mean check alone";
    EXPECT_FALSE(cmp.meanPasses(toleranceFor(offset))) << factor;
  }
}

// A light moved by a small amount towards the scene (0.5% of its position against the
// tolerances up to 1e4, 3% against those of 1e6): edges move by less than the radius, but
// the lighting changes.
TEST(InvarianceControls, ALightMovedASmallAmountFails) {
  const SceneCase& c = sceneNamed("primitives");
  for (const auto& [factor, offset] : {std::pair{0.995, 1e4}, std::pair{0.97, 1e6}}) {
    Json moved = c.scene;
    Json& key = objectNamed(moved, "lights", "key");
    key["position"] = invariance::toJson(invariance::toV3(key["position"]) * factor);
    const invariance::Comparison cmp = control("key light moved x " + std::to_string(factor),
                                               c.scene, moved, c.file, toleranceFor(offset));
    EXPECT_FALSE(cmp.passes(toleranceFor(offset))) << factor;
  }
}

// The independent-noise comparison (rotations of path-traced scenes) still sees a removed
// occluder: the Cornell box without its block, path-traced.
TEST(InvarianceControls, IndependentNoiseStillSeesARemovedOccluder) {
  const SceneCase& c = sceneNamed("cornell_path");
  Json removed = c.scene;
  removeNamed(removed, "objects", "block");
  Json reseeded = c.scene;
  reseeded["render"]["seed"] = 99;  // and another seed: noise independent of the original's
  removed["render"]["seed"] = 99;
  const invariance::Comparison same =
      control("another seed", c.scene, reseeded, c.file, independentNoise());
  EXPECT_TRUE(same.passes(independentNoise())) << "two seeds of one scene are the same scene";
  const invariance::Comparison cmp =
      control("block removed, another seed", c.scene, removed, c.file, independentNoise());
  EXPECT_FALSE(cmp.pixelsPass());
}

// The same with instant radiosity and the next two seeds' noise allowance.
TEST(InvarianceControls, AllowingForVplNoiseStillSeesARemovedOccluder) {
  const SceneCase& c = sceneNamed("cornell_ir");
  std::vector<Film> films;
  for (int k = 1; k <= 2; ++k) {
    Json next = c.scene;
    next["render"]["seed"] = c.scene["render"].value("seed", 0) + k;
    films.push_back(invariance::renderScene(next, c.file));
  }
  Json removed = c.scene;
  removeNamed(removed, "objects", "block");
  const invariance::Comparison cmp =
      control("block removed (VPLs)", c.scene, removed, c.file, vplNoise(), {&films[0], &films[1]});
  EXPECT_FALSE(cmp.pixelsPass());
}

// The rewriting itself, key by key, on a scene that has one of each kind of placement.
TEST(InvarianceRewriting, MovesEveryPlacementKey) {
  const Json scene = Json::parse(R"({
    "render": {"integrator": {"type": "whitted", "volume_step": 0.1}},
    "cameras": [{"name": "c", "position": {"keys": [[0, [0, 1, 5]], [1, [1, 1, 5]]]},
                 "look_at": [0, 0, 0], "aperture": 0.1, "focus_distance": 5}],
    "lights": [{"type": "point", "position": [1, 2, 3], "intensity": 10},
               {"type": "quad", "corner": [0, 2, 0], "edge_u": [1, 0, 0], "edge_v": [0, 0, 1]},
               {"type": "directional", "direction": [0, -1, 0]}],
    "textures": [{"name": "w", "type": "checker", "mapping": {"space": "world", "scale": 2}}],
    "materials": [{"name": "m", "type": "lambert", "diffuse": "w", "bump": {"texture": "w", "strength": 0.1}}],
    "objects": [{"name": "s", "type": "sphere", "center": [1, 0, 0], "radius": 1},
                {"name": "b", "type": "box", "min": [0, 0, 0], "max": [1, 1, 1],
                 "transform": [1, 0, 0, 2, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]},
                {"name": "a", "type": "sphere", "radius": 1,
                 "animation": {"translation": {"keys": [[0, [0, 0, 0]], [1, [1, 0, 0]]]}}}],
    "media": [{"name": "f", "region": {"type": "sphere", "center": [0, 0, 0], "radius": 2},
               "sigma_s": 1, "density": {"type": "noise"}}]})");
  invariance::SceneFacts facts;
  std::vector<std::string> notes;
  // Edit: position keys (keyframed ones key by key), the matrix's translation, the track.
  Json e = invariance::transformScene(scene, invariance::translation({10, 20, 30}), Placement::Edit,
                                      facts, &notes);
  EXPECT_EQ(e["cameras"][0]["position"]["keys"][1][1], Json::parse("[11, 21, 35]"));
  EXPECT_EQ(e["cameras"][0]["look_at"], Json::parse("[10, 20, 30]"));
  EXPECT_EQ(e["lights"][0]["position"], Json::parse("[11, 22, 33]"));
  EXPECT_EQ(e["lights"][1]["corner"], Json::parse("[10, 22, 30]"));
  EXPECT_EQ(e["objects"][0]["center"], Json::parse("[11, 20, 30]"));
  EXPECT_EQ(e["objects"][1]["transform"].back(), Json::parse(R"({"translate": [10, 20, 30]})"));
  EXPECT_EQ(e["objects"][1]["transform"][0].count("matrix"), 1u);  // a matrix became an op
  EXPECT_EQ(e["objects"][2]["animation"]["translation"]["keys"][1][1], Json::parse("[11, 20, 30]"));
  EXPECT_EQ(e["media"][0]["region"]["center"], Json::parse("[10, 20, 30]"));
  EXPECT_EQ(e["media"][0]["density"]["offset"], Json::parse("[10, 20, 30]"));  // noise follows
  EXPECT_EQ(e["textures"][0]["mapping"]["offset"], Json::parse("[-20, -40, -60]"));
  // Root: the op appended to each object; cameras and lights as in Edit.
  Json r = invariance::transformScene(scene, invariance::translation({10, 20, 30}), Placement::Root,
                                      facts, &notes);
  EXPECT_EQ(r["objects"][0]["center"], Json::parse("[1, 0, 0]"));
  EXPECT_EQ(r["objects"][0]["transform"], Json::parse(R"([{"translate": [10, 20, 30]}])"));
  EXPECT_EQ(r["media"][0]["region"]["transform"], Json::parse(R"([{"translate": [10, 20, 30]}])"));
  // Scale: lengths and intensities.
  Json s =
      invariance::transformScene(scene, invariance::scaling(2), Placement::Root, facts, &notes);
  EXPECT_EQ(s["lights"][0]["intensity"], 40.0);
  EXPECT_EQ(s["lights"][1]["edge_u"], Json::parse("[2, 0, 0]"));
  EXPECT_EQ(s["cameras"][0]["aperture"], 0.2);
  EXPECT_EQ(s["cameras"][0]["focus_distance"], 10.0);
  EXPECT_EQ(s["materials"][0]["bump"]["strength"], 0.2);
  EXPECT_EQ(s["media"][0]["sigma_s"], 0.5);
  EXPECT_EQ(s["render"]["integrator"]["volume_step"], 0.2);
  EXPECT_EQ(s["textures"][0]["mapping"]["scale"], 1.0);
  EXPECT_EQ(s["objects"][2]["transform"], Json::parse(R"([{"scale": 2.0}])"));
  // Mirror: a quad light keeps emitting to the same side; a camera becomes a matrix.
  facts.cameraFrames["c"] = {{{1, 0, 0, 0}, {0, 1, 0, 1}, {0, 0, 1, 5}, {0, 0, 0, 1}}};
  Json untextured = scene;  // a world-space texture cannot be mirrored (below)
  untextured.erase("textures");
  untextured["materials"] = Json::parse(R"([{"name": "m", "type": "lambert"}])");
  Json m = invariance::transformScene(untextured, invariance::reflection({1, 0, 0}),
                                      Placement::Root, facts, &notes);
  EXPECT_EQ(m["lights"][1]["edge_u"], Json::parse("[0, 0, 1]"));
  EXPECT_EQ(m["lights"][1]["edge_v"], Json::parse("[-1, 0, 0]"));
  EXPECT_FALSE(m["cameras"][0].contains("position"));
  EXPECT_EQ(m["cameras"][0]["transform"][0]["matrix"][0], Json::parse("[-1, 0, 0, 0]"));
  // What cannot be written fails loudly: a world-space texture cannot turn.
  EXPECT_THROW(invariance::transformScene(scene, invariance::rotation({0, 0, 1}, 30),
                                          Placement::Root, facts, &notes),
               std::runtime_error);
  EXPECT_THROW(invariance::transformScene(Json::parse(R"({"unknown": 1})"), invariance::identity(),
                                          Placement::Root, facts, &notes),
               std::runtime_error);
}

// compareFilms on synthetic films: one pixel changed in a flat region fails; an image moved by
// `radius` pixels passes and by more fails; the mean check reads the mean.
TEST(InvarianceControls, TheComparisonOnSyntheticFilms) {
  // A grey film with a bright square in the middle.
  auto square = [](int shift) {
    Film f = test::constantFilm(64, 48, {0.3f, 0.3f, 0.3f});
    for (int y = 16; y < 32; ++y)
      for (int x = 24 + shift; x < 40 + shift; ++x) f.color[f.index(x, y)] = {1.5f, 1.2f, 0.9f};
    return f;
  };
  Tolerance tol;
  tol.pixel = 0.05, tol.radius = 2, tol.mean = 0.01;
  const Film a = square(0);
  EXPECT_TRUE(invariance::compareFilms(a, a, tol).passes(tol));
  Film speck = a;
  speck.color[speck.index(5, 5)] = {0.45f, 0.45f, 0.45f};  // +50% on one pixel of flat grey
  invariance::Comparison cmp = invariance::compareFilms(a, speck, tol);
  EXPECT_EQ(cmp.bad, 1);
  EXPECT_EQ(cmp.worstX, 5);
  EXPECT_TRUE(cmp.meanPasses(tol));
  EXPECT_TRUE(invariance::compareFilms(a, square(2), tol).pixelsPass()) << "an edge 2 px away";
  EXPECT_FALSE(invariance::compareFilms(a, square(3), tol).pixelsPass()) << "an edge 3 px away";
  Film brighter = a;
  for (Rgb& c : brighter.color) c = c * 1.015f;
  cmp = invariance::compareFilms(a, brighter, tol);
  EXPECT_TRUE(cmp.pixelsPass());
  EXPECT_FALSE(cmp.meanPasses(tol));
  Film broken = a;
  broken.color[7] = {std::nanf(""), 0, 0};
  EXPECT_FALSE(invariance::compareFilms(a, broken, tol).passes(tol));
}

}  // namespace
}  // namespace glint
