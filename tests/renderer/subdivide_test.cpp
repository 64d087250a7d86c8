// Tests for anti-aliasing by recursive subdivision (renderer/subdivide.h): a pixel is the
// trapezoid rule over the lattice squares its contrast cut, its corner looks are shared, the
// image does not depend on threads, tiles or crops, and its cuts buy accuracy where a whole-
// pixel sample would not.
#include "renderer/subdivide.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <string>

#include "renderer/render.h"
#include "scene_error_support.h"
#include "scenes/build.h"
#include "scenes/sidecar.h"
#include "test_support.h"

namespace glint {
namespace {

// A noise-free (Whitted, point light) scene: a ball and a block on a checker-free floor in
// front of a grey background. Every look is exact, so a pixel's error is its edges' alone. (Not
// the test Cornell box: seen from its axis, its seams run through lattice points, where a
// packet of rays and a single ray may report either of the two walls that meet there.)
std::string sceneJson(int width, int height, const std::string& lens = "") {
  return R"({
    "render": {"width": )" +
         std::to_string(width) + R"(, "height": )" + std::to_string(height) +
         R"(, "seed": 3, "camera": "c", "integrator": {"type": "whitted"},
               "background": [0.3, 0.35, 0.4]},
    "cameras": [{"name": "c", "position": [0.13, 1.07, 3.1], "look_at": [0.05, 0.45, 0],
                 "yfov_degrees": 40)" +
         lens + R"(}],
    "lights": [{"type": "point", "position": [1.3, 3.1, 2.2], "intensity": 12}],
    "materials": [{"name": "floor", "type": "lambert", "diffuse": [0.6, 0.6, 0.55]},
                  {"name": "red", "type": "lambert", "diffuse": [0.7, 0.12, 0.1]},
                  {"name": "blue", "type": "lambert", "diffuse": [0.15, 0.2, 0.7]}],
    "objects": [
      {"type": "quad", "corner": [-3, 0, -3], "edge_u": [0, 0, 6], "edge_v": [6, 0, 0], "material": "floor"},
      {"type": "box", "min": [-0.9, 0, -0.7], "max": [-0.3, 0.8, -0.1], "material": "blue"},
      {"type": "sphere", "center": [0.45, 0.4, 0.1], "radius": 0.4, "material": "red"}]})";
}

struct Stage {
  SceneDescription desc;
  RenderScene scene;
  std::unique_ptr<Integrator> integrator;
  explicit Stage(int width = 40, int height = 30, const std::string& lens = "") {
    desc.file = "subdivide_test (in code)";
    applySceneJsonText(sceneJson(width, height, lens), desc.file, SceneJsonKind::Scene, &desc);
    scene = buildRenderScene(desc);
    integrator = makeIntegrator(scene, desc.render);
  }
  Film render(float contrast, int levels, RenderOptions options = {.threads = 2},
              RenderStats* stats = nullptr, float jitter = 1) const {
    RenderSettings settings = desc.render;
    settings.adaptive.contrast = contrast;
    settings.adaptive.subdivide = levels;
    settings.adaptive.jitter = jitter;
    return glint::render(scene, *integrator, settings, options, stats);
  }
  // The radiance through film point (x, y): the scene has no randomness, so any sampler does.
  Rgb look(float x, float y) const {
    Sampler sampler(0, 0, kIntegratorDimension);
    RayCounters counters;
    PathAovs aovs;
    return integrator->Li(scene.camera().pinholeRay({x, y}, 0), sampler, counters, aovs);
  }
};

void expectSameImage(const Film& a, const Film& b) {
  ASSERT_EQ(a.color.size(), b.color.size());
  for (size_t i = 0; i < a.color.size(); ++i) {
    ASSERT_EQ(a.color[i], b.color[i]) << "pixel " << i;
    ASSERT_EQ(a.variance[i], b.variance[i]) << "pixel " << i;
    ASSERT_EQ(a.samples[i], b.samples[i]) << "pixel " << i;
    ASSERT_EQ(a.alpha[i], b.alpha[i]) << "pixel " << i;
  }
}

void expectNear(Rgb a, Rgb b, const std::string& where) {
  for (int c = 0; c < 3; ++c)
    ASSERT_NEAR(a[c], b[c], 1e-5f * std::max(1.0f, std::abs(b[c]))) << where << " channel " << c;
}

// A contrast nothing reaches (x/(1+x) differs by less than 1) cuts no square: every pixel is
// the mean of its four corner looks, and each corner is traced once for the whole image.
// (Without jitter, so the looks are at the lattice points.)
TEST(Subdivision, AnUncutPixelIsTheMeanOfItsCornerLooks) {
  const Stage stage;
  RenderStats stats;
  const Film film = stage.render(1.0f, 3, {.threads = 2}, &stats, 0);
  ASSERT_EQ(film.width, 40);
  for (int y = 0; y < film.height; ++y)
    for (int x = 0; x < film.width; ++x) {
      const size_t i = film.index(x, y);
      ASSERT_EQ(film.samples[i], 4u);
      const float fx = float(x), fy = float(y);
      const Rgb mean = (stage.look(fx, fy) + stage.look(fx + 1, fy) + stage.look(fx, fy + 1) +
                        stage.look(fx + 1, fy + 1)) *
                       0.25f;
      expectNear(film.color[i], mean, std::to_string(x) + "," + std::to_string(y));
    }
  EXPECT_EQ(stats.rays.camera, 41u * 31u);
  EXPECT_DOUBLE_EQ(stats.meanSpp, 41.0 * 31.0 / (40.0 * 30.0));
}

// Contrast 0 cuts every square to the deepest level: each pixel is the trapezoid rule on its
// (2^levels + 1)² lattice points, and points on pixel borders are traced once.
TEST(Subdivision, ContrastZeroIsTheTrapezoidRuleOnTheWholeLattice) {
  const Stage stage(13, 10);
  RenderStats stats;
  const Film film = stage.render(0.0f, 2, {.threads = 2}, &stats, 0);
  for (int y = 0; y < film.height; ++y)
    for (int x = 0; x < film.width; ++x) {
      const size_t i = film.index(x, y);
      ASSERT_EQ(film.samples[i], 25u);
      Rgb sum;
      for (int j = 0; j <= 4; ++j)
        for (int k = 0; k <= 4; ++k) {
          // Trapezoid weights: 1 inside, 1/2 on an edge, 1/4 at a corner, over 16 squares.
          const float w = (j == 0 || j == 4 ? 0.5f : 1.0f) * (k == 0 || k == 4 ? 0.5f : 1.0f);
          sum += stage.look(float(x) + 0.25f * float(k), float(y) + 0.25f * float(j)) * (w / 16);
        }
      expectNear(film.color[i], sum, std::to_string(x) + "," + std::to_string(y));
    }
  // Shared corners: 53 x 41 lattice points; the corner rows and columns are each traced once,
  // and a tile traces the points inside its pixels once (one tile of 16 holds all 13 x 10).
  EXPECT_EQ(stats.rays.camera, 53u * 41u);
}

// Each look is keyed by its place in the whole image (its lens point too), so the image is the
// same on any thread count and tile size, and a crop's pixels are the whole frame's.
TEST(Subdivision, TheImageDoesNotDependOnThreadsTilesOrCrops) {
  for (const std::string lens : {"", R"(, "aperture": 0.08, "focus_distance": 2.2)"}) {
    SCOPED_TRACE(lens);
    const Stage stage(40, 30, lens);
    const Film film = stage.render(0.05f, 3);
    expectSameImage(stage.render(0.05f, 3, {.threads = 1, .tileSize = 7}), film);
    expectSameImage(stage.render(0.05f, 3, {.threads = 3, .tileSize = 64}), film);
    for (PixelWindow crop :
         {PixelWindow{7, 5, 23, 29}, PixelWindow{0, 20, 40, 27}, PixelWindow{31, 22, 40, 30}}) {
      RenderOptions options{.threads = 2};
      options.crop = crop;
      const Film part = stage.render(0.05f, 3, options);
      ASSERT_EQ(part.width, crop.width());
      ASSERT_EQ(part.originX, crop.x0);
      for (int y = crop.y0; y < crop.y1; ++y)
        for (int x = crop.x0; x < crop.x1; ++x) {
          const size_t i = part.index(x - crop.x0, y - crop.y0), j = film.index(x, y);
          ASSERT_EQ(part.color[i], film.color[j]) << x << "," << y;
          ASSERT_EQ(part.samples[i], film.samples[j]) << x << "," << y;
        }
    }
  }
}

double rmse(const Film& a, const Film& b) {
  double sum = 0;
  for (size_t i = 0; i < a.color.size(); ++i)
    for (int c = 0; c < 3; ++c)
      sum += double(a.color[i][c] - b.color[i][c]) * (a.color[i][c] - b.color[i][c]);
  return std::sqrt(sum / (3.0 * double(a.color.size())));
}

// The cuts go where the contrast is, and buy accuracy there: against the pixel integrals (a
// 1,024-sample box-filter render), two levels reach a lower error than 4 whole-pixel samples
// with fewer camera rays, a third level lowers it further, and jittered looks more than looks
// on the lattice points.
TEST(Subdivision, CutsGoToEdgesAndBeatWholePixelSamples) {
  const Stage stage;
  RenderSettings settings = stage.desc.render;
  settings.filter = {"box", 0.5f};
  settings.spp = 1024;
  const Film reference = render(stage.scene, *stage.integrator, settings, {.threads = 2}, nullptr);
  settings.spp = 4;
  RenderStats plainStats;
  const Film plain = render(stage.scene, *stage.integrator, settings, {.threads = 2}, &plainStats);

  RenderStats stats2, stats3;
  const Film uncut = stage.render(1.0f, 3);
  const Film two = stage.render(0.05f, 2, {.threads = 2}, &stats2);
  const Film three = stage.render(0.05f, 3, {.threads = 2}, &stats3);
  int flat = 0, cut = 0;
  for (uint32_t k : three.samples) flat += k == 4, cut += k > 4;
  EXPECT_GT(flat, int(three.samples.size()) / 2) << "most of the image is flat";
  EXPECT_GT(cut, 40) << "its edges are not";

  const Film lattice = stage.render(0.05f, 3, {.threads = 2}, nullptr, 0);
  const double ePlain = rmse(plain, reference), eUncut = rmse(uncut, reference),
               eTwo = rmse(two, reference), eThree = rmse(three, reference);
  // (Measured: plain 4 spp 0.0073; uncut 0.022; two levels 0.0044 at 2.25 looks per pixel;
  // three 0.0016 at 3.7, 0.0021 with its looks on the lattice points.)
  EXPECT_LT(eTwo, 0.3 * eUncut);
  EXPECT_LT(eThree, 0.7 * eTwo);
  EXPECT_LT(eTwo, 0.8 * ePlain);
  EXPECT_LT(stats2.meanSpp, 0.75 * plainStats.meanSpp);
  EXPECT_LT(stats2.meanSpp, stats3.meanSpp);
  // Jitter: a straight edge's lattice errors no longer line up.
  EXPECT_LT(eThree, 0.9 * rmse(lattice, reference));
}

// Alpha and the AOVs are area-weighted like the colour: a pixel wholly on the objects has alpha
// 1 and their depth, one wholly on the background alpha 0 and no depth, and an edge pixel the
// covered share of its area in between.
TEST(Subdivision, AlphaAndAovsAreAreaWeighted) {
  const Stage stage;
  RenderSettings settings = stage.desc.render;
  settings.adaptive.contrast = 0.05f;
  settings.adaptive.subdivide = 3;
  settings.aovs = true;
  const Film film = render(stage.scene, *stage.integrator, settings, {.threads = 2}, nullptr);
  ASSERT_TRUE(film.hasAovs);
  int covered = 0, empty = 0, partial = 0;
  for (size_t i = 0; i < film.alpha.size(); ++i) {
    const float a = film.alpha[i];
    ASSERT_GE(a, 0.0f);
    ASSERT_LE(a, 1.0f);
    if (a == 1.0f) {
      ++covered;
      EXPECT_GT(film.depth[i], 0.5f) << i;
      EXPECT_GT(length(film.normal[i]), 0.3f) << i;  // a mean of unit normals
    } else if (a == 0.0f) {
      ++empty;
      EXPECT_EQ(film.depth[i], 0.0f) << i;
      EXPECT_EQ(film.albedo[i], Rgb{}) << i;
    } else {
      ++partial;
      EXPECT_GT(film.samples[i], 4u) << "an edge pixel's corners differ: it is cut " << i;
    }
  }
  EXPECT_GT(covered, 300);
  EXPECT_GT(empty, 100);
  EXPECT_GT(partial, 10);
}

// What a one-pass quadrature cannot do is refused with a clear error, and the sidecar checks
// its depth.
TEST(Subdivision, WhatItCannotDoIsRefused) {
  const Stage stage(8, 6);
  RenderSettings settings = stage.desc.render;
  settings.adaptive.subdivide = 2;
  settings.adaptive.contrast = 0.1f;
  StopRule budget;
  budget.timeLimit = 5;
  EXPECT_THROW(renderUntil(stage.scene, *stage.integrator, settings, {}, budget, nullptr, nullptr),
               InputError);
  const Film partial = render(stage.scene, *stage.integrator, settings, {}, nullptr);
  EXPECT_THROW(renderUntil(stage.scene, *stage.integrator, settings, {}, StopRule{}, nullptr,
                           nullptr, &partial, 25),
               InputError);
  settings.adaptive.threshold = 0.01f;
  EXPECT_THROW(render(stage.scene, *stage.integrator, settings, {}, nullptr), InputError);

  SceneDescription desc;
  applySceneJsonText(R"({"render": {"adaptive": {"contrast": 0.1, "subdivide": 3}}})", "scene.json",
                     SceneJsonKind::Scene, &desc);
  EXPECT_EQ(desc.render.adaptive.subdivide, 3);
  EXPECT_SCENE_ERROR(test::errorFrom([] {
                       SceneDescription d;
                       applySceneJsonText(R"({"render": {"adaptive": {"subdivide": 7}}})",
                                          "scene.json", SceneJsonKind::Scene, &d);
                     }),
                     "scene.json", "/render/adaptive/subdivide", "<= 6");
}

// The command line: --subdivide renders, says so in --stats, resumes by rendering again, and
// refuses a time limit with exit code 2.
TEST(Subdivision, TheCommandLineRendersAndRefusesBudgets) {
  const std::string dir = test::scratchDir("subdivide_cli");
  const std::string scene = dir + "/scene.json";
  {
    std::FILE* f = std::fopen(scene.c_str(), "w");
    ASSERT_NE(f, nullptr);
    const std::string text = sceneJson(24, 18);
    std::fputs(text.c_str(), f);
    std::fclose(f);
  }
  const auto ok = test::runGlint("render " + scene + " --antialias 0.05 --subdivide 2 -o " + dir +
                                 "/stage.exr --stats " + dir + "/stats.json --quiet");
  ASSERT_EQ(ok.exitCode, 0) << ok.err;
  const std::string stats = test::slurp(dir + "/stats.json");
  EXPECT_NE(stats.find("\"subdivide\": 2"), std::string::npos) << stats;
  // --resume: the same settings are complete; another depth is rendered again (one pass, so
  // never continued).
  const std::string again =
      "render " + scene + " --antialias 0.05 -o " + dir + "/stage.exr --resume";
  const auto complete = test::runGlint(again + " --subdivide 2");
  ASSERT_EQ(complete.exitCode, 0) << complete.err;
  EXPECT_NE(complete.err.find("nothing to do"), std::string::npos) << complete.err;
  const auto redone = test::runGlint(again + " --subdivide 3");
  ASSERT_EQ(redone.exitCode, 0) << redone.err;
  EXPECT_NE(redone.err.find("redoing"), std::string::npos) << redone.err;
  EXPECT_NE(redone.err.find("subdivision 3"), std::string::npos) << redone.err;
  const auto refused =
      test::runGlint("render " + scene + " --antialias 0.05 --subdivide 2 --time-limit 2 -o " +
                     dir + "/budget.exr --quiet");
  EXPECT_EQ(refused.exitCode, 2);
  EXPECT_NE(refused.err.find("one pass"), std::string::npos) << refused.err;
}

}  // namespace
}  // namespace glint
