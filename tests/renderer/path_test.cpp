// Path tracer tests: closed-form scenes (furnace, a glowing enclosure), agreement with Whitted
// where both estimate the same thing, determinism across thread counts, and scenes built to
// provoke NaN/Inf. Every statistical check states its tolerance in standard errors taken from
// the film's per-pixel variance of the mean.
#include "renderer/path.h"

#include <gtest/gtest.h>

#include <cmath>

#include "geometry/shapes/plane.h"
#include "geometry/shapes/sphere.h"
#include "renderer/direct_light.h"
#include "renderer/render.h"
#include "scenes/build.h"
#include "scenes/sidecar.h"
#include "test_support.h"

namespace glint {
namespace {

// ---------------------------------------------------------------------------------------------
// Scenes
// ---------------------------------------------------------------------------------------------

MaterialDesc lambert(Rgb albedo, Rgb emissive = {0, 0, 0}) {
  MaterialDesc m;
  m.name = "lambert";
  m.type = MaterialType::Lambert;
  m.baseColor = albedo;
  m.emissive = emissive;
  return m;
}

ObjectDesc sphere(Vec3f center, float radius, int material) {
  ObjectDesc o;
  o.name = "sphere";
  o.shape = std::make_shared<Sphere>(center, radius);
  o.material = material;
  return o;
}

CameraDesc camera(Vec3f eye, Vec3f target, float yfovDegrees) {
  CameraDesc c;
  c.name = "c";
  c.yfov = yfovDegrees * kPi / 180;
  c.worldFromCamera = Transform::lookAt(eye, target, {0, 1, 0});
  return c;
}

SceneDescription pathScene(int size, int spp, int maxDepth, int rrDepth) {
  SceneDescription d;
  d.file = "path_test (in code)";
  d.render.width = size;
  d.render.height = size;
  d.render.spp = spp;
  d.render.integrator.type = "path";
  d.render.integrator.maxDepth = maxDepth;
  d.render.integrator.rrDepth = rrDepth;
  d.render.defaultLight = false;  // the scenes here are lit by what they hold
  return d;
}

Film renderPath(const RenderScene& scene, const RenderSettings& settings, int threads = 2,
                RenderStats* stats = nullptr, int tileSize = 16) {
  PathIntegrator integrator(scene, settings.integrator);
  RenderOptions options;
  options.threads = threads;
  options.tileSize = tileSize;
  RenderStats local;
  return render(scene, integrator, settings, options, stats ? stats : &local);
}

// The mean of the green channel over `pixels` and its standard error (pixels are independent).
struct Estimate {
  double mean = 0, sigma = 0;
  size_t n = 0;
};
template <typename Keep>
Estimate average(const Film& film, Keep keep) {
  Estimate e;
  double sum = 0, var = 0;
  for (size_t i = 0; i < film.color.size(); ++i) {
    if (!keep(i)) continue;
    sum += film.color[i].y;
    var += film.variance[i].y;
    ++e.n;
  }
  if (e.n == 0) return e;
  e.mean = sum / double(e.n);
  e.sigma = std::sqrt(var) / double(e.n);
  return e;
}

// ---------------------------------------------------------------------------------------------
// Furnace
// ---------------------------------------------------------------------------------------------

// A diffuse sphere of albedo a in a uniform environment of radiance 1 reflects exactly a: every
// direction leaving a convex object escapes. Both strategies find the environment (NEE and
// BSDF sampling draw the same cosine distribution), so a wrong MIS weight shows as a wrong
// mean, not as noise.
TEST(PathTracer, FurnaceSphereReflectsItsAlbedo) {
  for (float a : {0.2f, 0.5f, 0.9f}) {
    SceneDescription d = pathScene(32, 16, 8, 3);
    d.materials.push_back(lambert({a, a, a}));
    d.objects.push_back(sphere({0, 0, 0}, 1, 0));
    d.cameras.push_back(camera({0, 0, 4}, {0, 0, 0}, 40));
    RenderScene scene = buildRenderScene(d);
    test::useUniformEnvironment(&scene, {1, 1, 1});
    RenderStats stats;
    Film film = renderPath(scene, d.render, 2, &stats);
    size_t onSphere = 0, onEnvironment = 0;
    for (size_t i = 0; i < film.color.size(); ++i) {
      if (film.alpha[i] == 0) {
        // Camera rays that escape see the environment with weight 1: exactly 1.
        EXPECT_EQ(film.color[i], (Rgb{1, 1, 1})) << "a " << a << " pixel " << i;
        ++onEnvironment;
      } else if (film.alpha[i] == 1) {
        // 5 standard errors, plus float rounding.
        const float tolerance = 5 * std::sqrt(film.variance[i].y) + 1e-4f;
        EXPECT_NEAR(film.color[i].y, a, tolerance) << "a " << a << " pixel " << i;
        ++onSphere;
      }
    }
    EXPECT_GT(onSphere, 100u);
    EXPECT_GT(onEnvironment, 100u);
    const Estimate e = average(film, [&](size_t i) { return film.alpha[i] == 1; });
    EXPECT_NEAR(e.mean, a, 4 * e.sigma + 1e-4) << "sphere mean, a " << a;
    EXPECT_EQ(stats.nonfiniteSamples, 0u);
    EXPECT_GT(stats.rays.shadow, 0u);
  }
}

// A near-mirror plastic (a delta lobe over a diffuse base) and a polished metal under a
// uniform sky: their BSDF sampling is nearly exact there, so the path tracer leaves the sky to
// it (Light::leftToBsdfSampling). Sampling the sky as well made one branch carry the diffuse
// part twice: samples of 1.42 under a sky of 1 for the plastic. One bounce, so a sample is
// what the vertex brings; the mean must still be Whitted's, which samples the sky at every
// point and traces the mirror reflection.
TEST(PathTracer, LeavesAUniformSkyToANearlyExactBsdf) {
  auto scene = [](const std::string& material, const std::string& integrator, int spp) {
    return R"({"render": {"width": 32, "height": 32, "spp": )" + std::to_string(spp) +
           R"(, "camera": "c", "seed": 3, "integrator": {"type": ")" + integrator +
           R"(", "max_depth": 1}},
      "environment": {"color": [1, 1, 1]},
      "cameras": [{"name": "c", "position": [0, 0, 3.2], "look_at": [0, 0, 0], "yfov_degrees": 45}],
      "materials": [)" +
           material + R"(],
      "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}]})";
  };
  const std::string plastic =
      R"({"name": "m", "type": "pbr", "base_color": [0.9, 0.7, 0.6], "metallic": 0, "roughness": 0})";
  const std::string metal =
      R"({"name": "m", "type": "pbr", "base_color": [0.9, 0.8, 0.7], "metallic": 1, "roughness": 0.2})";
  for (const std::string& material : {plastic, metal}) {
    // One sample per pixel: the brightest is one sample. The plastic's diffuse samples weigh
    // up to (1 - F(wi)) / (1 - F_avg) = 0.96 / 0.908 of the lobes' weights (at most 1): 1.06;
    // the metal's F G2 / G1 <= 1.
    const test::Rendered one = test::renderJson(scene(material, "path", 1));
    EXPECT_LE(one.stats.brightestSample, 1.1f) << material;
    EXPECT_GE(one.stats.brightestSample, 0.99f) << material;  // the sky is seen
    // No shadow rays: the sky is the only light, and every vertex left it to the BSDF.
    EXPECT_EQ(one.stats.rays.shadow, 0u) << material;
  }
  // Unbiased: the sphere's mean agrees with Whitted's, within 4 standard errors of both.
  const test::Rendered path = test::renderJson(scene(plastic, "path", 64));
  const test::Rendered whitted = test::renderJson(scene(plastic, "whitted", 64));
  auto onSphere = [&](size_t i) { return path.film.alpha[i] == 1; };
  const Estimate a = average(path.film, onSphere), b = average(whitted.film, onSphere);
  ASSERT_GT(a.n, 300u);
  EXPECT_NEAR(a.mean, b.mean, 4 * std::hypot(a.sigma, b.sigma))
      << "path " << a.mean << ", Whitted " << b.mean;
  EXPECT_GT(whitted.stats.rays.shadow, 0u);  // Whitted still samples the sky
}

// ---------------------------------------------------------------------------------------------
// Closed enclosure
// ---------------------------------------------------------------------------------------------

// Inside a closed sphere whose walls emit Le and reflect albedo a (Lambert), radiance is the
// same everywhere and solves L = Le + a L: L = Le / (1 - a). Truncated after D bounces it is
// Le (1 - a^(D+1)) / (1 - a).
Estimate renderEnclosure(float a, float Le, int maxDepth, int rrDepth, uint64_t seed) {
  SceneDescription d = pathScene(16, 64, maxDepth, rrDepth);
  d.render.seed = seed;
  d.materials.push_back(lambert({a, a, a}, {Le, Le, Le}));
  d.objects.push_back(sphere({0, 0, 0}, 2, 0));
  d.cameras.push_back(camera({0.3f, -0.2f, 0.5f}, {1, 0, -1}, 60));
  RenderScene scene = buildRenderScene(d);
  RenderStats stats;
  Film film = renderPath(scene, d.render, 2, &stats);
  EXPECT_EQ(stats.nonfiniteSamples, 0u);
  return average(film, [](size_t) { return true; });
}

TEST(PathTracer, GlowingEnclosureConvergesToLeOverOneMinusAlbedo) {
  const float Le = 0.5f;
  for (float a : {0.5f, 0.8f}) {
    const double exact = Le / (1 - a);
    // Russian roulette from bounce 3; depth 200 leaves a^201 of the answer out (< 1e-19).
    for (uint64_t seed : {1u, 2u}) {
      Estimate rr = renderEnclosure(a, Le, 200, 3, seed);
      EXPECT_NEAR(rr.mean, exact, 4 * rr.sigma + 1e-4 * exact) << "a " << a << " seed " << seed;

      EXPECT_LT(rr.sigma, 0.01 * exact) << "too noisy for the test to mean anything";
    }
    // No roulette: the truncated series, for a depth where truncation is visible.
    for (int depth : {0, 1, 5, 60}) {
      const double truncated = Le * (1 - std::pow(double(a), depth + 1)) / (1 - a);
      Estimate plain = renderEnclosure(a, Le, depth, 1000, 3);
      EXPECT_NEAR(plain.mean, truncated, 4 * plain.sigma + 1e-4 * truncated)
          << "a " << a << " depth " << depth;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Agreement with Whitted
// ---------------------------------------------------------------------------------------------

// Direct light only (one bounce, no emitters, black background): the path tracer picks one
// of the two lights per vertex where Whitted sums both, so its image is noisy but must have
// the same mean.
TEST(PathTracer, AgreesWithWhittedOnDirectLight) {
  const std::string json = R"({
    "render": {"width": 40, "height": 30, "spp": 16, "camera": "c", "seed": 5,
               "integrator": {"type": "whitted", "max_depth": 1, "light_sampler": "uniform"}},
    "cameras": [{"name": "c", "position": [0, 2, 6], "look_at": [0, 0.8, 0]}],
    "lights": [{"type": "point", "position": [3, 6, 4], "intensity": 60},
               {"type": "spot", "position": [-2, 4, 2], "direction": [0.4, -1, -0.3],
                "intensity": 40, "outer_cone_degrees": 35}],
    "materials": [{"name": "floor", "type": "lambert", "diffuse": [0.7, 0.7, 0.7]},
                  {"name": "wall", "type": "lambert", "diffuse": [0.6, 0.3, 0.2]},
                  {"name": "ball", "type": "phong", "diffuse": [0.3, 0.5, 0.3],
                   "specular": [0.4, 0.4, 0.4], "shininess": 20}],
    "objects": [{"type": "plane", "material": "floor"},
                {"type": "box", "min": [-4, 0, -3], "max": [4, 3, -2.5], "material": "wall"},
                {"type": "sphere", "center": [0, 1, 0], "radius": 0.9, "material": "ball"}]})";
  SceneDescription d;
  d.file = "scene.json";
  applySceneJsonText(json, d.file, SceneJsonKind::Scene, &d);
  RenderScene scene = buildRenderScene(d);
  EXPECT_EQ(resolveIntegrator(scene, {.type = "auto"}), IntegratorKind::Whitted);
  auto whitted = makeIntegrator(scene, d.render);
  Film reference = render(scene, *whitted, d.render, {.threads = 2}, nullptr);
  RenderStats stats;
  Film film = renderPath(scene, d.render, 2, &stats);
  EXPECT_EQ(stats.nonfiniteSamples, 0u);
  double sum = 0, sumRef = 0, var = 0;
  size_t outliers = 0;
  for (size_t i = 0; i < film.color.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const double sigma = std::sqrt(double(film.variance[i][c]) + reference.variance[i][c]);
      if (std::abs(film.color[i][c] - reference.color[i][c]) > 5 * sigma + 1e-4) ++outliers;
    }
    sum += film.color[i].y, sumRef += reference.color[i].y;
    var += film.variance[i].y + reference.variance[i].y;
  }
  // 5 sigma per pixel and channel: chance alone gives none of 3600 (a sample variance from
  // 16 samples can underestimate, so allow a handful).
  EXPECT_LE(outliers, 3u);
  const double n = double(film.color.size());
  EXPECT_NEAR(sum / n, sumRef / n, 4 * std::sqrt(var) / n + 1e-6) << "image mean";
  EXPECT_GT(sumRef / n, 0.05) << "the scene is lit";
}

// ---------------------------------------------------------------------------------------------
// Determinism and the factory
// ---------------------------------------------------------------------------------------------

TEST(PathTracer, ImageIsIdenticalForOneAndTwoThreads) {
  SceneDescription d = pathScene(24, 8, 6, 2);
  d.render.aovs = true;
  d.materials.push_back(lambert({0.7f, 0.6f, 0.5f}));
  d.materials.push_back(lambert({0.5f, 0.5f, 0.5f}, {2, 2, 2}));
  d.objects.push_back(sphere({0, 0, 0}, 1, 0));
  d.objects.push_back(sphere({1.5f, 1.2f, 0.5f}, 0.4f, 1));
  d.cameras.push_back(camera({0, 0.5f, 4}, {0, 0, 0}, 50));
  RenderScene scene = buildRenderScene(d);
  test::useUniformEnvironment(&scene, {0.3f, 0.4f, 0.5f});
  Film one = renderPath(scene, d.render, 1, nullptr, 16);
  Film two = renderPath(scene, d.render, 2, nullptr, 7);
  ASSERT_EQ(one.color.size(), two.color.size());
  for (size_t i = 0; i < one.color.size(); ++i) {
    ASSERT_EQ(one.color[i], two.color[i]) << "pixel " << i;
    ASSERT_EQ(one.variance[i], two.variance[i]) << "pixel " << i;
    ASSERT_EQ(one.albedo[i], two.albedo[i]) << "pixel " << i;
  }
}

TEST(PathTracer, AutoChoosesThePathTracerForExtendedLight) {
  SceneDescription d = pathScene(8, 1, 4, 3);
  d.render.integrator.type = "auto";
  d.materials.push_back(lambert({0.5f, 0.5f, 0.5f}));
  d.objects.push_back(sphere({0, 0, 0}, 1, 0));
  d.cameras.push_back(camera({0, 0, 4}, {0, 0, 0}, 40));
  LightDesc point;
  point.intensity = 5;
  point.worldFromLight = Transform::translate({0, 3, 0});
  d.lights.push_back(point);
  RenderScene scene = buildRenderScene(d);
  // Point lights only: Whitted renders them exactly.
  EXPECT_EQ(resolveIntegrator(scene, d.render.integrator), IntegratorKind::Whitted);
  EXPECT_FALSE(scene.features().has(Feature::Indirect));
  EXPECT_EQ(resolveIntegrator(scene, {.type = "whitted"}), IntegratorKind::Whitted);
  test::useUniformEnvironment(&scene, {1, 1, 1});
  EXPECT_EQ(resolveIntegrator(scene, d.render.integrator), IntegratorKind::Path);
  EXPECT_NE(dynamic_cast<PathIntegrator*>(makeIntegrator(scene, d.render).get()), nullptr);
  // The builder marks indirect light when the path tracer is asked for.
  d.render.integrator.type = "path";
  EXPECT_TRUE(buildRenderScene(d).features().has(Feature::Indirect));
}

TEST(PathTracer, RendersMediaAndAutoPicksItForMultipleScattering) {
  SceneDescription d = pathScene(8, 1, 4, 3);
  d.materials.push_back(lambert({0.5f, 0.5f, 0.5f}));
  d.objects.push_back(sphere({0, 0, 0}, 1, 0));
  d.cameras.push_back(camera({0, 0, 4}, {0, 0, 0}, 40));
  LightDesc point;
  point.intensity = 5;
  point.worldFromLight = Transform::translate({0, 3, 0});
  d.lights.push_back(point);
  MediumDesc fog;  // the whole scene
  fog.sigmaS = {0.1f, 0.1f, 0.1f};
  d.media.push_back(fog);
  d.render.integrator.type = "auto";
  RenderScene scene = buildRenderScene(d);
  // Point lights and single scattering: Whitted; multiple scattering: the path tracer.
  EXPECT_EQ(resolveIntegrator(scene, d.render.integrator), IntegratorKind::Whitted);
  d.render.integrator.volume = "multiple";
  EXPECT_EQ(resolveIntegrator(scene, d.render.integrator), IntegratorKind::Path);
  d.render.integrator.volume = "single";
  test::useUniformEnvironment(&scene, {1, 1, 1});  // extended light: the path tracer
  EXPECT_EQ(resolveIntegrator(scene, d.render.integrator), IntegratorKind::Path);
  d.render.integrator.type = "path";
  EXPECT_NE(dynamic_cast<PathIntegrator*>(makeIntegrator(scene, d.render).get()), nullptr);
}

// ---------------------------------------------------------------------------------------------
// Numerics
// ---------------------------------------------------------------------------------------------

TEST(PathTracer, PowerHeuristicHandlesTheEdges) {
  EXPECT_FLOAT_EQ(powerHeuristic(1, 1), 0.5f);
  EXPECT_FLOAT_EQ(powerHeuristic(3, 1), 0.9f);
  EXPECT_EQ(powerHeuristic(0, 0), 0.0f);
  EXPECT_EQ(powerHeuristic(1e30f, 1), 1.0f);  // f^2 overflows
  EXPECT_EQ(powerHeuristic(1, kInfinity), 0.0f);
  EXPECT_EQ(powerHeuristic(0, 1), 0.0f);
}

// Grazing camera rays over a plane and a sphere, a light of intensity zero, an emitting
// triangle of zero area and an environment: nothing non-finite may be produced.
TEST(PathTracer, ProvocativeSceneProducesNoNonFiniteSamples) {
  SceneDescription d = pathScene(48, 8, 10, 2);
  d.materials.push_back(lambert({0.8f, 0.8f, 0.8f}));
  d.materials.push_back(lambert({0.5f, 0.5f, 0.5f}, {5, 5, 5}));
  d.materials.push_back(lambert({0.5f, 0.5f, 0.5f}));
  ObjectDesc plane;
  plane.shape = std::make_shared<Plane>(Vec3f{0, 0, 0}, Vec3f{0, 1, 0}, 1.0f);
  plane.material = 0;
  d.objects.push_back(plane);
  d.objects.push_back(sphere({0, 1, -3}, 1, 2));
  // A degenerate emitter: three vertices on one point, and one with two equal vertices.
  MeshDesc tri;
  tri.name = "degenerate";
  tri.positions = {{0.5f, 0.5f, -1}, {0.5f, 0.5f, -1}, {0.5f, 0.5f, -1}, {1, 0.5f, -1}};
  tri.indices = {0, 1, 2, 0, 1, 3};
  tri.material = 1;
  d.meshes.push_back(tri);
  d.instances.push_back({0, Transform(), "degenerate", {}});
  // Camera a hair above the plane, looking along it: rays graze it and the sphere's top.
  d.cameras.push_back(camera({0, 1e-4f, 2}, {0, 1e-4f, -3}, 60));
  LightDesc dark;
  dark.intensity = 0;
  dark.worldFromLight = Transform::translate({0, 2, 0});
  d.lights.push_back(dark);
  RenderScene scene = buildRenderScene(d);
  // The zero-intensity light plus an environment, both sampled by power (one has none).
  scene.addLight(std::make_unique<UniformEnvironmentLight>(Rgb{0.5f, 0.5f, 0.5f}));
  for (const char* sampler : {"power", "uniform"}) {
    scene.setLightSampler(sampler);
    RenderStats stats;
    Film film = renderPath(scene, d.render, 2, &stats);
    EXPECT_EQ(stats.nonfiniteSamples, 0u) << sampler;
    size_t lit = 0;
    for (size_t i = 0; i < film.color.size(); ++i) {
      ASSERT_TRUE(isFinite(film.color[i])) << sampler << " pixel " << i;
      ASSERT_TRUE(isFinite(film.variance[i])) << sampler << " pixel " << i;
      lit += film.color[i].y > 0;
    }
    EXPECT_GT(lit, film.color.size() / 2) << sampler;
  }
}

}  // namespace
}  // namespace glint
