// Instant radiosity tests: agreement with the path tracer on a closed Cornell-style box
// (unclamped), clamping only ever darkens, more light paths mean less error, determinism
// across thread counts, VPLs at the shading point, the vectorised Lambert loop against the
// general evaluation, and the sidecar's validation.
#include "renderer/instant_radiosity.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "renderer/render.h"
#include "scene_error_support.h"
#include "scenes/build.h"
#include "scenes/sidecar.h"
#include "test_support.h"

namespace glint {
namespace {

// ---------------------------------------------------------------------------------------------
// The box (test::cornellBoxJson) and its integrator settings
// ---------------------------------------------------------------------------------------------

std::string irSettings(int paths, float clamp, int maxDepth = 6, float shadowShare = 1.0f / 16) {
  return R"({"type": "instant-radiosity", "vpl_paths": )" + std::to_string(paths) +
         R"(, "vpl_clamp": )" + std::to_string(clamp) + R"(, "max_depth": )" +
         std::to_string(maxDepth) + R"(, "vpl_shadow_share": )" + std::to_string(shadowShare) + "}";
}

std::string pathSettings(int maxDepth = 6) {
  return R"({"type": "path", "max_depth": )" + std::to_string(maxDepth) + "}";
}

SceneDescription describe(const std::string& json) {
  SceneDescription d;
  d.file = "scene.json";
  applySceneJsonText(json, d.file, SceneJsonKind::Scene, &d);
  return d;
}

struct Rendered {
  Film film;
  RenderStats stats;
};
Rendered renderWith(const std::string& json, int threads = 2, int tileSize = 16) {
  const SceneDescription d = describe(json);
  const RenderScene scene = buildRenderScene(d);
  auto integrator = makeIntegrator(scene, d.render);
  Rendered r;
  RenderOptions options;
  options.threads = threads;
  options.tileSize = tileSize;
  r.film = render(scene, *integrator, d.render, options, &r.stats);
  return r;
}

// The mean of one channel over the pixels of a rectangle, and its standard error from the
// film's per-pixel variance of the mean (pixels are independent).
struct Estimate {
  double mean = 0, sigma = 0;
};
Estimate regionMean(const Film& film, int x0, int y0, int x1, int y1, int channel) {
  double sum = 0, var = 0;
  int n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      sum += film.color[film.index(x, y)][channel];
      var += film.variance[film.index(x, y)][channel];
      ++n;
    }
  return {sum / n, std::sqrt(var) / n};
}

// Root-mean-square difference of the luminance-like green channel of two films.
double rmse(const Film& a, const Film& b) {
  double s = 0;
  for (size_t i = 0; i < a.color.size(); ++i) {
    const double d = double(a.color[i].y) - b.color[i].y;
    s += d * d;
  }
  return std::sqrt(s / double(a.color.size()));
}

// ---------------------------------------------------------------------------------------------
// Agreement with the path tracer
// ---------------------------------------------------------------------------------------------

// Unclamped instant radiosity estimates the same integral as the path tracer (paths of up to
// max_depth bounces, Russian roulette on both sides). The VPL set is a randomised
// quasi-Monte Carlo estimate: each seed scrambles the Halton digits afresh, so the renders of
// K seeds are K independent unbiased estimates and their spread measures the VPL error. Every
// region (the image, its quadrants, and per channel) must agree within 4 standard errors of
// the two estimates combined, plus 1% for what 5 seeds leave uncertain in the spread itself.
TEST(InstantRadiosity, UnclampedConvergesToThePathTracer) {
  const int size = 16, seeds = 5;
  const Rendered reference = renderWith(test::cornellBoxJson(size, 2048, 1, pathSettings()));
  EXPECT_EQ(reference.stats.nonfiniteSamples, 0u);
  std::vector<Film> ir;
  for (int s = 0; s < seeds; ++s) {
    Rendered r = renderWith(test::cornellBoxJson(size, 16, 10 + s, irSettings(1024, 0)));
    EXPECT_EQ(r.stats.nonfiniteSamples, 0u);
    ir.push_back(std::move(r.film));
  }
  struct Region {
    int x0, y0, x1, y1;
  };
  const int h = size / 2;
  for (Region g : {Region{0, 0, size, size}, Region{0, 0, h, h}, Region{h, 0, size, h},
                   Region{0, h, h, size}, Region{h, h, size, size}}) {
    for (int c = 0; c < 3; ++c) {
      const Estimate ref = regionMean(reference.film, g.x0, g.y0, g.x1, g.y1, c);
      double sum = 0, sumSq = 0;
      for (const Film& f : ir) {
        const double m = regionMean(f, g.x0, g.y0, g.x1, g.y1, c).mean;
        sum += m, sumSq += m * m;
      }
      const double mean = sum / seeds;
      const double spread = std::sqrt(std::max(0.0, (sumSq - sum * mean) / (seeds - 1)));
      const double sigma = std::sqrt(ref.sigma * ref.sigma + spread * spread / seeds);
      EXPECT_NEAR(mean, ref.mean, 4 * sigma + 0.01 * ref.mean)
          << "region " << g.x0 << "," << g.y0 << " channel " << c << " spread " << spread
          << " path sigma " << ref.sigma;
      EXPECT_GT(ref.mean, 0.05) << "the region is lit";
    }
  }
}

// In an absorbing fog (no scattering, so nothing is missing from instant radiosity's model)
// the VPLs' light is attenuated along the light paths and the VPL shadow rays, and the image
// converges to the path tracer's, which is some 40% darker than the clear box.
TEST(InstantRadiosity, AbsorbingFogConvergesToThePathTracer) {
  const int size = 12, seeds = 3;
  auto foggy = [](const std::string& json) {
    nlohmann::json j = nlohmann::json::parse(json);
    j["media"] = nlohmann::json::array({{{"name", "haze"}, {"sigma_a", 0.35}}});
    return j.dump();
  };
  const Rendered reference = renderWith(foggy(test::cornellBoxJson(size, 2048, 1, pathSettings())));
  const Rendered clear = renderWith(test::cornellBoxJson(size, 256, 1, pathSettings()));
  std::vector<Film> ir;
  for (int s = 0; s < seeds; ++s) {
    Rendered r = renderWith(foggy(test::cornellBoxJson(size, 16, 20 + s, irSettings(512, 0))));
    EXPECT_EQ(r.stats.nonfiniteSamples, 0u);
    ir.push_back(std::move(r.film));
  }
  for (int c = 0; c < 3; ++c) {
    const Estimate ref = regionMean(reference.film, 0, 0, size, size, c);
    double sum = 0, sumSq = 0;
    for (const Film& f : ir) {
      const double m = regionMean(f, 0, 0, size, size, c).mean;
      sum += m, sumSq += m * m;
    }
    const double mean = sum / seeds;
    const double spread = std::sqrt(std::max(0.0, (sumSq - sum * mean) / (seeds - 1)));
    const double sigma = std::sqrt(ref.sigma * ref.sigma + spread * spread / seeds);
    EXPECT_NEAR(mean, ref.mean, 4 * sigma + 0.015 * ref.mean) << "channel " << c;
    // The fog matters: the clear box is far brighter than the error allowed above.
    EXPECT_GT(regionMean(clear.film, 0, 0, size, size, c).mean, 1.2 * ref.mean) << "channel " << c;
  }
}

// Doubling the light paths from 16 to 1024 brings the image closer to the path tracer's: the
// VPL error dominates at 16 paths (visible splotches), the camera samples' noise at 1024.
TEST(InstantRadiosity, MoreLightPathsMeanLessError) {
  const int size = 24;
  const Film reference = renderWith(test::cornellBoxJson(size, 1024, 1, pathSettings())).film;
  double previous = 1e30;
  for (int paths : {16, 128, 1024}) {
    const Film f = renderWith(test::cornellBoxJson(size, 16, 2, irSettings(paths, 0))).film;
    const double e = rmse(f, reference);
    EXPECT_LT(e, previous) << paths << " paths";
    previous = e;
  }
  // 1024 paths: within a few percent of the image's brightness (about 0.3).
  EXPECT_LT(previous, 0.03);
}

// ---------------------------------------------------------------------------------------------
// Clamping
// ---------------------------------------------------------------------------------------------

// The same seed gives the same VPLs and the same camera samples, and min(G, bound) <= G term by
// term (float addition and multiplication are monotone), so no pixel may get brighter. A bound
// of 2 (for a box of size 2: well below the walls' mutual G near the corners) must darken the
// image measurably, and stay below the path tracer: clamping only loses energy.
TEST(InstantRadiosity, ClampingNeverBrightensAPixel) {
  const int size = 24;
  // Every VPL gets its shadow ray (vpl_shadow_share 0): sampled shadow rays would add noise
  // that differs between the two renders.
  const Film unclamped =
      renderWith(test::cornellBoxJson(size, 4, 3, irSettings(256, 0, 6, 0))).film;
  const Film clamped = renderWith(test::cornellBoxJson(size, 4, 3, irSettings(256, 2, 6, 0))).film;
  double sumU = 0, sumC = 0;
  size_t darker = 0;
  for (size_t i = 0; i < unclamped.color.size(); ++i) {
    for (int c = 0; c < 3; ++c)
      ASSERT_LE(clamped.color[i][c], unclamped.color[i][c] * (1 + 1e-6f) + 1e-7f) << "pixel " << i;
    darker += clamped.color[i].y < unclamped.color[i].y;
    sumU += unclamped.color[i].y, sumC += clamped.color[i].y;
  }
  EXPECT_GT(darker, unclamped.color.size() / 2);
  EXPECT_LT(sumC, 0.99 * sumU);
}

// ---------------------------------------------------------------------------------------------
// Determinism and numerics
// ---------------------------------------------------------------------------------------------

// Shadow rays by importance (vpl_shadow_share): with the same VPL set, testing only the VPLs
// that matter and sampling the rest is unbiased. Every region and channel agrees with the
// render that tests every VPL within 4 standard errors of the two (the films' own per-pixel
// variances, which include the selection's noise), with far fewer shadow rays.
TEST(InstantRadiosity, ShadowRaysByImportanceAreUnbiasedAndFewer) {
  const int size = 16;
  const Rendered all = renderWith(test::cornellBoxJson(size, 64, 3, irSettings(256, 0, 6, 0)));
  const Rendered picked =
      renderWith(test::cornellBoxJson(size, 64, 3, irSettings(256, 0, 6, 0.25f)));
  EXPECT_LT(double(picked.stats.rays.shadow), 0.6 * double(all.stats.rays.shadow));
  EXPECT_GT(picked.stats.rays.shadow, 0u);
  const int h = size / 2;
  for (int y0 : {0, h})
    for (int x0 : {0, h})
      for (int c = 0; c < 3; ++c) {
        const Estimate a = regionMean(all.film, x0, y0, x0 + h, y0 + h, c);
        const Estimate b = regionMean(picked.film, x0, y0, x0 + h, y0 + h, c);
        EXPECT_NEAR(b.mean, a.mean, 4 * std::sqrt(a.sigma * a.sigma + b.sigma * b.sigma) + 1e-6)
            << "region " << x0 << "," << y0 << " channel " << c;
        EXPECT_GT(a.mean, 0.02) << "the region is lit";
      }
}

TEST(InstantRadiosity, ImageIsIdenticalForOneAndTwoThreads) {
  const std::string json = test::cornellBoxJson(20, 4, 9, irSettings(64, 0));
  const Rendered one = renderWith(json, 1, 16);
  const Rendered two = renderWith(json, 2, 7);
  ASSERT_EQ(one.film.color.size(), two.film.color.size());
  for (size_t i = 0; i < one.film.color.size(); ++i) {
    ASSERT_EQ(one.film.color[i], two.film.color[i]) << "pixel " << i;
    ASSERT_EQ(one.film.variance[i], two.film.variance[i]) << "pixel " << i;
  }
  EXPECT_EQ(one.stats.rays.shadow, two.stats.rays.shadow);
}

TEST(InstantRadiosity, VplSetDependsOnlyOnTheSeed) {
  const SceneDescription d = describe(test::cornellBoxJson(8, 1, 4, irSettings(100, 0)));
  const RenderScene scene = buildRenderScene(d);
  const InstantRadiosityIntegrator a(scene, d.render.integrator, 4),
      b(scene, d.render.integrator, 4), c(scene, d.render.integrator, 5);
  ASSERT_EQ(a.vpls().size(), b.vpls().size());
  // More VPLs than paths: the paths bounce (albedo 0.7, roulette from bounce 3).
  EXPECT_GT(a.vpls().size(), 150u);
  for (size_t i = 0; i < a.vpls().size(); ++i) {
    ASSERT_EQ(a.vpls()[i].si.p, b.vpls()[i].si.p);
    ASSERT_EQ(a.vpls()[i].flux, b.vpls()[i].flux);
  }
  EXPECT_NE(a.vpls()[0].si.p, c.vpls()[0].si.p) << "another seed, another scramble";
  // Total flux of first-bounce VPLs: everything the light emits lands on a wall (closed box).
  // The one-sided quad light emits phi = pi L A, and cosine-sampled light rays each carry
  // exactly phi / paths.
  double first = 0;
  for (const Vpl& v : a.vpls()) first += v.vertex == 1 ? v.flux.y : 0;
  const double phi = kPi * 10 * 0.36;
  EXPECT_NEAR(first, phi, 1e-4 * phi);
}

// The scrambled radical inverse stays in [0, 1) and stratifies: the first b^k points of base b
// fall one in each interval [j / b^k, (j + 1) / b^k).
TEST(InstantRadiosity, ScrambledHaltonIsStratified) {
  for (uint32_t base : {2u, 3u, 7u}) {
    const uint32_t n = base * base * base;
    std::vector<int> bins(n, 0);
    for (uint64_t i = 0; i < n; ++i) {
      const float v = scrambledRadicalInverse(base, i, 12345 + base);
      ASSERT_GE(v, 0.0f);
      ASSERT_LT(v, 1.0f);
      ++bins[std::min<size_t>(n - 1, size_t(v * n))];
    }
    for (uint32_t j = 0; j < n; ++j) EXPECT_EQ(bins[j], 1) << "base " << base << " bin " << j;
  }
}

// Rays aimed straight at VPLs put shading points on (or within rounding of) them: d -> 0,
// where G = cos cos / d^2 is 0/0 or huge. No radiance may come out non-finite, and the
// provocation must actually happen (some hits land within the error bound of a VPL).
TEST(InstantRadiosity, VplAtTheShadingPointGivesNoNonFiniteRadiance) {
  const SceneDescription d = describe(test::cornellBoxJson(8, 1, 4, irSettings(64, 0)));
  const RenderScene scene = buildRenderScene(d);
  const InstantRadiosityIntegrator ir(scene, d.render.integrator, 4);
  ASSERT_FALSE(ir.vpls().empty());
  size_t onTop = 0;
  for (size_t i = 0; i < ir.vpls().size(); ++i) {
    const SurfaceInteraction& v = ir.vpls()[i].si;
    const Ray ray{v.p + v.ng * 0.25f, -v.ng, 0, kInfinity, 0};
    Hit hit;
    ASSERT_TRUE(scene.accel().closestHit(ray, &hit));
    const SurfaceInteraction si =
        computeSurfaceInteraction(scene.geometry(), ray, hit, {.position = true});
    onTop += length(si.p - v.p) <= length(si.pError) + length(v.pError);
    Sampler sampler(pixelSampleKey(1, i), 0, kIntegratorDimension);
    RayCounters counters;
    PathAovs aovs;
    const Rgb L = ir.Li(ray, sampler, counters, aovs);
    ASSERT_TRUE(isFinite(L)) << "VPL " << i;
    ASSERT_GE(std::min({L.x, L.y, L.z}), 0.0f) << "VPL " << i;
  }
  EXPECT_GT(onTop, ir.vpls().size() / 4) << "the test provokes d -> 0";
  // And a whole render of the box, whose corners hold VPLs a hair from other walls.
  const Rendered r = renderWith(test::cornellBoxJson(16, 4, 4, irSettings(256, 0)));
  EXPECT_EQ(r.stats.nonfiniteSamples, 0u);
  for (const Rgb& c : r.film.color) ASSERT_TRUE(isFinite(c));
}

// The vectorised loop for Lambert gather points and VPLs (lambertVplContributions) claims the
// exact values of the general evaluation: Bsdf::f at both ends, the same G, the same tests.
// Random points and normals in a box, half of the BSDFs with a perturbed shading normal (the
// terminator term), some VPLs on the gather point itself, with and without the G bound.
TEST(InstantRadiosity, LambertVplLoopGivesTheGeneralEvaluationsValues) {
  std::mt19937 rng(27);
  std::uniform_real_distribution<float> u(-1, 1);
  auto direction = [&] {
    Vec3f v;
    do v = {u(rng), u(rng), u(rng)};
    while (!(lengthSquared(v) > 0.01f && lengthSquared(v) <= 1));
    return normalize(v);
  };
  // A Lambert point at p, its shading normal tilted from the geometric one where `perturbed`.
  auto surface = [&](Vec3f p, bool perturbed, Rgb R, Vpl* out) {
    out->si.p = p;
    out->si.pError = Vec3f{1, 1, 1} * 1e-6f;
    out->si.ng = direction();
    out->si.ns = perturbed ? normalize(out->si.ng + direction() * 0.4f) : out->si.ng;
    if (dot(out->si.ns, out->si.ng) < 0) out->si.ns = -out->si.ns;
    out->si.wo = direction();
    if (dot(out->si.wo, out->si.ng) < 0) out->si.wo = -out->si.wo;
    out->bsdf = Bsdf(out->si, perturbed, [&](Bsdf* b) { b->emplace<DiffuseBxdf>(R); });
  };
  size_t lit = 0, dark = 0, atThePoint = 0;
  for (int gatherIndex = 0; gatherIndex < 64; ++gatherIndex) {
    Vpl gather;
    const Vec3f x{u(rng), u(rng), u(rng)};
    surface(x, gatherIndex % 2 == 1, {0.7f, 0.5f, 0.3f}, &gather);
    VplArrays arrays;
    std::vector<Vpl> vpls(200);
    for (size_t k = 0; k < vpls.size(); ++k) {
      // Every 25th VPL on the gather point as rounding sees it (within the error bounds),
      // every 50th exactly on it.
      const Vec3f p = k % 50 == 0   ? x
                      : k % 25 == 0 ? x + direction() * 1e-6f
                                    : Vec3f{u(rng), u(rng), u(rng)};
      surface(p, k % 2 == 0, {0.2f + 0.5f * (u(rng) + 1) / 2, 0.6f, 0.1f}, &vpls[k]);
      vpls[k].flux = Rgb{1.5f, 0.75f, 0.25f} * ((u(rng) + 2) / 2);
      arrays.add(vpls[k]);
    }
    for (const float clamp : {0.0f, 2.0f}) {
      const std::optional<LambertGatherPoint> q =
          LambertGatherPoint::at(gather.si, gather.bsdf, clamp);
      ASSERT_TRUE(q.has_value());
      std::vector<float> r(vpls.size()), g(vpls.size()), b(vpls.size());
      lambertVplContributions(arrays, *q, r.data(), g.data(), b.data());
      for (size_t k = 0; k < vpls.size(); ++k) {
        const Vpl& v = vpls[k];
        Rgb expected;
        const Vec3f d = v.si.p - gather.si.p;
        const float dist2 = dot(d, d), dist = std::sqrt(dist2);
        if (dist > length(gather.si.pError) + length(v.si.pError) && dist2 > 0) {
          const Vec3f wi = d / dist;
          const Rgb f = gather.bsdf.f(wi), fVpl = v.bsdf.f(-wi);
          if (maxComponent(f) > 0 && maxComponent(fVpl) > 0) {
            float G = std::abs(dot(gather.si.ns, wi)) * std::abs(dot(v.si.ns, wi)) / dist2;
            if (clamp > 0) G = std::min(G, clamp);
            expected = f * fVpl * v.flux * G;
          }
        } else {
          ++atThePoint;
        }
        ASSERT_EQ(r[k], expected.x) << "gather point " << gatherIndex << ", VPL " << k;
        ASSERT_EQ(g[k], expected.y) << "gather point " << gatherIndex << ", VPL " << k;
        ASSERT_EQ(b[k], expected.z) << "gather point " << gatherIndex << ", VPL " << k;
        ++(maxComponent(expected) > 0 ? lit : dark);
      }
    }
  }
  // Not vacuous: both outcomes, and VPLs on the point, occur often.
  EXPECT_GT(lit, 2000u);
  EXPECT_GT(dark, 2000u);
  EXPECT_GE(atThePoint, 64u * 2 * 8);
}

// ---------------------------------------------------------------------------------------------
// Settings and the factory
// ---------------------------------------------------------------------------------------------

TEST(InstantRadiosity, SidecarRejectsNonPositivePathCounts) {
  for (const char* paths : {"0", "-3"}) {
    const std::string json = R"({"render": {"integrator": {"type": "instant-radiosity",
                                 "vpl_paths": )" +
                             std::string(paths) + "}}}";
    SceneDescription d;
    EXPECT_SCENE_ERROR(
        test::errorFrom([&] { applySceneJsonText(json, "scene.json", SceneJsonKind::Scene, &d); }),
        "scene.json", "/render/integrator/vpl_paths", "> 0");
  }
  SceneDescription d;
  EXPECT_SCENE_ERROR(test::errorFrom([&] {
                       applySceneJsonText(R"({"render": {"integrator": {"vpl_clamp": -1}}})",
                                          "scene.json", SceneJsonKind::Scene, &d);
                     }),
                     "scene.json", "/render/integrator/vpl_clamp", ">= 0");
}

TEST(InstantRadiosity, FactoryBuildsItAndAutoNeverPicksIt) {
  SceneDescription d = describe(test::cornellBoxJson(8, 1, 4, irSettings(8, 0)));
  const RenderScene scene = buildRenderScene(d);
  EXPECT_TRUE(scene.features().has(Feature::Vpls));
  EXPECT_TRUE(scene.features().has(Feature::Indirect));
  EXPECT_NE(dynamic_cast<InstantRadiosityIntegrator*>(makeIntegrator(scene, d.render).get()),
            nullptr);
  d.render.integrator.type = "auto";
  const RenderScene autoScene = buildRenderScene(d);
  EXPECT_EQ(resolveIntegrator(autoScene, d.render.integrator), IntegratorKind::Path);
  EXPECT_FALSE(autoScene.features().has(Feature::Vpls));
  const auto& names = integratorNames();
  EXPECT_NE(std::find(names.begin(), names.end(), "instant-radiosity"), names.end());
  EXPECT_EQ(names.back(), "auto");
}

TEST(InstantRadiosity, MaxDepthOneIsDirectLightOnly) {
  // No VPL can stay within one bounce: the image is Whitted's direct light.
  const SceneDescription d = describe(test::cornellBoxJson(12, 4, 4, irSettings(64, 0, 1), true));
  const RenderScene scene = buildRenderScene(d);
  const InstantRadiosityIntegrator ir(scene, d.render.integrator, 4);
  EXPECT_TRUE(ir.vpls().empty());
  SceneDescription w = d;
  w.render.integrator.type = "whitted";
  const Film a = render(scene, ir, d.render, {.threads = 2}, nullptr);
  const Film b = render(scene, *makeIntegrator(scene, w.render), w.render, {.threads = 2}, nullptr);
  for (size_t i = 0; i < a.color.size(); ++i) ASSERT_EQ(a.color[i], b.color[i]) << "pixel " << i;
}

}  // namespace
}  // namespace glint
