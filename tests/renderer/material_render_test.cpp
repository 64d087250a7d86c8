// Render tests of the material plumbing in the Whitted integrator: surfaces that should be
// invisible (glass of index 1, a fully transparent eyelight) leave the image unchanged, a
// mirror shows what it faces, and scenes without such materials trace no secondary rays.
#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "renderer/light.h"
#include "renderer/render.h"
#include "scenes/build.h"
#include "scenes/load.h"
#include "scenes/sidecar.h"
#include "test_support.h"

namespace glint {
namespace {

// A checkered floor, a back wall and two lights, seen by a camera; `extra` adds materials
// and objects (JSON fragments, each starting with a comma when not empty). Shadow rays stop
// at glass and transparent surfaces in the Whitted integrator, so tests of invisible
// surfaces turn shadows off.
std::string sceneJson(const std::string& extraMaterials, const std::string& extraObjects,
                      bool shadows = true) {
  const std::string castShadows = shadows ? "true" : "false";
  return R"({
    "render": {"width": 48, "height": 36, "spp": 4, "camera": "c", "seed": 3,
               "background": [0.3, 0.4, 0.6]},
    "cameras": [{"name": "c", "position": [0, 2, 6], "look_at": [0, 0.8, 0]}],
    "lights": [{"type": "point", "position": [3, 6, 4], "intensity": 60, "cast_shadows": )" +
         castShadows + R"(},
               {"type": "directional", "direction": [-0.3, -1, -0.2], "intensity": 0.5, "cast_shadows": false}],
    "textures": [{"name": "checks", "type": "checker", "colors": [[0.8, 0.8, 0.8], [0.1, 0.1, 0.1]],
                  "mapping": {"space": "world", "plane": "xz", "scale": 2}}],
    "materials": [{"name": "floor", "type": "lambert", "diffuse": "checks"},
                  {"name": "wall", "type": "lambert", "diffuse": [0.6, 0.3, 0.2]})" +
         extraMaterials + R"(],
    "objects": [{"type": "plane", "material": "floor"},
                {"type": "box", "min": [-4, 0, -3], "max": [4, 3, -2.5], "material": "wall"})" +
         extraObjects + "]}";
}

using test::Rendered;
using test::renderJson;

// The largest per-channel difference between two films of the same size.
float maxDifference(const Film& a, const Film& b) {
  float worst = 0;
  for (size_t i = 0; i < a.color.size(); ++i)
    worst = std::max(worst, maxComponent(abs(a.color[i] - b.color[i])));
  return worst;
}

TEST(MaterialRender, GlassOfIndexOneIsInvisible) {
  // eta = 1: no reflection (F = 0 exactly) and no bending, so every ray passes straight
  // through both surfaces and sees what it would see without the sphere. The spawned rays
  // start past the hit's error bound, which moves them by a few ulps: allow 1e-3.
  Rendered without = renderJson(sceneJson("", "", false));
  Rendered with = renderJson(sceneJson(
      R"(, {"name": "g", "type": "glass", "ior": 1})",
      R"(, {"type": "sphere", "center": [0, 1, 0], "radius": 0.9, "material": "g"})", false));
  ASSERT_EQ(with.film.color.size(), without.film.color.size());
  EXPECT_LT(maxDifference(with.film, without.film), 1e-3f);
  EXPECT_GT(with.stats.rays.secondary, 0u);
  EXPECT_TRUE(with.features.has(Feature::Refraction));
}

TEST(MaterialRender, GlassOfIndexOneAndAHalfIsVisible) {
  Rendered without = renderJson(sceneJson("", ""));
  Rendered with = renderJson(
      sceneJson(R"(, {"name": "g", "type": "glass", "ior": 1.5})",
                R"(, {"type": "sphere", "center": [0, 1, 0], "radius": 0.9, "material": "g"})"));
  EXPECT_GT(maxDifference(with.film, without.film), 0.1f);
  EXPECT_EQ(with.stats.nonfiniteSamples, 0u);
}

// Faint mirror and glass branches go by Russian roulette (integrator.min_weight): unbiased, so
// the image's mean agrees with following every branch, within the noise the roulette adds,
// and fewer secondary rays are traced. The two renders share their camera samples (the
// roulette's number is drawn either way), so their difference is the roulette's noise alone.
TEST(MaterialRender, FaintBranchRouletteIsUnbiasedAndTracesFewerRays) {
  auto scene = [](const std::string& minWeight) {
    return R"({
      "render": {"width": 48, "height": 36, "spp": 64, "camera": "c", "seed": 5,
                 "background": [0.3, 0.4, 0.6],
                 "integrator": {"type": "whitted", "max_depth": 8, "min_weight": )" +
           minWeight + R"(}},
      "cameras": [{"name": "c", "position": [0, 1.5, 4], "look_at": [0, 1, 0]}],
      "lights": [{"type": "point", "position": [3, 6, 4], "intensity": 60}],
      "materials": [{"name": "floor", "type": "lambert", "diffuse": [0.7, 0.7, 0.7]},
                    {"name": "g", "type": "glass", "ior": 1.5},
                    {"name": "m", "type": "mirror", "color": [0.9, 0.9, 0.9]}],
      "objects": [{"type": "plane", "material": "floor"},
                  {"type": "sphere", "center": [-0.6, 1, 0], "radius": 0.7, "material": "g"},
                  {"type": "sphere", "center": [0.9, 0.8, -0.5], "radius": 0.6, "material": "m"}]})";
  };
  Rendered every = renderJson(scene("0"));
  Rendered roulette = renderJson(scene("0.2"));
  ASSERT_EQ(every.film.color.size(), roulette.film.color.size());
  EXPECT_LT(roulette.stats.rays.secondary, every.stats.rays.secondary * 3 / 4);
  // Per channel: the mean difference against its standard error from the roulette film's
  // variance of each pixel's mean (the roulette's noise and the shared anti-aliasing noise).
  const double n = double(every.film.color.size());
  for (int c = 0; c < 3; ++c) {
    double difference = 0, variance = 0, mean = 0;
    for (size_t i = 0; i < every.film.color.size(); ++i) {
      difference += roulette.film.color[i][c] - every.film.color[i][c];
      variance += roulette.film.variance[i][c];
      mean += every.film.color[i][c];
    }
    const double z = std::abs(difference / n) / std::sqrt(variance / (n * n));
    EXPECT_LT(z, 4.0) << "channel " << c << ", image mean " << mean / n;
  }
  // The roulette changes something (a stand-in that followed every branch would not).
  EXPECT_GT(maxDifference(roulette.film, every.film), 1e-4f);
  EXPECT_EQ(roulette.stats.nonfiniteSamples, 0u);
}

TEST(MaterialRender, FullyTransparentEyelightIsInvisible) {
  Rendered without = renderJson(sceneJson("", "", false));
  Rendered with = renderJson(sceneJson(
      R"(, {"name": "t", "type": "eyelight", "color": [1, 0, 0], "transparency": 1})",
      R"(, {"type": "box", "min": [-1, 0.2, -1], "max": [1, 1.5, 1], "material": "t"})", false));
  EXPECT_LT(maxDifference(with.film, without.film), 1e-3f);
  EXPECT_TRUE(with.features.has(Feature::Transparency));
}

TEST(MaterialRender, HalfTransparentEyelightBlends) {
  // A camera-facing quad: eyelight colour x |cos| = colour where the view is head-on.
  auto scene = [](const std::string& transparency) {
    return R"({"render": {"width": 8, "height": 8, "spp": 1, "camera": "c", "background": [0, 0, 1]},
      "cameras": [{"name": "c", "type": "orthographic", "xmag": 0.5, "ymag": 0.5,
                   "position": [0, 0, 5], "look_at": [0, 0, 0]}],
      "materials": [{"name": "t", "type": "eyelight", "color": [1, 0, 0])" +
           transparency + R"(}],
      "objects": [{"type": "quad", "corner": [-1, -1, 0], "edge_u": [2, 0, 0],
                   "edge_v": [0, 2, 0], "material": "t"}]})";
  };
  Rendered half = renderJson(scene(R"(, "transparency": 0.25)"));
  for (const Rgb& c : half.film.color) {
    EXPECT_NEAR(c.x, 0.75f, 1e-5f);  // 0.75 of the red surface
    EXPECT_NEAR(c.z, 0.25f, 1e-5f);  // 0.25 of the blue background behind it
  }
}

TEST(MaterialRender, ScenesWithoutSpecularMaterialsTraceNoSecondaryRays) {
  Rendered plain = renderJson(sceneJson("", ""));
  EXPECT_EQ(plain.stats.rays.secondary, 0u);
  for (Feature f : {Feature::Refraction, Feature::Transparency, Feature::Bump, Feature::Textures})
    EXPECT_FALSE(plain.features.has(f)) << featureName(f);
  EXPECT_TRUE(plain.features.has(Feature::Procedural));  // the checker
}

// Whitted shades a plain material (lit, opaque, not emitting or absorbing, no specular lobe)
// through its own instantiation, compiled without the other branches, when there is no
// indirect light (WhittedIntegrator's HitKind::Plain), and an opaque unlit one through another
// (HitKind::Unlit), for camera and mirrored rays alike; its shadow rays take the plain any-hit
// path when they cross no glass or media (plainShadows_). The same scene four ways must give
// one image:
// - `mask`: the plain and unlit materials get alpha_mode "mask" at full alpha, which changes
//   nothing but makes them transparent-capable, so their hits take the general path;
// - `glass`: a glass ball below the floor, where nothing can see it, turns on shadows through
//   glass for every material.
// The plain materials here are textured, bumped and glossy; the mirror and the emitter take the
// general path throughout, and the mirror's reflections reach the plain ones as secondary rays.
TEST(MaterialRender, WhittedShadesPlainMaterialsAsTheGeneralPathDoes) {
  auto scene = [](bool mask, bool glass) {
    const std::string m = mask ? R"(, "alpha_mode": "mask")" : "";
    return R"({
      "render": {"width": 48, "height": 36, "spp": 4, "camera": "c", "seed": 9,
                 "background": [0.3, 0.4, 0.6],
                 "integrator": {"type": "whitted", "max_depth": 4}},
      "cameras": [{"name": "c", "position": [0, 2, 6], "look_at": [0, 0.8, 0]}],
      "lights": [{"type": "point", "position": [3, 6, 4], "intensity": 60},
                 {"type": "directional", "direction": [-0.3, -1, -0.2], "intensity": 0.5}],
      "textures": [{"name": "checks", "type": "checker",
                    "colors": [[0.8, 0.8, 0.8], [0.1, 0.1, 0.1]],
                    "mapping": {"space": "world", "plane": "xz", "scale": 2}}],
      "materials": [{"name": "floor", "type": "lambert", "diffuse": "checks")" +
           m + R"(},
                    {"name": "wall", "type": "lambert", "diffuse": [0.6, 0.3, 0.2],
                     "bump": {"texture": "checks", "strength": 0.5})" +
           m + R"(},
                    {"name": "ball", "type": "phong", "diffuse": [0.3, 0.5, 0.3],
                     "specular": [0.4, 0.4, 0.4], "shininess": 20)" +
           m + R"(},
                    {"name": "eye", "type": "eyelight", "color": [0.9, 0.5, 0.2])" +
           m + R"(},
                    {"name": "m", "type": "mirror", "color": [0.9, 0.9, 0.9]},
                    {"name": "glow", "type": "lambert", "diffuse": [0.2, 0.2, 0.2],
                     "emissive": [2, 1, 0.5]},
                    {"name": "g", "type": "glass", "ior": 1.5}],
      "objects": [{"type": "plane", "material": "floor"},
                  {"type": "box", "min": [-4, 0, -3], "max": [4, 3, -2.5], "material": "wall"},
                  {"type": "sphere", "center": [-1.2, 0.8, 0], "radius": 0.8, "material": "ball"},
                  {"type": "sphere", "center": [1.2, 0.8, 0], "radius": 0.8, "material": "m"},
                  {"type": "sphere", "center": [0, 0.3, 1.2], "radius": 0.3, "material": "glow"},
                  {"type": "box", "min": [0.3, 0, 1.4], "max": [0.9, 0.6, 2], "material": "eye"})" +
           (glass ? R"(, {"type": "sphere", "center": [0, -5, 0], "radius": 1, "material": "g"})"
                  : "") +
           "]}";
  };
  const Rendered plain = renderJson(scene(false, false));
  EXPECT_FALSE(plain.features.has(Feature::Transparency));
  EXPECT_FALSE(plain.features.has(Feature::Refraction));
  double mean = 0;
  for (const Rgb& c : plain.film.color) mean += c.y;
  EXPECT_GT(mean / double(plain.film.color.size()), 0.05);
  EXPECT_GT(plain.stats.rays.secondary, 0u);  // the mirror's reflections
  for (const auto& [mask, glass] : {std::pair{true, false}, {false, true}, {true, true}}) {
    SCOPED_TRACE(std::string(mask ? "mask" : "") + (glass ? " glass" : ""));
    const Rendered other = renderJson(scene(mask, glass));
    EXPECT_EQ(other.features.has(Feature::Transparency), mask);
    EXPECT_EQ(other.features.has(Feature::Refraction), glass);  // shadows cross glass
    ASSERT_EQ(plain.film.color.size(), other.film.color.size());
    EXPECT_LT(maxDifference(plain.film, other.film), 1e-5f);
    EXPECT_EQ(other.stats.nonfiniteSamples, 0u);
  }
}

TEST(MaterialRender, MirrorReflectsTheBackground) {
  // An orthographic camera looking down at a mirror tilted by 45 degrees sees the horizon:
  // the background radiance times the mirror's reflectance.
  Rendered r = renderJson(R"({"render": {"width": 8, "height": 8, "spp": 1, "camera": "c",
      "background": [0.2, 0.4, 0.8]},
    "cameras": [{"name": "c", "type": "orthographic", "xmag": 0.3, "ymag": 0.3,
                 "position": [0, 5, 0], "look_at": [0, 0, 0], "up": [0, 0, -1]}],
    "materials": [{"name": "m", "type": "mirror", "color": [0.5, 0.5, 0.5]}],
    "objects": [{"type": "quad", "corner": [-1, 0, -1], "edge_u": [2, 0, 0], "edge_v": [0, 0, 2],
                 "material": "m", "transform": [{"rotate": {"axis": [1, 0, 0], "degrees": 45}}]}]})");
  for (const Rgb& c : r.film.color) {
    EXPECT_NEAR(c.x, 0.1f, 1e-5f);
    EXPECT_NEAR(c.y, 0.2f, 1e-5f);
    EXPECT_NEAR(c.z, 0.4f, 1e-5f);
  }
  EXPECT_EQ(r.stats.rays.secondary, 64u);
}

TEST(MaterialRender, ThreadCountsGiveIdenticalImagesWithGlassAndBump) {
  std::string text = sceneJson(
      R"(, {"name": "g", "type": "glass"}, {"name": "b", "type": "lambert", "diffuse": [0.7, 0.7, 0.7],
           "bump": {"texture": "checks", "strength": 0.02}})",
      R"(, {"type": "sphere", "center": [-1, 1, 0], "radius": 0.8, "material": "g"},
         {"type": "sphere", "center": [1.2, 0.7, 0.5], "radius": 0.7, "material": "b"})");
  SceneDescription d;
  d.file = "scene.json";
  applySceneJsonText(text, d.file, SceneJsonKind::Scene, &d);
  RenderScene scene = buildRenderScene(d);
  auto integrator = makeIntegrator(scene, d.render);
  Film one = render(scene, *integrator, d.render, {.threads = 1}, nullptr);
  Film two = render(scene, *integrator, d.render, {.threads = 2, .tileSize = 7}, nullptr);
  for (size_t i = 0; i < one.color.size(); ++i) ASSERT_EQ(one.color[i], two.color[i]) << i;
}

// glTF's unlit: every pixel that sees the surface has exactly its colour, whatever the lights,
// the angle (no cosine, unlike eyelight) or the integrator; and a mirror shows that colour too.
TEST(MaterialRender, UnlitSurfacesShowTheirColourExactly) {
  const Rgb colour{0.3f, 0.6f, 0.9f};
  for (const char* integrator : {"whitted", "path"}) {
    SCOPED_TRACE(integrator);
    const std::string json = R"({
      "render": {"width": 16, "height": 12, "spp": 4, "camera": "c", "integrator": ")" +
                             std::string(integrator) + R"("},
      "cameras": [{"name": "c", "position": [0, 1, 3], "look_at": [0, 0, 0], "yfov_degrees": 30}],
      "lights": [{"type": "point", "position": [1, 3, 1], "intensity": 50}],
      "materials": [{"name": "u", "type": "unlit", "color": [0.3, 0.6, 0.9]}],
      "objects": [{"type": "box", "min": [-50, -1, -50], "max": [50, 0, 50], "material": "u"}]})";
    Rendered r = renderJson(json);
    for (const Rgb& c : r.film.color)
      for (int k = 0; k < 3; ++k) ASSERT_NEAR(c[k], colour[k], 1e-6f);
    EXPECT_EQ(r.stats.rays.shadow, 0u);  // nothing to light
  }
}

// A test glTF (tests/data/gltf) set up for an 8 x 8, 2 spp image.
SceneDescription smallGltf(const std::string& name) {
  SceneDescription d = loadScene(test::dataDir() + "/gltf/" + name);
  d.render.width = 8;
  d.render.height = 8;
  d.render.spp = 2;
  return d;
}

Film renderSmall(const RenderScene& scene, const SceneDescription& d) {
  auto integrator = makeIntegrator(scene, d.render);
  RenderOptions options;
  options.threads = 2;
  RenderStats stats;
  return render(scene, *integrator, d.render, options, &stats);
}

void expectEveryPixel(const Film& film, Rgb expected) {
  for (const Rgb& c : film.color)
    for (int k = 0; k < 3; ++k) ASSERT_NEAR(c[k], expected[k], 1e-3f);
}

// KHR_materials_volume: every camera ray crosses 2 units of a clear (index 1) cube whose inside
// absorbs attenuationColor (0.5, 0.25, 0.8) per unit distance (tests/data/gltf/
// material_layers.gltf): the image is the white background times the colour squared, in both
// integrators, to rounding.
TEST(MaterialRender, VolumeAbsorbsByBeerLambert) {
  for (const char* integrator : {"whitted", "path"}) {
    SCOPED_TRACE(integrator);
    SceneDescription d = smallGltf("material_layers.gltf");
    d.render.background = {1, 1, 1};
    d.render.integrator.type = integrator;
    RenderScene scene = buildRenderScene(d);
    expectEveryPixel(renderSmall(scene, d), {0.25f, 0.0625f, 0.64f});
  }
}

// TEXCOORD_1 (tests/data/gltf/second_uv_set.gltf): a texture that names texCoord 1 reads the
// second set (green), the same texture through texCoord 0 the first (red); the film shows the
// square whose material reads set 1.
TEST(MaterialRender, TexturesReadTheUvSetTheyName) {
  SceneDescription d = smallGltf("second_uv_set.gltf");
  ASSERT_EQ(d.meshes.size(), 2u);
  EXPECT_EQ(d.meshes[0].uvs1.size(), 4u);
  RenderScene scene = buildRenderScene(d);
  expectEveryPixel(renderSmall(scene, d), {0, 1, 0});
  // The off-camera square's material reads set 0 of the same texture: red.
  SurfaceInteraction si;
  si.uv = {0.25f, 0.5f};
  si.uv1 = {0.75f, 0.5f};
  TextureLookups lookups(si);
  EXPECT_NEAR(scene.materials()[1]->albedo(si, lookups).x, 1, 1e-3f);
  EXPECT_NEAR(scene.materials()[0]->albedo(si, lookups).y, 1, 1e-3f);
}

// An emissive texture on TEXCOORD_1 glows the same when a light samples it as when a camera
// sees it: light samples carry the second set too (they used to read set 0: red, not green).
TEST(MaterialRender, EmissiveTextureOnTheSecondSetIsTheSameSampled) {
  SceneDescription d = smallGltf("second_uv_set.gltf");
  for (MaterialDesc& m : d.materials) {
    m.type = MaterialType::Pbr;
    m.emissive = {1, 1, 1};
    m.emissiveTexture = m.baseColorTexture;
    m.baseColorTexture = -1;
    m.baseColor = {0, 0, 0};
  }
  RenderScene scene = buildRenderScene(d);
  LightSampleContext ctx;
  ctx.p = {0, 0, 1};
  ctx.n = ctx.ns = {0, 0, -1};
  int samples = 0;
  for (const auto& light : scene.lights())
    for (float u : {0.1f, 0.4f, 0.6f, 0.9f}) {
      auto s = light->sampleLi(ctx, {u, 1 - u});
      // The studio environment lights this scene too; the square at x = 5 reads set 0.
      if (!s || s->infinite || s->pLight.x > 2.5f) continue;
      ++samples;
      EXPECT_NEAR(s->L.x, 0, 1e-3f) << "sample at " << s->pLight.x << ", " << s->pLight.y;
      EXPECT_NEAR(s->L.y, 1, 1e-3f) << "sample at " << s->pLight.x << ", " << s->pLight.y;
    }
  EXPECT_EQ(samples, 4);
}

}  // namespace
}  // namespace glint
