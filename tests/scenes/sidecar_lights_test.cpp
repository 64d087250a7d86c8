// The sidecar's area, projective and environment lights: reading, bad input, and the render
// scene built from them (emitting surfaces included).
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <tuple>

#include "image/io.h"
#include "image/output.h"
#include "renderer/area_lights.h"
#include "renderer/environment_light.h"
#include "renderer/film.h"
#include "renderer/projective_light.h"
#include "scene_error_support.h"
#include "scenes/build.h"
#include "scenes/sidecar.h"
#include "test_support.h"

namespace glint {
namespace {

using test::errorFrom;

constexpr const char* kFile = "demo.glint.json";

SceneDescription apply(const std::string& text) {
  SceneDescription scene;
  applySceneJsonText(text, kFile, SceneJsonKind::Scene, &scene);
  return scene;
}
SceneError applyError(const std::string& text) {
  SceneDescription scene;
  return errorFrom([&] { applySceneJsonText(text, kFile, SceneJsonKind::Scene, &scene); });
}

// The light as an area light over a shape of type `shape` (null: a triangle mesh), or null.
const AreaLight* areaLightOf(const Light* light, const char* shape) {
  auto* area = dynamic_cast<const AreaLight*>(light);
  if (!area) return nullptr;
  if (!shape) return area->shape() ? nullptr : area;
  return area->shape() && std::string(area->shape()->shape().typeName()) == shape ? area : nullptr;
}

// A floor quad, so the scene has geometry.
const std::string kFloor =
    R"("objects": [{"type": "quad", "corner": [-2, 0, 2], "edge_u": [4, 0, 0], "edge_v": [0, 0, -4]}])";

TEST(SidecarLights, ReadsQuadDiskSphereAndProjective) {
  SceneDescription d = apply(R"({
    "textures": [{"name": "clouds", "type": "clouds"}],
    "lights": [
      {"type": "quad", "corner": [0, 2, 0], "edge_u": [1, 0, 0], "edge_v": [0, 0, 1],
       "color": [1, 0.5, 0.25], "intensity": 4, "two_sided": true},
      {"type": "disk", "position": [0, 3, 0], "direction": [0, -1, 0], "radius": 0.5},
      {"type": "sphere", "position": [1, 2, 3], "radius": 0.25},
      {"type": "projective", "position": [0, 5, 0], "direction": [0, -1, 0], "up": [0, 0, -1],
       "fov_degrees": 30, "texture": "clouds",
       "attenuation": {"keys": [[0, 0], [2, 1]]}}
    ],
    "render": {"time": 1}, )" +
                             kFloor + "}");
  ASSERT_EQ(d.lights.size(), 4u);
  EXPECT_EQ(d.lights[0].type, LightType::Quad);
  EXPECT_TRUE(d.lights[0].twoSided);
  EXPECT_EQ(d.lights[0].edgeV, (Vec3f{0, 0, 1}));
  EXPECT_EQ(d.lights[1].type, LightType::Disk);
  EXPECT_FALSE(d.lights[1].twoSided);
  EXPECT_FLOAT_EQ(d.lights[2].radius, 0.25f);
  EXPECT_EQ(d.lights[3].type, LightType::Projective);
  EXPECT_EQ(d.lights[3].texture, 0);
  EXPECT_NEAR(d.lights[3].fov, 30 * kPi / 180, 1e-6f);
  EXPECT_NEAR(d.lights[3].attenuation, 0.5f, 1e-6f);  // keyframed, at time 1

  RenderScene s = buildRenderScene(d);
  ASSERT_EQ(s.lights().size(), 4u);
  auto* quad = areaLightOf(s.lights()[0].get(), "quad");
  ASSERT_NE(quad, nullptr);
  EXPECT_NEAR(quad->area(), 1, 1e-6f);
  // Radiance 4 (1, 0.5, 0.25), both sides, area 1: phi = 2 pi L.
  EXPECT_NEAR(quad->phi().x, 2 * kPi * 4, 1e-3f);
  // The disk faces down: it lights the floor below, not a point above.
  auto* disk = areaLightOf(s.lights()[1].get(), "disk");
  ASSERT_NE(disk, nullptr);
  EXPECT_NEAR(disk->area(), kPi * 0.25f, 1e-5f);
  LightSampleContext below, above;
  below.p = {0, 0, 0};
  above.p = {0, 4, 0};
  EXPECT_TRUE(disk->sampleLi(below, {0.3f, 0.4f}).has_value());
  EXPECT_FALSE(disk->sampleLi(above, {0.3f, 0.4f}).has_value());
  EXPECT_NE(areaLightOf(s.lights()[2].get(), "sphere"), nullptr);
  EXPECT_NE(dynamic_cast<const ProjectiveLight*>(s.lights()[3].get()), nullptr);
  EXPECT_TRUE(s.features().has(Feature::AreaLights));
  EXPECT_TRUE(s.features().has(Feature::Projective));
  EXPECT_FALSE(s.features().has(Feature::Environment));
  EXPECT_FALSE(s.features().has(Feature::DefaultLight));
}

// Area lights placed by a transform: a quad's corner and edges in the light's space, a disk in
// the frame's XY plane facing -Z, a sphere scaled unevenly into an ellipsoid.
TEST(SidecarLights, AreaLightsTakeATransform) {
  SceneDescription d = apply(R"({
    "lights": [
      {"type": "quad", "corner": [0, 0, 0], "edge_u": [1, 0, 0], "edge_v": [0, 0, 1],
       "transform": [{"scale": [2, 1, 3]}, {"translate": [0, 2, 0]}]},
      {"type": "disk", "radius": 0.5,
       "transform": [{"rotate": {"axis": [1, 0, 0], "degrees": -90}}, {"translate": [0, 3, 0]}]},
      {"type": "sphere", "radius": 1, "transform": [{"scale": [1, 1, 2]}, {"translate": [4, 2, 0]}]},
      {"type": "sphere", "radius": 1, "transform": [{"scale": 0.5}, {"translate": [-4, 2, 0]}]}
    ], )" + kFloor + "}");
  RenderScene s = buildRenderScene(d);
  ASSERT_EQ(s.lights().size(), 4u);
  auto* quad = areaLightOf(s.lights()[0].get(), "quad");
  ASSERT_NE(quad, nullptr);
  EXPECT_NEAR(quad->area(), 6, 1e-5f);
  // The XY-plane disk turned to face down: lights the floor below, nothing above.
  auto* disk = areaLightOf(s.lights()[1].get(), "disk");
  ASSERT_NE(disk, nullptr);
  LightSampleContext below, above;
  below.p = {0, 0, 0};
  above.p = {0, 5, 0};
  EXPECT_TRUE(disk->sampleLi(below, {0.3f, 0.4f}).has_value());
  EXPECT_FALSE(disk->sampleLi(above, {0.3f, 0.4f}).has_value());
  // A prolate spheroid of semi-axes 1, 1, 2: area 2 pi (1 + 2 * 2 / e asin e), e^2 = 3/4.
  auto* ellipsoid = areaLightOf(s.lights()[2].get(), "sphere");
  ASSERT_NE(ellipsoid, nullptr);
  const float e = std::sqrt(0.75f);
  EXPECT_NEAR(ellipsoid->area(), 2 * kPi * (1 + 2 / e * std::asin(e)), 2e-3f * 21.5f);
  auto* sphere = areaLightOf(s.lights()[3].get(), "sphere");
  ASSERT_NE(sphere, nullptr);
  EXPECT_NEAR(sphere->area(), kPi, 1e-5f);
  // A frame is given once.
  EXPECT_SCENE_ERROR(
      applyError(R"({"lights": [{"type": "sphere", "radius": 1, "position": [0, 0, 0],
                                 "transform": [{"translate": [0, 1, 0]}]}]})"),
      kFile, "/lights/0/position", "give either a 'transform' or 'position', not both");
}

TEST(SidecarLights, BadInputNamesThePointer) {
  struct Case {
    const char* json;
    const char* pointer;
    const char* phrase;
  };
  const Case cases[] = {
      {R"({"lights": [{"type": "sphere", "position": [0, 0, 0], "radius": -1}]})",
       "/lights/0/radius", "must be > 0"},
      {R"({"lights": [{"type": "disk", "position": [0, 0, 0], "direction": [0, 1, 0], "radius": 0}]})",
       "/lights/0/radius", "must be > 0"},
      {R"({"lights": [{"type": "quad", "corner": [0, 0, 0], "edge_u": [1, 0, 0], "edge_v": [2, 0, 0]}]})",
       "/lights/0/edge_v", "no area"},
      {R"({"lights": [{"type": "quad", "corner": [0, 0, 0], "edge_u": [1, 0, 0], "edge_v": [0, 0, 0]}]})",
       "/lights/0/edge_v", "no area"},
      {R"({"lights": [{"type": "disk", "position": [0, 0, 0], "direction": [0, 0, 0], "radius": 1}]})",
       "/lights/0/direction", "must not be zero"},
      {R"({"lights": [{"type": "quad", "corner": [0, 0, 0], "edge_u": [1, 0, 0], "edge_v": [0, 1, 0], "range": 3}]})",
       "/lights/0/range", "unknown key"},
      {R"({"lights": [{"type": "projective", "position": [0, 0, 0], "direction": [0, -1, 0], "attenuation": 1.5}]})",
       "/lights/0/attenuation", "must be >= 0 and <= 1"},
      {R"({"lights": [{"type": "projective", "position": [0, 0, 0], "direction": [0, -1, 0], "texture": "nope"}]})",
       "/lights/0/texture", "no texture named 'nope'"},
      {R"({"lights": [{"type": "projective", "position": [0, 0, 0], "direction": [0, -1, 0], "up": [0, 2, 0]}]})",
       "/lights/0/up", "not parallel"},
      {R"({"lights": [{"type": "projective", "position": [0, 0, 0], "direction": [0, -1, 0], "fov_degrees": 180}]})",
       "/lights/0/fov_degrees", "< 180"},
      {R"({"environment": {"image": "missing.exr"}})", "/environment/image", "file not found"},
      {R"({"environment": {"color": [1, 1, 1], "image": "sky.exr"}})", "/environment/image",
       "not both"},
      {R"({"environment": {"color": [1, -1, 1]}})", "/environment/color/1", ">= 0"},
      {R"({"environment": {"colour": [1, 1, 1]}})", "/environment/colour", "unknown key"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.json);
    EXPECT_SCENE_ERROR(applyError(c.json), kFile, c.pointer, c.phrase);
  }
}

TEST(SidecarLights, ConstantEnvironmentLightsTheScene) {
  SceneDescription d =
      apply(R"({"environment": {"color": [0.5, 1, 2], "intensity": 2}, )" + kFloor + "}");
  ASSERT_TRUE(d.environment.has_value());
  RenderScene s = buildRenderScene(d);
  ASSERT_EQ(s.infiniteLights().size(), 1u);
  EXPECT_EQ(s.escaped({0, 1, 0}), (Rgb{1, 2, 4}));
  EXPECT_TRUE(s.features().has(Feature::Environment));
  EXPECT_FALSE(s.features().has(Feature::DefaultLight));
}

TEST(SidecarLights, ImageEnvironmentIsReadFromAnExr) {
  const std::string dir = test::scratchDir("sidecar_lights_env");
  Film film(8, 4, false);
  for (size_t i = 0; i < film.color.size(); ++i) film.color[i] = Rgb{float(i), 1, 0.5f};
  writeImage(dir + "/sky.exr", film, RenderSettings{}, {});
  SceneDescription d;
  applySceneJsonText(
      R"({"environment": {"image": "sky.exr", "intensity": 3, "rotation_degrees": 90}, )" + kFloor +
          "}",
      dir + "/scene.json", SceneJsonKind::Scene, &d);
  RenderScene s = buildRenderScene(d);
  ASSERT_EQ(s.infiniteLights().size(), 1u);
  auto* env = dynamic_cast<const ImageEnvironmentLight*>(s.infiniteLights()[0]);
  ASSERT_NE(env, nullptr);
  // Straight up is the top row; every pixel of it has G = 1, times the intensity.
  EXPECT_NEAR(s.escaped({0, 1, 0}).y, 3, 1e-5f);
  // At a pixel centre, that pixel (R = its index); between centres, bilinear (R is linear in
  // the pixel's column and row, so the interpolation is exact).
  EXPECT_NEAR(env->Le(env->directionOf({2.5f / 8, 2.5f / 4})).x, 3 * float(2 * 8 + 2), 1e-3f);
  EXPECT_NEAR(env->Le(env->directionOf({0.3f, 0.6f})).x, 3 * (8 * 1.9f + 1.9f), 2e-3f);
}

TEST(SidecarLights, EnvironmentPresetsAndFormats) {
  const std::string dir = test::scratchDir("sidecar_lights_env_formats");
  SceneDescription d;
  applySceneJsonText(R"({"environment": {"preset": "studio", "intensity": 2}, )" + kFloor + "}",
                     dir + "/scene.json", SceneJsonKind::Scene, &d);
  ASSERT_TRUE(d.environment.has_value());
  EXPECT_TRUE(d.environment->studio);
  RenderScene s = buildRenderScene(d);
  EXPECT_FALSE(s.features().has(Feature::DefaultLight));  // the scene asked for it
  ASSERT_EQ(s.infiniteLights().size(), 1u);
  // Twice the studio: straight up is brighter than the horizon, all of it grey.
  const Rgb up = s.escaped({0, 1, 0}), horizon = s.escaped({0, 0.02f, -1});
  EXPECT_GT(up.y, horizon.y);
  EXPECT_EQ(up.x, up.z);
  // Radiance .hdr files are read as well as EXR.
  {
    // glint does not write .hdr itself; OpenImageIO does.
    const std::vector<float> half(4 * 2 * 3, 0.5f);
    auto out = OIIO::ImageOutput::create(dir + "/sky.hdr");
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(dir + "/sky.hdr", OIIO::ImageSpec(4, 2, 3, OIIO::TypeDesc::FLOAT)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, half.data()));
    out->close();
  }
  SceneDescription h;
  applySceneJsonText(R"({"environment": {"image": "sky.hdr"}, )" + kFloor + "}",
                     dir + "/scene.json", SceneJsonKind::Scene, &h);
  EXPECT_NEAR(buildRenderScene(h).escaped({0, 1, 0}).y, 0.5f, 1e-2f);
  // Errors name the key.
  for (const auto& [json, pointer, message] :
       std::vector<std::tuple<std::string, std::string, std::string>>{
           {R"({"environment": {"preset": "sunset"}})", "/environment/preset", "unknown preset"},
           {R"({"environment": {"preset": "studio", "color": [1, 1, 1]}})", "/environment/preset",
            "not both"},
           {R"({"environment": {"image": "scene.json"}})", "/environment/image", "scene-linear"}}) {
    SceneDescription bad;
    std::ofstream(dir + "/scene.json") << "{}";
    try {
      applySceneJsonText(json, dir + "/scene.json", SceneJsonKind::Scene, &bad);
      ADD_FAILURE() << "accepted " << json;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(pointer), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
}

TEST(SidecarLights, EmittingSurfacesBecomeLights) {
  SceneDescription d = apply(R"({
    "materials": [{"name": "glow", "type": "lambert", "diffuse": [0, 0, 0], "emissive": [2, 2, 2]}],
    "objects": [
      {"type": "quad", "corner": [-2, 0, 2], "edge_u": [4, 0, 0], "edge_v": [0, 0, -4]},
      {"type": "disk", "radius": 0.5, "material": "glow", "transform": [{"translate": [0, 2, 0]}]},
      {"type": "sphere", "radius": 0.5, "material": "glow", "transform": [{"scale": 2}]},
      {"type": "box", "min": [0, 0, 0], "max": [1, 1, 1], "material": "glow"},
      {"type": "quad", "corner": [0, 3, 0], "edge_u": [1, 0, 0], "edge_v": [0, 0, 1], "material": "glow"}
    ]})");
  d.render.defaultLight = false;  // the emitters alone
  RenderScene s = buildRenderScene(d);
  ASSERT_EQ(s.instanceLight().size(), 5u);
  EXPECT_EQ(s.instanceLight()[0], -1);
  ASSERT_GE(s.instanceLight()[1], 0);
  ASSERT_GE(s.instanceLight()[2], 0);
  ASSERT_GE(s.instanceLight()[3], 0);
  ASSERT_GE(s.instanceLight()[4], 0);
  EXPECT_EQ(s.lights().size(), 4u);  // and no default light
  EXPECT_FALSE(s.features().has(Feature::DefaultLight));
  EXPECT_TRUE(s.features().has(Feature::AreaLights));
  auto* disk = areaLightOf(s.lights()[size_t(s.instanceLight()[1])].get(), "disk");
  ASSERT_NE(disk, nullptr);
  EXPECT_NEAR(disk->area(), kPi * 0.25f, 1e-5f);
  // Two-sided radiance 2 over the area: phi = 2 pi L A.
  EXPECT_NEAR(disk->phi().x, 2 * kPi * 2 * disk->area(), 1e-3f);
  auto* sphere = areaLightOf(s.lights()[size_t(s.instanceLight()[2])].get(), "sphere");
  ASSERT_NE(sphere, nullptr);
  EXPECT_NEAR(sphere->area(), 4 * kPi, 1e-4f);  // radius 0.5 scaled by 2
  // The box's six faces, sampled by area.
  auto* box = areaLightOf(s.lights()[size_t(s.instanceLight()[3])].get(), "box");
  ASSERT_NE(box, nullptr);
  EXPECT_NEAR(box->area(), 6, 1e-4f);
  EXPECT_NEAR(box->phi().x, 2 * kPi * 2 * 6, 1e-2f);
  auto* quad = areaLightOf(s.lights()[size_t(s.instanceLight()[4])].get(), "quad");
  ASSERT_NE(quad, nullptr);
  // The radiance a light sample carries is the material's emission.
  LightSampleContext ctx;
  ctx.p = {0.5f, 0, 0.5f};
  ctx.n = ctx.ns = {0, 1, 0};
  auto ls = quad->sampleLi(ctx, {0.5f, 0.5f});
  ASSERT_TRUE(ls.has_value());
  EXPECT_EQ(ls->L, (Rgb{2, 2, 2}));
}

TEST(SidecarLights, EmissiveMeshesAndTexturedEmission) {
  SceneDescription d = apply(R"({
    "textures": [{"name": "checks", "type": "checker", "colors": [[1, 0, 0], [0, 0, 4]],
                  "mapping": {"scale": 2}}],
    "materials": [{"name": "glow", "type": "lambert", "emissive": [2, 2, 2]},
                  {"name": "tiles", "type": "lambert", "emissive": "checks"}],
    "objects": [
      {"type": "terrain", "size": 2, "depth": 2, "height": 0.5, "material": "glow"},
      {"type": "quad", "corner": [0, 3, 0], "edge_u": [1, 0, 0], "edge_v": [0, 0, 1], "material": "tiles"}
    ]})");
  RenderScene s = buildRenderScene(d);
  ASSERT_EQ(s.instanceLight().size(), 2u);
  auto* mesh = areaLightOf(s.lights()[size_t(s.instanceLight()[0])].get(), nullptr);
  ASSERT_NE(mesh, nullptr);
  EXPECT_GE(mesh->area(), 4.0f);  // at least its footprint
  EXPECT_NEAR(mesh->phi().x, 2 * kPi * 2 * mesh->area(), 1e-3f * mesh->phi().x);
  // The quad's light carries the texture at the sampled uv, as a camera hit there sees it.
  auto* quad = areaLightOf(s.lights()[size_t(s.instanceLight()[1])].get(), "quad");
  ASSERT_NE(quad, nullptr);
  LightSampleContext ctx;
  ctx.p = {0.5f, 0, 0.5f};
  ctx.n = ctx.ns = {0, 1, 0};
  auto a = quad->sampleLi(ctx, {0.1f, 0.1f}), b = quad->sampleLi(ctx, {0.6f, 0.1f});
  ASSERT_TRUE(a.has_value());
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ(a->L, (Rgb{1, 0, 0}));
  EXPECT_EQ(b->L, (Rgb{0, 0, 4}));
  // Half the quad is red (1), half blue (4): the power follows the texture's average.
  EXPECT_NEAR(quad->phi().x, 2 * kPi * 0.5f, 1e-3f);
  EXPECT_NEAR(quad->phi().z, 2 * kPi * 2.0f, 1e-3f);
}

TEST(SidecarLights, EmittersDoNotSwitchTheDefaultLightOff) {
  SceneDescription d = apply(R"({
    "materials": [{"name": "glow", "type": "lambert", "emissive": [1, 1, 1]}],
    "objects": [{"type": "plane", "material": "glow"},
                {"type": "sphere", "radius": 1, "material": "glow"}]})");
  RenderScene s = buildRenderScene(d);
  // The studio, then the sphere; an infinite plane glows when hit but cannot be sampled.
  ASSERT_EQ(s.lights().size(), 2u);
  EXPECT_TRUE(s.features().has(Feature::DefaultLight));
  EXPECT_EQ(s.infiniteLights().size(), 1u);
  // Switched off, the emitters alone light the scene.
  d.render.defaultLight = false;
  s = buildRenderScene(d);
  EXPECT_EQ(s.lights().size(), 1u);
  EXPECT_FALSE(s.features().has(Feature::DefaultLight));
  // ... and is listed, with the reason, for `glint info`.
  ASSERT_EQ(s.unsampledEmitters().size(), 1u);
  EXPECT_EQ(s.unsampledEmitters()[0].shape, "plane");
  EXPECT_NE(s.unsampledEmitters()[0].reason.find("unbounded"), std::string::npos);
}

TEST(SidecarLights, EmittingCsgTreesAreListedAsUnsampled) {
  SceneDescription d = apply(R"({
    "materials": [{"name": "glow", "type": "lambert", "emissive": [1, 1, 1]}],
    "objects": [{"type": "csg", "material": "glow", "tree": {"op": "union", "children": [
      {"type": "box", "min": [0, 0, 0], "max": [1, 1, 1]}, {"type": "sphere", "radius": 0.5}]}},
      {"type": "sphere", "radius": 0.5, "material": "glow", "transform": [{"translate": [3, 0, 0]}]}]})");
  d.render.defaultLight = false;  // the emitters alone
  RenderScene s = buildRenderScene(d);
  ASSERT_EQ(s.lights().size(), 1u);  // the sphere
  EXPECT_EQ(s.instanceLight()[0], -1);
  ASSERT_EQ(s.unsampledEmitters().size(), 1u);
  EXPECT_EQ(s.unsampledEmitters()[0].instance, 0u);
  EXPECT_EQ(s.unsampledEmitters()[0].shape, "csg");
  EXPECT_NE(s.unsampledEmitters()[0].reason.find("CSG"), std::string::npos);
}

}  // namespace
}  // namespace glint
