// Tests for adaptive sampling (RenderSettings::adaptive, renderer/render.cpp): a pixel's samples
// are the same ones a fixed-spp render draws, it stops only by its own statistics (so the image
// does not depend on the thread count), and the samples go where the noise is.
#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <string>
#include <utility>

#include "renderer/render.h"
#include "scene_error_support.h"
#include "scenes/build.h"
#include "scenes/sidecar.h"
#include "test_support.h"

namespace glint {
namespace {

// A Lambert ball under a quad light, path-traced, in front of a constant background: the
// background's samples all agree, the ball's do not.
const std::string kScene = test::litBallJson(24, 24);

struct Setup {
  SceneDescription desc;
  RenderScene scene;
  std::unique_ptr<Integrator> integrator;
};

std::unique_ptr<Setup> build() {
  auto s = std::make_unique<Setup>();
  s->desc.file = "adaptive_test (in code)";
  applySceneJsonText(kScene, s->desc.file, SceneJsonKind::Scene, &s->desc);
  s->scene = buildRenderScene(s->desc);
  s->integrator = makeIntegrator(s->scene, s->desc.render);
  return s;
}

Film renderWith(const Setup& s, int spp, float threshold, int threads, RenderStats* stats) {
  RenderSettings settings = s.desc.render;
  settings.spp = spp;
  settings.seed = 7;
  settings.adaptive.threshold = threshold;
  settings.adaptive.minSpp = 16;
  return render(s.scene, *s.integrator, settings, {.threads = threads}, stats);
}

void expectSameImage(const Film& a, const Film& b) {
  ASSERT_EQ(a.color.size(), b.color.size());
  for (size_t i = 0; i < a.color.size(); ++i) {
    ASSERT_EQ(a.color[i], b.color[i]) << "pixel " << i;
    ASSERT_EQ(a.variance[i], b.variance[i]) << "pixel " << i;
  }
}

// The extremes are fixed-spp renders with the very same samples: a threshold everything meets
// stops every pixel after min_spp; a tiny one stops only pixels whose first min_spp samples
// all agree (variance exactly 0: the background, and edge pixels whose first samples all
// missed the ball, adaptive sampling's known bias), all others take every sample.
TEST(AdaptiveSampling, TheExtremesAreFixedSppRenders) {
  auto s = build();
  RenderStats stats;
  const Film least = renderWith(*s, 16, 0, 2, &stats);
  EXPECT_EQ(stats.meanSpp, 16);
  expectSameImage(renderWith(*s, 64, 1e9f, 2, &stats), least);
  EXPECT_EQ(stats.meanSpp, 16);

  const Film full = renderWith(*s, 64, 0, 2, &stats);
  EXPECT_EQ(stats.meanSpp, 64);
  const Film tiny = renderWith(*s, 64, 1e-9f, 2, &stats);
  int noisy = 0;
  for (size_t i = 0; i < full.color.size(); ++i) {
    const bool exact = least.variance[i] == Rgb{};
    noisy += !exact;
    ASSERT_EQ(tiny.color[i], exact ? least.color[i] : full.color[i]) << "pixel " << i;
  }
  EXPECT_GT(noisy, 50);
  EXPECT_GT(stats.meanSpp, 16);
  EXPECT_LT(stats.meanSpp, 64);
}

// From min_spp 2, a pixel may stop after 2, 4 or 8 samples, then at multiples of 16: the
// background (its samples all agree) stops at 2, every pixel's count is a checkpoint, some lit
// pixels stop in between, and the image is the same on one thread and when rendered in the
// warm-up passes of a budget (1, 2, 4, 8, 16 spp, ...).
TEST(AdaptiveSampling, EarlyCheckpointsLetQuietPixelsStopAfterAFewSamples) {
  auto s = build();
  RenderSettings settings = s->desc.render;
  settings.spp = 64;
  settings.seed = 7;
  settings.adaptive.threshold = 0.2f;
  settings.adaptive.minSpp = 2;
  RenderStats stats;
  const Film film = render(s->scene, *s->integrator, settings, {.threads = 2}, &stats);
  int early = 0;
  for (size_t i = 0; i < film.samples.size(); ++i) {
    const uint32_t k = film.samples[i];
    EXPECT_TRUE(k == 2 || k == 4 || k == 8 || k % 16 == 0) << "pixel " << i << ": " << k;
    if (film.alpha[i] == 0) {
      EXPECT_EQ(k, 2u) << "background pixel " << i;
    }
    early += film.alpha[i] > 0 && (k == 4 || k == 8);
  }
  EXPECT_GT(early, 0);
  EXPECT_LT(stats.meanSpp, 64);
  expectSameImage(render(s->scene, *s->integrator, settings, {.threads = 1}, nullptr), film);
  StopRule warmup;
  warmup.maxSpp = 64;
  warmup.warmup = true;
  RenderStats budgetStats;
  ProgressiveResult result;
  expectSameImage(renderUntil(s->scene, *s->integrator, settings, {.threads = 2}, warmup,
                              &budgetStats, &result),
                  film);
}

// In between: the background stops at min_spp, the lit ball takes more, and each pixel that
// stopped early met the rule; one thread gives the same image.
TEST(AdaptiveSampling, SamplesGoWhereTheNoiseIs) {
  auto s = build();
  RenderStats stats;
  const float threshold = 0.05f;
  const Film film = renderWith(*s, 256, threshold, 2, &stats);
  EXPECT_GT(stats.meanSpp, 16);
  EXPECT_LT(stats.meanSpp, 256);
  const Film least = renderWith(*s, 16, 0, 2, nullptr);
  const Film full = renderWith(*s, 256, 0, 2, nullptr);
  int background = 0, early = 0;
  for (size_t i = 0; i < film.color.size(); ++i) {
    if (film.alpha[i] == 0) {  // background: zero variance, stops as soon as it may
      ++background;
      EXPECT_EQ(film.color[i], least.color[i]);
      continue;
    }
    if (film.color[i] == full.color[i]) continue;  // took every sample
    ++early;
    for (int c = 0; c < 3; ++c) {
      const double mean = film.color[i][c];
      EXPECT_LE(film.variance[i][c], threshold * threshold * (mean * mean + 0.01) * 1.0001)
          << "pixel " << i << " stopped before meeting the rule";
    }
  }
  EXPECT_GT(background, 100);
  EXPECT_GT(early, 0);
  expectSameImage(renderWith(*s, 256, threshold, 1, nullptr), film);
}

// Anti-aliasing by contrast on a noise-free (Whitted, point light) box: flat pixels stop after
// one sample, edge pixels take all 16, every count is a contrast checkpoint, and the image is
// the same on one thread and in a budget's warm-up passes.
struct Whitted {
  SceneDescription desc;
  RenderScene scene;
  std::unique_ptr<Integrator> integrator;
  explicit Whitted(float contrast) {
    desc.file = "adaptive_test (in code)";
    applySceneJsonText(test::cornellBoxJson(40, 16, 3, R"({"type": "whitted"})", true), desc.file,
                       SceneJsonKind::Scene, &desc);
    desc.render.adaptive.contrast = contrast;
    scene = buildRenderScene(desc);
    integrator = makeIntegrator(scene, desc.render);
  }
  Film render(RenderOptions options, RenderStats* stats = nullptr) const {
    return glint::render(scene, *integrator, desc.render, options, stats);
  }
};

TEST(AntiAliasing, FlatPixelsStopEarlyAndEdgesTakeEverySample) {
  const Whitted w(0.1f);
  RenderStats stats;
  const Film film = w.render({.threads = 2}, &stats);
  int one = 0, all = 0;
  for (size_t i = 0; i < film.samples.size(); ++i) {
    const uint32_t k = film.samples[i];
    EXPECT_TRUE(k == 1 || k == 2 || k == 4 || k == 8 || k == 16) << "pixel " << i << ": " << k;
    one += k == 1, all += k == 16;
  }
  EXPECT_GT(one, int(film.samples.size()) / 2) << "most of a box is flat";
  EXPECT_GT(all, 20) << "its edges are not";
  EXPECT_LT(stats.meanSpp, 8);
  expectSameImage(w.render({.threads = 1, .tileSize = 7}), film);
  StopRule warmup;
  warmup.maxSpp = 16;
  ProgressiveResult result;
  RenderStats budgetStats;
  expectSameImage(renderUntil(w.scene, *w.integrator, w.desc.render, {.threads = 2}, warmup,
                              &budgetStats, &result),
                  film);
  // Off, every pixel takes every sample.
  const Whitted plain(0.0f);
  RenderStats plainStats;
  plain.render({.threads = 2}, &plainStats);
  EXPECT_EQ(plainStats.meanSpp, 16);
}

// A pixel the first checkpoint stops is its centre's radiance (POV-Ray's one ray per pixel:
// exact for a linear gradient across the pixel); a pixel that went on dropped that look, so
// with k samples it is a plain k-spp render's pixel, bit for bit (the same stratified samples,
// added in the same order); the mean spp counts the dropped looks.
TEST(AntiAliasing, AStoppedPixelIsItsCentreAndARefinedOneAPlainRendersPixel) {
  const Whitted w(0.1f);
  RenderStats stats;
  const Film film = w.render({.threads = 2}, &stats);
  std::map<uint32_t, Film> plain;
  for (uint32_t k : {2u, 4u, 8u, 16u}) {
    RenderSettings settings = w.desc.render;
    settings.adaptive.contrast = 0;
    settings.spp = int(k);
    plain.emplace(k, glint::render(w.scene, *w.integrator, settings, {.threads = 2}, nullptr));
  }
  int centres = 0, refined = 0;
  uint64_t traced = 0;
  for (int y = 0; y < film.height; ++y)
    for (int x = 0; x < film.width; ++x) {
      const size_t i = film.index(x, y);
      const uint32_t k = film.samples[i];
      traced += k + (k > 1 ? 1 : 0);
      if (k > 1) {
        ASSERT_EQ(film.color[i], plain.at(k).color[i]) << x << "," << y << ": " << k;
        ASSERT_EQ(film.variance[i], plain.at(k).variance[i]) << x << "," << y;
        ++refined;
        continue;
      }
      ASSERT_EQ(k, 1u);
      const Ray ray = w.scene.camera().pinholeRay({float(x) + 0.5f, float(y) + 0.5f}, 0);
      Sampler sampler(pixelSampleKey(w.desc.render.seed, i), 0, kIntegratorDimension);
      RayCounters counters;
      PathAovs aovs;
      const Rgb L = w.integrator->Li(ray, sampler, counters, aovs);
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(film.color[i][c], L[c], 1e-6f * std::max(1.0f, L[c])) << x << "," << y;
      ++centres;
    }
  EXPECT_GT(centres, int(film.color.size()) / 2);
  EXPECT_GT(refined, 20);
  EXPECT_DOUBLE_EQ(stats.meanSpp, double(traced) / double(film.color.size()));
}

// A render continued from an image (--resume, an interrupted budget) takes the same samples in
// every pixel as one rendered straight through, also when the image ends at a checkpoint where
// some of its pixels stopped (4, 16) or on the centre look alone (1).
TEST(AntiAliasing, AContinuedRenderMatchesAFreshOne) {
  const Whitted w(0.1f);
  for (auto [from, to] : {std::pair{1u, 16u}, {4u, 16u}, {16u, 32u}, {3u, 8u}}) {
    SCOPED_TRACE(std::to_string(from) + " -> " + std::to_string(to));
    RenderSettings settings = w.desc.render;
    settings.spp = int(from);
    const Film partial = glint::render(w.scene, *w.integrator, settings, {.threads = 2}, nullptr);
    settings.spp = int(to);
    const Film fresh = glint::render(w.scene, *w.integrator, settings, {.threads = 2}, nullptr);
    StopRule rule;
    rule.maxSpp = to;
    ProgressiveResult result;
    const Film continued = renderUntil(w.scene, *w.integrator, settings, {.threads = 2}, rule,
                                       nullptr, &result, &partial, from);
    ASSERT_EQ(continued.samples.size(), fresh.samples.size());
    for (size_t i = 0; i < fresh.samples.size(); ++i) {
      ASSERT_EQ(continued.samples[i], fresh.samples[i]) << "pixel " << i;
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(continued.color[i][c], fresh.color[i][c],
                    1e-5f * std::max(1.0f, std::abs(fresh.color[i][c])))
            << "pixel " << i;
    }
  }
}

// A crop (and so a farm tile) renders a margin around its window, so its pixels are exactly the
// whole frame's: decisions at its border see the same neighbours.
TEST(AntiAliasing, ACropHasTheWholeFramesPixels) {
  const Whitted w(0.02f);
  const Film full = w.render({.threads = 2});
  for (PixelWindow crop : {PixelWindow{7, 5, 23, 31}, PixelWindow{0, 20, 40, 27}}) {
    RenderOptions options{.threads = 2};
    options.crop = crop;
    const Film part = w.render(options);
    ASSERT_EQ(part.width, crop.width());
    for (int y = crop.y0; y < crop.y1; ++y)
      for (int x = crop.x0; x < crop.x1; ++x) {
        const size_t i = part.index(x - crop.x0, y - crop.y0), j = full.index(x, y);
        ASSERT_EQ(part.color[i], full.color[j]) << x << "," << y;
        ASSERT_EQ(part.variance[i], full.variance[j]) << x << "," << y;
        ASSERT_EQ(part.samples[i], full.samples[j]) << x << "," << y;
      }
  }
}

TEST(AdaptiveSampling, SidecarSettingsAreChecked) {
  SceneDescription desc;
  applySceneJsonText(R"({"render": {"adaptive": {"threshold": 0.02, "min_spp": 64}}})",
                     "scene.json", SceneJsonKind::Scene, &desc);
  EXPECT_FLOAT_EQ(desc.render.adaptive.threshold, 0.02f);
  EXPECT_EQ(desc.render.adaptive.minSpp, 64);
  auto load = [](const char* text) {
    return [text] {
      SceneDescription d;
      applySceneJsonText(text, "scene.json", SceneJsonKind::Scene, &d);
    };
  };
  EXPECT_SCENE_ERROR(test::errorFrom(load(R"({"render": {"adaptive": {"min_spp": 1}}})")),
                     "scene.json", "/render/adaptive/min_spp", ">= 2");
  EXPECT_SCENE_ERROR(test::errorFrom(load(R"({"render": {"adaptive": {"threshold": -1}}})")),
                     "scene.json", "/render/adaptive/threshold", ">= 0");
  EXPECT_SCENE_ERROR(test::errorFrom(load(R"({"render": {"adaptive": {"contrast": 2}}})")),
                     "scene.json", "/render/adaptive/contrast", "<= 1");
}

}  // namespace
}  // namespace glint
