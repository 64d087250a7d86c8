// Shadow rays reach what they aim at. Towards a point or spot light (no surface of its own)
// they end exactly at the light, so an occluder just in front of it is found from any
// distance; towards an area light they stop short only by the light sample's own error and the
// rounding of the distance, so the light never shadows itself and an occluder near it is still
// found. Each case failed while shadow rays kept a fixed fraction (1e-4) of their segment.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

#include "geometry/accel/accelerator.h"
#include "geometry/interaction.h"
#include "geometry/shapes/box.h"
#include "geometry/shapes/sphere.h"
#include "renderer/light.h"
#include "scenes/build.h"
#include "scenes/sidecar.h"
#include "test_support.h"

namespace glint {
namespace {

void addShape(GeometryScene* scene, std::unique_ptr<Shape> shape) {
  Instance inst;
  inst.shape = uint32_t(scene->shapes.size());
  scene->shapes.push_back(std::move(shape));
  scene->instances.push_back(inst);
}

// A point light 1e-5 (relative) above a slab 4e-5 thick, the floor 1 below: the floor under the
// slab is in the slab's umbra and must render exactly black, at every scale. The camera sits
// between floor and slab, looking down.
TEST(ShadowRays, APointLightJustAboveAThinSlabLeavesTheUmbraBlack) {
  for (double s : {1e-3, 1.0, 1e3}) {
    SCOPED_TRACE(s);
    auto scene = [&](bool slab) {
      auto num = [](double v) {
        std::ostringstream out;
        out.precision(17);
        out << v;
        return out.str();
      };
      return R"({
        "render": {"width": 16, "height": 16, "spp": 1, "camera": "c"},
        "cameras": [{"name": "c", "type": "orthographic", "xmag": )" +
             num(0.5 * s) + R"(, "ymag": )" + num(0.5 * s) + R"(, "position": [0, )" +
             num(0.5 * s) +
             R"(, 0], "look_at": [0, 0, 0], "up": [0, 0, -1]}],
        "lights": [{"type": "point", "position": [0, )" +
             num(s * (1 + 5e-5)) + R"(, 0], "intensity": )" + num(s * s) + R"(}],
        "materials": [{"name": "white", "type": "lambert", "diffuse": [0.8, 0.8, 0.8]}],
        "objects": [{"type": "plane", "material": "white"})" +
             (slab ? R"(, {"type": "box", "min": [)" + num(-s) + ", " + num(s) + ", " + num(-s) +
                         R"(], "max": [)" + num(s) + ", " + num(s * (1 + 4e-5)) + ", " + num(s) +
                         R"(], "material": "white"})"
                   : std::string()) +
             "]}";
    };
    const test::Rendered open = test::renderJson(scene(false));
    const test::Rendered shadowed = test::renderJson(scene(true));
    int lit = 0, umbraLit = 0;
    for (size_t i = 0; i < open.film.color.size(); ++i) {
      lit += luminance(open.film.color[i]) > 0.1f;
      umbraLit += luminance(shadowed.film.color[i]) > 0;
    }
    EXPECT_EQ(lit, 16 * 16) << "the floor must be lit without the slab";
    EXPECT_EQ(umbraLit, 0) << "light leaked past the slab";
  }
}

// A lamp 1 mm under a ceiling (a 20 cm slab) lights nothing above it, however far away the
// receiver: points on a higher ceiling, facing down, 10 m to 10 km up and out.
TEST(ShadowRays, ALampUnderACeilingLightsNothingAboveIt) {
  for (const std::string& name : acceleratorNames()) {
    SCOPED_TRACE(name);
    for (float height : {10.0f, 100.0f, 1e4f}) {
      SCOPED_TRACE(height);
      GeometryScene scene;
      addShape(&scene,
               std::make_unique<Box>(Vec3f{-1e5f, 1e-3f, -1e5f}, Vec3f{1e5f, 0.201f, 1e5f}));
      // The higher ceiling, a slab whose underside is at `height`.
      addShape(&scene,
               std::make_unique<Box>(Vec3f{-1e5f, height, -1e5f}, Vec3f{1e5f, height + 1, 1e5f}));
      auto accel = makeAccelerator(name, scene);
      const Vec3f lamp{0, 0, 0};
      std::mt19937 rng(3);
      std::uniform_real_distribution<float> u(-1, 1);
      int blocked = 0;
      for (int i = 0; i < 200; ++i) {
        // A receiver found by a ray from just under the higher ceiling, as a renderer finds it.
        const Vec3f above{u(rng) * height, height - 0.5f, u(rng) * height};
        Ray up{above, {0, 1, 0}};
        Hit hit;
        ASSERT_TRUE(accel->closestHit(up, &hit));
        const SurfaceInteraction si = computeSurfaceInteraction(scene, up, hit);
        blocked += accel->anyHit(si.spawnRayTo(lamp, 0));
      }
      EXPECT_EQ(blocked, 200);
    }
  }
}

// A light inside a closed shell 4e-5 thick (radius 0.01) is hidden from receivers hundreds to
// thousands of units away; without the shell they all see it (and nothing else: the receiver's
// own surface is not re-hit).
TEST(ShadowRays, AThinShellHidesTheLightInsideFromFarAway) {
  for (const std::string& name : acceleratorNames()) {
    SCOPED_TRACE(name);
    for (float far : {550.0f, 1e4f}) {
      SCOPED_TRACE(far);
      for (bool shell : {false, true}) {
        GeometryScene scene;
        addShape(&scene, std::make_unique<Sphere>(Vec3f{0, 0, 0}, far));  // the receivers
        if (shell) {
          addShape(&scene, std::make_unique<Sphere>(Vec3f{0, 0, 0}, 0.01f));
          addShape(&scene, std::make_unique<Sphere>(Vec3f{0, 0, 0}, 0.01f + 4e-5f));
        }
        auto accel = makeAccelerator(name, scene);
        std::mt19937 rng(11);
        std::normal_distribution<float> g;
        int blocked = 0, hits = 0;
        for (int i = 0; i < 300; ++i) {
          const Vec3f dir = normalize(Vec3f{g(rng), g(rng), g(rng)});
          Ray in{dir * (2 * far), -dir};
          Hit hit;
          if (!accel->closestHit(in, &hit) || hit.instance != 0) continue;
          ++hits;
          const SurfaceInteraction si = computeSurfaceInteraction(scene, in, hit);
          // The light is inside the receiver sphere: the ray leaves its surface inwards.
          LightSampleContext ctx(si, 0);
          ctx.n = -ctx.n;
          blocked += accel->anyHit(spawnRayTo(ctx.p, ctx.pError, ctx.n, Vec3f{0, 0, 0}, 0));
        }
        EXPECT_EQ(hits, 300);
        EXPECT_EQ(blocked, shell ? 300 : 0);
      }
    }
  }
}

// An area light (an emitting quad, which camera rays see) never shadows itself, from receivers
// 1 to 1e4 away at any angle, while a blocker 1e-3 in front of it still shadows receivers
// 1,000 away (a fraction 1e-4 of that segment is 0.1) and one 0.05 in front shadows them from
// 1e4 (where a float coordinate's ulp is already 1e-3).
TEST(ShadowRays, AreaLightsDoNotShadowThemselvesAndBlockersNearThemStillCount) {
  for (float gap : {0.0f, 1e-3f, 0.05f}) {
    SCOPED_TRACE(gap);
    const bool blocker = gap > 0;
    SceneDescription d;
    d.file = "scene.json";
    std::string text = R"({
      "render": {"default_light": false},
      "materials": [{"name": "lamp", "type": "lambert", "diffuse": [0, 0, 0], "emissive": [1, 1, 1]},
                    {"name": "grey", "type": "lambert", "diffuse": [0.5, 0.5, 0.5]}],
      "objects": [{"name": "light", "type": "quad", "corner": [-0.5, 0, -0.5],
                   "edge_u": [1, 0, 0], "edge_v": [0, 0, 1], "material": "lamp"})";
    if (blocker)
      text += R"(, {"type": "box", "min": [-2, )" + std::to_string(-gap - 1e-4f) +
              R"(, -2], "max": [2, )" + std::to_string(-gap) + R"(, 2], "material": "grey"})";
    text += "]}";
    applySceneJsonText(text, d.file, SceneJsonKind::Scene, &d);
    RenderScene scene = buildRenderScene(d);
    ASSERT_EQ(scene.lights().size(), 1u);
    const Light& light = *scene.lights()[0];
    // The light is geometry: a ray aimed at it from below reports it.
    Hit hit;
    ASSERT_TRUE(
        scene.accel().closestHit(Ray{{0.1f, blocker ? -1e-4f : -5.0f, 0.2f}, {0, 1, 0}}, &hit));
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u01(0, 1), u(-1, 1);
    int samples = 0, shadowed = 0;
    for (float far : {1.0f, 100.0f, 1e3f, 1e4f}) {
      for (int i = 0; i < 200; ++i) {
        // A receiver below the light (its emitting side faces -y), with the rounding error a
        // point of that magnitude carries.
        const Vec3f p{u(rng) * far, -far * (0.05f + u01(rng)), u(rng) * far};
        LightSampleContext ctx;
        ctx.p = p;
        ctx.pError = abs(p) * gamma(7);
        ctx.n = ctx.ns = Vec3f{0, 1, 0};
        const std::optional<LightSample> ls = light.sampleLi(ctx, {u01(rng), u01(rng)});
        if (!ls || !(ls->pdf > 0)) continue;
        ++samples;
        shadowed += scene.accel().anyHit(shadowRay(ctx, *ls));
      }
      if (!blocker) {
        EXPECT_EQ(shadowed, 0) << "the light shadowed itself at distance " << far;
      } else if (far <= 1e3f || gap >= 0.05f) {
        EXPECT_EQ(shadowed, samples) << "a blocker " << gap << " in front of the light was "
                                     << "missed from " << far;
      }
      samples = shadowed = 0;
    }
  }
}

// Whitted's shadows through glass: under a glass pane (index 1.5, faces normal to the light)
// the floor straight below the light keeps (1 - R) / (1 + R) of its light, R = 0.04 the
// normal-incidence Fresnel reflectance, multiple internal reflections included; a tinted pane
// multiplies that by its tint once per face. With glass_shadows off the pane is black, and
// the path tracer, which does not use it, is not asked.
TEST(ShadowRays, WhittedShadowsThroughAGlassPaneKeepTheFresnelTransmittance) {
  auto scene = [](const std::string& pane, bool glassShadows) {
    return std::string(R"({
      "render": {"width": 4, "height": 4, "spp": 1, "camera": "c",
                 "integrator": {"type": "whitted", "glass_shadows": )") +
           (glassShadows ? "true" : "false") + R"(}},
      "cameras": [{"name": "c", "type": "orthographic", "xmag": 0.005, "ymag": 0.005,
                   "position": [0, 0.2, 0], "look_at": [0, 0, 0], "up": [0, 0, -1]}],
      "lights": [{"type": "point", "position": [0, 3, 0], "intensity": 9}],
      "materials": [{"name": "white", "type": "lambert", "diffuse": [0.8, 0.8, 0.8]},
                    {"name": "clear", "type": "glass", "ior": 1.5},
                    {"name": "green", "type": "glass", "ior": 1.5, "color": [0.5, 0.8, 0.5]}],
      "objects": [{"type": "plane", "material": "white"})" +
           (pane.empty() ? std::string()
                         : R"(, {"type": "box", "min": [-5, 1, -5], "max": [5, 1.2, 5],
                                 "material": ")" +
                               pane + R"("})") +
           "]}";
  };
  auto mean = [](const Film& f) {
    double sum = 0;
    for (const Rgb& c : f.color) sum += luminance(c);
    return sum / double(f.color.size());
  };
  auto meanGreen = [](const Film& f) {
    double sum = 0;
    for (const Rgb& c : f.color) sum += c.y;
    return sum / double(f.color.size());
  };
  const float R = 0.04f;  // ((1.5 - 1) / (1.5 + 1))^2
  const double open = mean(test::renderJson(scene("", true)).film);
  ASSERT_GT(open, 0.05);
  const double clear = mean(test::renderJson(scene("clear", true)).film);
  EXPECT_NEAR(clear / open, (1 - R) / (1 + R), 2e-4);
  const double openGreen = meanGreen(test::renderJson(scene("", true)).film);
  const double green = meanGreen(test::renderJson(scene("green", true)).film);
  EXPECT_NEAR(green / openGreen, 0.8 * 0.8 * (1 - R) / (1 + R), 2e-4);
  EXPECT_EQ(mean(test::renderJson(scene("clear", false)).film), 0.0);
}

}  // namespace
}  // namespace glint
