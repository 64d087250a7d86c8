// The path tracer in participating media: closed forms (an absorbing slab, an emitting slab, a
// medium furnace whose emission balances its absorption), agreement with Whitted's single
// scattering at max_depth 1, multiple against single scattering, determinism across thread
// counts, and scenes built to provoke NaN/Inf. Every statistical check states its tolerance in
// standard errors taken from the film's per-pixel variance of the mean.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "geometry/shapes/box.h"
#include "geometry/shapes/sphere.h"
#include "renderer/path.h"
#include "renderer/render.h"
#include "renderer/volume.h"
#include "scenes/build.h"
#include "test_support.h"

namespace glint {
namespace {

// ---------------------------------------------------------------------------------------------
// Scenes
// ---------------------------------------------------------------------------------------------

constexpr float kHalf = 2;  // the orthographic camera sees [-2, 2]^2 of the plane z = 0

// An orthographic camera on +z looking down -z at [-2, 2]^2, a box filter of one pixel (so a
// pixel's expectation is the mean over its own square), and a small far-away triangle out of
// view so that the geometry is not empty. Media and lights are added by the tests.
SceneDescription mediaScene(int size, int spp, const std::string& integrator, int maxDepth = 64) {
  SceneDescription d;
  d.file = "path_volume_test (in code)";
  MeshDesc far;
  far.positions = {{100, 100, 100}, {101, 100, 100}, {100, 101, 100}};
  far.indices = {0, 1, 2};
  d.meshes.push_back(far);
  d.instances.push_back({0, Transform(), "far", {}});
  CameraDesc cam;
  cam.name = "c";
  cam.type = CameraType::Orthographic;
  cam.xmag = cam.ymag = kHalf;
  cam.worldFromCamera = Transform::lookAt({0, 0, 6}, {0, 0, 0}, {0, 1, 0});
  d.cameras.push_back(cam);
  d.render.width = d.render.height = size;
  d.render.spp = spp;
  d.render.filter = {"box", 0.5f};
  d.render.integrator.type = integrator;
  d.render.integrator.maxDepth = maxDepth;
  return d;
}

// A homogeneous medium in the box [lower, upper].
MediumDesc boxMedium(Vec3f lower, Vec3f upper, Rgb sigmaA, Rgb sigmaS, Rgb emission = {},
                     float g = 0) {
  MediumDesc m;
  m.name = "box";
  m.region = MediumDesc::Region::Shape;
  m.shape = std::make_shared<Box>(lower, upper);
  m.sigmaA = sigmaA, m.sigmaS = sigmaS, m.emission = emission, m.g = g;
  return m;
}

// A homogeneous medium in the sphere of `radius` at the origin.
MediumDesc sphereMedium(float radius, Rgb sigmaA, Rgb sigmaS, Rgb emission = {}, float g = 0) {
  MediumDesc m;
  m.name = "ball";
  m.region = MediumDesc::Region::Shape;
  m.shape = std::make_shared<Sphere>(Vec3f{0, 0, 0}, radius);
  m.sigmaA = sigmaA, m.sigmaS = sigmaS, m.emission = emission, m.g = g;
  return m;
}

LightDesc pointLight(Vec3f p, float intensity) {
  LightDesc l;
  l.type = LightType::Point;
  l.intensity = intensity;
  l.worldFromLight = Transform::translate(p);
  return l;
}

// Removes every light the scene names (the studio a scene without lights gets included);
// emitting surfaces stay lights.
void dropLights(RenderScene* scene) {
  scene->setLights({});
  scene->setLightSampler("power");
}

Film renderWith(const RenderScene& scene, const RenderSettings& settings, int threads = 2,
                int tileSize = 16, RenderStats* stats = nullptr) {
  auto integrator = makeIntegrator(scene, settings);
  RenderOptions options;
  options.threads = threads;
  options.tileSize = tileSize;
  RenderStats local;
  Film film = render(scene, *integrator, settings, options, stats ? stats : &local);
  EXPECT_EQ((stats ? stats : &local)->nonfiniteSamples, 0u);
  return film;
}

// World position of pixel centre (x, y) on the plane z = 0.
Vec2f pixelCentre(const Film& film, int x, int y) {
  return {-kHalf + 2 * kHalf * (float(x) + 0.5f) / float(film.width),
          kHalf - 2 * kHalf * (float(y) + 0.5f) / float(film.height)};
}

// The per-channel mean over the kept pixels and its standard error (pixels are independent).
struct Estimate {
  Rgb mean, sigma;
  size_t n = 0;
};
template <typename Keep>
Estimate average(const Film& film, Keep keep) {
  Estimate e;
  double sum[3] = {0, 0, 0}, var[3] = {0, 0, 0};
  for (int y = 0; y < film.height; ++y)
    for (int x = 0; x < film.width; ++x) {
      if (!keep(pixelCentre(film, x, y))) continue;
      const size_t i = film.index(x, y);
      for (int c = 0; c < 3; ++c) sum[c] += film.color[i][c], var[c] += film.variance[i][c];
      ++e.n;
    }
  if (e.n == 0) return e;
  for (int c = 0; c < 3; ++c) {
    e.mean[c] = float(sum[c] / double(e.n));
    e.sigma[c] = float(std::sqrt(var[c]) / double(e.n));
  }
  return e;
}
Estimate averageAll(const Film& film) {
  return average(film, [](Vec2f) { return true; });
}

// ---------------------------------------------------------------------------------------------
// Closed forms
// ---------------------------------------------------------------------------------------------

// A purely absorbing slab of thickness 1 (chromatic, so delta tracking takes null collisions
// in the thinner channels) in front of an environment of radiance 1: exp(-sigma_a), as
// Whitted's closed form gives exactly.
TEST(PathVolume, AbsorbingSlabTransmitsTheExponential) {
  const Rgb sigmaA{0.5f, 1.0f, 2.0f};
  auto inside = [](Vec2f p) { return std::abs(p.x) < 1.4f && std::abs(p.y) < 1.4f; };
  auto outside = [](Vec2f p) { return std::abs(p.x) > 1.6f || std::abs(p.y) > 1.6f; };
  for (const char* type : {"path", "whitted"}) {
    SceneDescription d = mediaScene(16, 64, type);
    d.media.push_back(boxMedium({-1.5f, -1.5f, -0.5f}, {1.5f, 1.5f, 0.5f}, sigmaA, {}));
    RenderScene scene = buildRenderScene(d);
    test::useUniformEnvironment(&scene, {1, 1, 1});
    const Film film = renderWith(scene, d.render);
    const Estimate in = average(film, inside), out = average(film, outside);
    ASSERT_GT(in.n, 50u);
    ASSERT_GT(out.n, 10u);
    for (int c = 0; c < 3; ++c) {
      const float exact = std::exp(-sigmaA[c]);
      EXPECT_NEAR(in.mean[c], exact, 4 * in.sigma[c] + 1e-5f) << type << " channel " << c;
      EXPECT_NEAR(out.mean[c], 1, 1e-6f) << type << " channel " << c;
    }
    if (std::string(type) == "path") {
      EXPECT_GT(in.sigma.x, 0) << "tracking is stochastic";
    }
  }
}

// An emitting, absorbing slab of thickness 1 with nothing behind it: Le / sigma_t
// (1 - exp(-sigma_t)), and Le where sigma_t = 0 (a channel, or a whole medium without
// extinction, which takes the majorant-0 branch).
TEST(PathVolume, EmittingSlabMatchesTheClosedForm) {
  const Rgb Le{2, 3, 4};
  auto inside = [](Vec2f p) { return std::abs(p.x) < 1.4f && std::abs(p.y) < 1.4f; };
  for (const Rgb sigmaA : {Rgb{0.5f, 1.0f, 2.0f}, Rgb{0, 1.0f, 2.0f}, Rgb{0, 0, 0}}) {
    for (const char* volume : {"multiple", "emission"}) {
      SceneDescription d = mediaScene(16, 64, "path");
      d.render.integrator.volume = volume;
      // In the emission mode scattering only extinguishes, so it joins sigma_t there.
      const bool emissionMode = std::string(volume) == "emission";
      const Rgb sigmaS = emissionMode ? sigmaA * 0.5f : Rgb{};
      d.media.push_back(boxMedium({-1.5f, -1.5f, -0.5f}, {1.5f, 1.5f, 0.5f}, sigmaA, sigmaS, Le));
      RenderScene scene = buildRenderScene(d);
      dropLights(&scene);
      const Film film = renderWith(scene, d.render);
      const Estimate in = average(film, inside);
      for (int c = 0; c < 3; ++c) {
        const float st = sigmaA[c] + sigmaS[c];
        const float exact = st > 0 ? Le[c] / st * -std::expm1(-st) : Le[c];
        EXPECT_NEAR(in.mean[c], exact, 4 * in.sigma[c] + 1e-5f * exact)
            << volume << " sigma_a " << sigmaA[c] << " channel " << c;
      }
    }
  }
}

// The medium furnace: under an environment of radiance 1, a medium whose emission per unit
// length equals its absorption coefficient (Le = sigma_a, the same density field scaling both)
// keeps radiance 1 everywhere: L = 1 solves the transfer equation, dL/ds = -sigma_t L + sigma_s
// L + sigma_a = 0. Albedo 1 without emission is the classic case. Any scattering order that is
// lost, any wrong MIS weight between phase and light sampling, or a biased tracking weight
// shows as a mean different from 1.
TEST(PathVolume, MediumFurnaceKeepsRadianceOne) {
  struct Case {
    const char* name;
    Rgb sigmaA, sigmaS;
    float g;
    bool noise;
  };
  const Case cases[] = {
      {"albedo 1", {0, 0, 0}, {2, 2, 2}, 0.0f, false},
      {"albedo 1, forward", {0, 0, 0}, {2, 2, 2}, 0.7f, false},
      {"chromatic, emitting", {0.2f, 0.6f, 1.2f}, {1.5f, 1.0f, 0.5f}, -0.4f, false},
      {"noise density, emitting", {0.5f, 0.5f, 0.5f}, {2.0f, 1.0f, 1.5f}, 0.3f, true},
  };
  for (const Case& k : cases) {
    SceneDescription d = mediaScene(16, 256, "path", 1000);
    MediumDesc m = sphereMedium(1.5f, k.sigmaA, k.sigmaS, k.sigmaA, k.g);
    if (k.noise) {
      m.density = DensityType::Noise;
      m.noiseScale = 1.5f;
      m.noiseThreshold = 0.2f;
    }
    d.media.push_back(m);
    RenderScene scene = buildRenderScene(d);
    test::useUniformEnvironment(&scene, {1, 1, 1});
    const Film film = renderWith(scene, d.render);
    const Estimate all = averageAll(film);
    const Estimate centre = average(film, [](Vec2f p) { return p.x * p.x + p.y * p.y < 1.44f; });
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(all.mean[c], 1, 4 * all.sigma[c] + 1e-5f) << k.name << " channel " << c;
      EXPECT_NEAR(centre.mean[c], 1, 4 * centre.sigma[c] + 1e-5f) << k.name << " channel " << c;
    }
    EXPECT_GT(centre.sigma.y, 1e-4f) << k.name << ": the medium scatters";
  }
}

// Albedo < 1 without emission: between the unscattered transmittance (the "emission" mode,
// which scatters nothing) and 1.
TEST(PathVolume, AbsorbingFurnaceLiesBetweenTransmittanceAndOne) {
  auto render = [](const char* volume) {
    SceneDescription d = mediaScene(16, 64, "path", 1000);
    d.render.integrator.volume = volume;
    d.media.push_back(sphereMedium(1.5f, {0.5f, 0.5f, 0.5f}, {1.5f, 1.5f, 1.5f}));
    RenderScene scene = buildRenderScene(d);
    test::useUniformEnvironment(&scene, {1, 1, 1});
    return average(renderWith(scene, d.render),
                   [](Vec2f p) { return p.x * p.x + p.y * p.y < 1.44f; });
  };
  const Estimate unscattered = render("emission"), full = render("multiple");
  EXPECT_GT(full.mean.y, unscattered.mean.y + 4 * (full.sigma.y + unscattered.sigma.y));
  EXPECT_LT(full.mean.y, 1 - 4 * full.sigma.y);
}

// ---------------------------------------------------------------------------------------------
// Single and multiple scattering
// ---------------------------------------------------------------------------------------------

// Fog in the box [-1, 1]^3 lit by a point light above it (volume_test's lit medium).
SceneDescription litFog(int spp, const std::string& integrator, int maxDepth, float albedo,
                        float sigmaT = 0.7f) {
  SceneDescription d = mediaScene(16, spp, integrator, maxDepth);
  d.lights.push_back(pointLight({0.3f, 2, 0}, 10));
  const float ss = albedo * sigmaT, sa = sigmaT - ss;
  d.media.push_back(boxMedium({-1, -1, -1}, {1, 1, 1}, {sa, sa, sa}, {ss, ss, ss}, {}, 0.3f));
  return d;
}

// max_depth 1 leaves one scattering event with its light sample: Whitted's single scattering
// (tracked: unbiased too). Both means over the image agree within their standard errors; with
// a wall behind the fog, also the direct light on the wall, whose shadow rays cross the fog.
TEST(PathVolume, MaxDepthOneIsWhittedsSingleScattering) {
  for (bool wall : {false, true}) {
    SceneDescription p = litFog(512, "path", 1, 0.7f);
    if (wall) {
      MaterialDesc grey;
      grey.name = "grey";
      grey.type = MaterialType::Lambert;
      grey.baseColor = {0.6f, 0.6f, 0.6f};
      p.materials.push_back(grey);
      MeshDesc quad;
      quad.name = "wall";
      quad.positions = {{-3, -3, -1.5f}, {3, -3, -1.5f}, {3, 3, -1.5f}, {-3, 3, -1.5f}};
      quad.normals.assign(4, {0, 0, 1});
      quad.indices = {0, 1, 2, 0, 2, 3};
      quad.material = 0;
      p.meshes.push_back(quad);
      p.instances.push_back({1, Transform(), "wall", {}});
    }
    SceneDescription w = p;
    w.render.integrator.type = "whitted";
    w.render.integrator.volumeEstimator = "track";
    const Estimate path = averageAll(renderWith(buildRenderScene(p), p.render));
    const Estimate whitted = averageAll(renderWith(buildRenderScene(w), w.render));
    ASSERT_GT(whitted.mean.y, 0.01f);
    EXPECT_NEAR(path.mean.y, whitted.mean.y,
                4 * std::sqrt(path.sigma.y * path.sigma.y + whitted.sigma.y * whitted.sigma.y))
        << (wall ? "wall" : "fog only");
    std::printf(
        "[ fog     ] single scattering%s: path (max_depth 1) %.5f +- %.5f, "
        "whitted %.5f +- %.5f\n",
        wall ? " + wall" : "", path.mean.y, path.sigma.y, whitted.mean.y, whitted.sigma.y);
  }
}

// Multiple scattering adds light to single scattering, more the higher the albedo.
TEST(PathVolume, MultipleScatteringAddsMoreAtHigherAlbedo) {
  float lastGain = 0;
  for (float albedo : {0.3f, 0.6f, 0.9f}) {
    SceneDescription s = litFog(1024, "path", 1, albedo, 1.5f);
    SceneDescription m = litFog(1024, "path", 64, albedo, 1.5f);
    const Estimate single = averageAll(renderWith(buildRenderScene(s), s.render));
    const Estimate multiple = averageAll(renderWith(buildRenderScene(m), m.render));
    const float sigma =
        std::sqrt(single.sigma.y * single.sigma.y + multiple.sigma.y * multiple.sigma.y);
    EXPECT_GT(multiple.mean.y, single.mean.y + 4 * sigma) << "albedo " << albedo;
    const float gain = multiple.mean.y / single.mean.y;
    EXPECT_GT(gain, lastGain) << "albedo " << albedo;
    lastGain = gain;
    std::printf("[ fog     ] albedo %.1f: single %.5f +- %.5f, multiple %.5f +- %.5f (x%.3f)\n",
                albedo, single.mean.y, single.sigma.y, multiple.mean.y, multiple.sigma.y, gain);
  }
}

// ---------------------------------------------------------------------------------------------
// Determinism and numerics
// ---------------------------------------------------------------------------------------------

// A Lambert sphere in noise fog under an environment and a point light.
SceneDescription busyFog(int size, int spp) {
  SceneDescription d = mediaScene(size, spp, "path", 8);
  d.render.integrator.rrDepth = 2;
  MaterialDesc white;
  white.name = "white";
  white.type = MaterialType::Lambert;
  white.baseColor = {0.7f, 0.6f, 0.5f};
  d.materials.push_back(white);
  ObjectDesc ball;
  ball.name = "ball";
  ball.shape = std::make_shared<Sphere>(Vec3f{0.3f, -0.2f, 0}, 0.7f);
  ball.material = 0;
  d.objects.push_back(ball);
  d.lights.push_back(pointLight({0.5f, 2.5f, 1}, 8));
  MediumDesc fog = boxMedium({-2, -2, -2}, {2, 2, 2}, {0.1f, 0.2f, 0.3f}, {0.8f, 0.6f, 0.4f},
                             {0.05f, 0.02f, 0.0f}, 0.5f);
  fog.density = DensityType::Noise;
  fog.noiseScale = 1.2f;
  d.media.push_back(fog);
  return d;
}

TEST(PathVolume, ImageIsIdenticalForOneAndTwoThreads) {
  SceneDescription d = busyFog(20, 4);
  d.render.aovs = true;
  RenderScene scene = buildRenderScene(d);
  const Film one = renderWith(scene, d.render, 1, 16);
  const Film two = renderWith(scene, d.render, 2, 7);
  ASSERT_EQ(one.color.size(), two.color.size());
  size_t lit = 0, surface = 0;
  for (size_t i = 0; i < one.color.size(); ++i) {
    ASSERT_EQ(one.color[i], two.color[i]) << "pixel " << i;
    ASSERT_EQ(one.variance[i], two.variance[i]) << "pixel " << i;
    ASSERT_EQ(one.albedo[i], two.albedo[i]) << "pixel " << i;
    lit += one.color[i].y > 0;
    surface += one.albedo[i].y > 0;
  }
  EXPECT_GT(lit, one.color.size() / 2);
  // AOVs are the ball's, seen through the fog.
  EXPECT_GT(surface, one.color.size() / 10);
}

TEST(PathVolume, DensityZeroAndStrongAnisotropyProduceNoNonFiniteSamples) {
  // Density 0 everywhere: a constant and a grid box, and the whole scene.
  {
    SceneDescription d = busyFog(16, 4);
    d.media.clear();
    MediumDesc grid = boxMedium({-2, -2, -2}, {2, 2, 2}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1});
    grid.density = DensityType::Grid;
    grid.gridRes[0] = grid.gridRes[1] = grid.gridRes[2] = 2;
    grid.gridValues.assign(8, 0.0f);
    d.media.push_back(grid);
    MediumDesc zero = boxMedium({-1, -1, -1}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1});
    zero.value = 0;
    d.media.push_back(zero);
    zero.region = MediumDesc::Region::Scene;
    d.media.push_back(zero);
    SceneDescription clear = d;
    clear.media.clear();
    RenderStats stats;
    const Film f = renderWith(buildRenderScene(d), d.render, 2, 16, &stats);
    EXPECT_EQ(stats.nonfiniteSamples, 0u);
    const Film ref = renderWith(buildRenderScene(clear), clear.render);
    for (size_t i = 0; i < f.color.size(); ++i) ASSERT_TRUE(isFinite(f.color[i])) << i;
    // Nothing absorbs, emits or scatters: the same image as without media, in the mean.
    const Estimate a = averageAll(f), b = averageAll(ref);
    EXPECT_NEAR(a.mean.y, b.mean.y, 4 * std::sqrt(a.sigma.y * a.sigma.y + b.sigma.y * b.sigma.y));
    EXPECT_GT(a.mean.y, 0.002f);
  }
  // Nearly specular phase functions, forwards and backwards, with both light kinds.
  for (float g : {0.95f, -0.95f}) {
    SceneDescription d = busyFog(16, 8);
    d.media.back().g = g;
    RenderScene scene = buildRenderScene(d);
    scene.addLight(std::make_unique<UniformEnvironmentLight>(Rgb{0.5f, 0.5f, 0.5f}));
    scene.setLightSampler("power");
    RenderStats stats;
    const Film f = renderWith(scene, d.render, 2, 16, &stats);
    EXPECT_EQ(stats.nonfiniteSamples, 0u) << "g " << g;
    size_t lit = 0;
    for (size_t i = 0; i < f.color.size(); ++i) {
      ASSERT_TRUE(isFinite(f.color[i])) << "g " << g << " pixel " << i;
      ASSERT_TRUE(isFinite(f.variance[i])) << "g " << g << " pixel " << i;
      lit += f.color[i].y > 0;
    }
    EXPECT_GT(lit, f.color.size() / 2) << "g " << g;
  }
}

}  // namespace
}  // namespace glint
