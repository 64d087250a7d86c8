// Tests for adaptive sampling (RenderSettings::adaptive, renderer/render.cpp): a pixel's samples
// are the same ones a fixed-spp render draws, it stops only by its own statistics (so the image
// does not depend on the thread count), and the samples go where the noise is.
#include <gtest/gtest.h>

#include <memory>
#include <string>

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
}

}  // namespace
}  // namespace glint
