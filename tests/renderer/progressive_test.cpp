// Tests for progressive rendering (renderer/render.h: ProgressiveRender, renderUntil): the image
// after a pass is the image a render to that spp gives, whatever stopped it (spp, a time limit,
// a noise target, Ctrl-C dropping the pass in flight); a render continued from its film matches
// a fresh one to float rounding, with adaptive sampling too; the error estimate means what it
// says.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>

#include "renderer/render.h"
#include "scenes/build.h"
#include "scenes/load.h"
#include "scenes/sidecar.h"
#include "test_support.h"

namespace glint {
namespace {

// A Lambert ball under a quad light, path-traced, before a constant background.
const std::string kScene = test::litBallJson(20, 18);

struct Setup {
  SceneDescription desc;
  RenderScene scene;
  std::unique_ptr<Integrator> integrator;
  RenderSettings settings;
};

std::unique_ptr<Setup> build(bool aovs = true, float adaptive = 0) {
  auto s = std::make_unique<Setup>();
  s->desc.file = "progressive_test (in code)";
  applySceneJsonText(kScene, s->desc.file, SceneJsonKind::Scene, &s->desc);
  s->scene = buildRenderScene(s->desc);
  s->integrator = makeIntegrator(s->scene, s->desc.render);
  s->settings = s->desc.render;
  s->settings.seed = 11;
  s->settings.aovs = aovs;
  s->settings.adaptive.threshold = adaptive;
  s->settings.adaptive.minSpp = 16;
  return s;
}

Film renderAt(const Setup& s, int spp, int threads = 2) {
  RenderSettings settings = s.settings;
  settings.spp = spp;
  return render(s.scene, *s.integrator, settings, {.threads = threads}, nullptr);
}

void expectSameImage(const Film& a, const Film& b) {
  ASSERT_EQ(a.color.size(), b.color.size());
  for (size_t i = 0; i < a.color.size(); ++i) {
    ASSERT_EQ(a.color[i], b.color[i]) << "pixel " << i;
    ASSERT_EQ(a.variance[i], b.variance[i]) << "pixel " << i;
    ASSERT_EQ(a.alpha[i], b.alpha[i]) << "pixel " << i;
    ASSERT_EQ(a.samples[i], b.samples[i]) << "pixel " << i;
  }
  ASSERT_EQ(a.hasAovs, b.hasAovs);
  if (!a.hasAovs) return;
  for (size_t i = 0; i < a.color.size(); ++i) {
    ASSERT_EQ(a.albedo[i], b.albedo[i]) << "pixel " << i;
    ASSERT_EQ(a.normal[i], b.normal[i]) << "pixel " << i;
    ASSERT_EQ(a.depth[i], b.depth[i]) << "pixel " << i;
  }
}

// |a - b| within `rel` of their size (plus a floor for values near 0).
void expectNear(float a, float b, double rel, double floor, const std::string& what) {
  EXPECT_LE(std::abs(double(a) - double(b)), rel * std::max(std::abs(double(b)), floor))
      << what << ": " << a << " vs " << b;
}

TEST(PassSchedule, DoublesToSixteenThenStepsBySixteen) {
  EXPECT_EQ(nextPassEnd(0), 1u);
  EXPECT_EQ(nextPassEnd(1), 2u);
  EXPECT_EQ(nextPassEnd(2), 4u);
  EXPECT_EQ(nextPassEnd(3), 4u);  // a resumed render at 3 spp rejoins the schedule
  EXPECT_EQ(nextPassEnd(8), 16u);
  EXPECT_EQ(nextPassEnd(16), 32u);
  EXPECT_EQ(nextPassEnd(20), 32u);
  EXPECT_EQ(nextPassEnd(48), 64u);
  EXPECT_EQ(nextPassEnd(0x7fffffffu), 0x7ffffff0u + 16u);
  EXPECT_EQ(nextPassEnd(UINT32_MAX - 3), UINT32_MAX);  // no overflow
}

// Every pass of a long render shows the image a render to that spp gives, on any thread count.
TEST(ProgressiveRender, EachPassIsTheRenderAtItsSpp) {
  auto s = build();
  StopRule rule;
  rule.maxSpp = 40;
  int checked = 0;
  RenderStats stats;
  ProgressiveResult result;
  Film last = renderUntil(s->scene, *s->integrator, s->settings, {.threads = 1}, rule, &stats,
                          &result, nullptr, 0, [&](const ProgressiveRender& pr) {
                            if (pr.spp() == 4 || pr.spp() == 32) {
                              expectSameImage(pr.film(), renderAt(*s, int(pr.spp())));
                              ++checked;
                            }
                          });
  EXPECT_EQ(checked, 2);
  EXPECT_EQ(result.reason, StopReason::Spp);
  EXPECT_EQ(result.spp, 40u);
  EXPECT_EQ(result.passes, 7);  // 1 2 4 8 16 32 40
  expectSameImage(last, renderAt(*s, 40));
  EXPECT_EQ(stats.rays.camera, 40u * 20 * 18);
  EXPECT_DOUBLE_EQ(stats.meanSpp, 40.0);
}

// render() takes its samples in one pass straight to the film (renderOnce, no per-pixel sums
// kept): the same image, AOVs and statistics as the passes' way (renderTo), with adaptive
// sampling stopping pixels part-way too.
TEST(ProgressiveRender, RenderOnceIsRenderTo) {
  for (const float adaptive : {0.0f, 0.05f}) {
    auto s = build(true, adaptive);
    RenderSettings settings = s->settings;
    settings.spp = 48;
    RenderStats once;
    const Film a = render(s->scene, *s->integrator, settings, {.threads = 2}, &once);
    ProgressiveRender pr(s->scene, *s->integrator, settings, {.threads = 1});
    ASSERT_TRUE(pr.renderTo(48));
    expectSameImage(a, pr.film());
    EXPECT_EQ(once.meanSpp, pr.stats().meanSpp);
    EXPECT_EQ(once.rays.camera, pr.stats().rays.camera);
    if (adaptive > 0) {
      EXPECT_LT(once.meanSpp, 48.0) << "adaptive sampling stopped no pixel";
    }
    // And renderOnce ends the render: it keeps nothing to continue from.
    ProgressiveRender ended(s->scene, *s->integrator, settings, {.threads = 2});
    ended.renderOnce(8);
    EXPECT_EQ(ended.spp(), 8u);
    EXPECT_THROW(ended.renderTo(16), std::logic_error);
  }
}

// Ctrl-C during a pass drops it: the film is the last completed pass's, exactly.
TEST(ProgressiveRender, ACancelledPassIsDropped) {
  auto s = build();
  std::atomic<bool> cancel{false};
  ProgressiveRender pr(s->scene, *s->integrator, s->settings, {.threads = 2, .tileSize = 4});
  ASSERT_TRUE(pr.renderPass(64, &cancel));
  ASSERT_TRUE(pr.renderPass(64, &cancel));
  ASSERT_EQ(pr.spp(), 2u);
  int tiles = 0;
  // Cancel after a few tiles of the third pass have finished (and changed their pixels' sums).
  EXPECT_FALSE(pr.renderPass(64, &cancel, [&](uint64_t) {
    if (++tiles == 3) cancel = true;
  }));
  EXPECT_EQ(pr.spp(), 2u);
  expectSameImage(pr.film(), renderAt(*s, 2));
  EXPECT_THROW(pr.renderPass(64, nullptr), std::logic_error);
}

TEST(ProgressiveRender, RenderUntilReportsAnInterruption) {
  auto s = build();
  std::atomic<bool> cancel{false};
  StopRule rule;
  rule.maxSpp = 1000;
  rule.cancel = &cancel;
  ProgressiveResult result;
  Film film = renderUntil(s->scene, *s->integrator, s->settings, {.threads = 2}, rule, nullptr,
                          &result, nullptr, 0, [&](const ProgressiveRender& pr) {
                            if (pr.spp() == 8) cancel = true;  // during the pass to 16
                          });
  EXPECT_EQ(result.reason, StopReason::Interrupted);
  EXPECT_EQ(result.spp, 8u);
  expectSameImage(film, renderAt(*s, 8));
}

// A noise target stops at the first pass (from 16 spp on) whose estimate meets it, and the
// image is the render at the spp it reports.
TEST(ProgressiveRender, ANoiseTargetStopsWhereTheEstimateMeetsIt) {
  auto s = build(false);
  StopRule rule;
  rule.maxSpp = 4096;
  rule.noiseTarget = 0.02;
  std::vector<std::pair<uint32_t, double>> passes;
  ProgressiveResult result;
  Film film = renderUntil(
      s->scene, *s->integrator, s->settings, {.threads = 2}, rule, nullptr, &result, nullptr, 0,
      [&](const ProgressiveRender& pr) { passes.emplace_back(pr.spp(), pr.estimatedError()); });
  EXPECT_EQ(result.reason, StopReason::NoiseTarget);
  ASSERT_GE(passes.size(), 2u);
  EXPECT_LE(result.error, 0.02);
  EXPECT_EQ(passes.back().first, result.spp);
  // The pass before did not meet it (or was below 16 spp, where the target is not checked).
  const auto& before = passes[passes.size() - 2];
  EXPECT_TRUE(before.second > 0.02 || before.first < 16) << before.first << " " << before.second;
  EXPECT_GT(result.spp, 16u);  // this scene needs more than the first check
  EXPECT_LT(result.spp, 4096u);
  expectSameImage(film, renderAt(*s, int(result.spp)));
  EXPECT_DOUBLE_EQ(result.error, estimatedRelativeError(film));
  // The error falls about as 1/sqrt(spp): from 16 to the stop, within a factor 1.5 of that.
  double e16 = 0;
  for (const auto& [spp, e] : passes)
    if (spp == 16) e16 = e;
  ASSERT_GT(e16, 0);
  const double predicted = e16 * std::sqrt(16.0 / result.spp);
  EXPECT_NEAR(result.error / predicted, 1.0, 0.5);
}

// A time limit lets the first pass run whatever it costs, then stops before a pass that would
// not fit: a limit of a nanosecond gives 1 spp.
TEST(ProgressiveRender, ATimeLimitAlwaysCompletesTheFirstPass) {
  auto s = build(false);
  StopRule rule;
  rule.maxSpp = 1u << 30;
  rule.timeLimit = 1e-9;
  ProgressiveResult result;
  Film film =
      renderUntil(s->scene, *s->integrator, s->settings, {.threads = 2}, rule, nullptr, &result);
  EXPECT_EQ(result.reason, StopReason::TimeLimit);
  EXPECT_EQ(result.spp, 1u);
  expectSameImage(film, renderAt(*s, 1));
  // A generous limit ends on the spp cap instead.
  rule.maxSpp = 8;
  rule.timeLimit = 3600;
  renderUntil(s->scene, *s->integrator, s->settings, {.threads = 2}, rule, nullptr, &result);
  EXPECT_EQ(result.reason, StopReason::Spp);
  EXPECT_EQ(result.spp, 8u);
}

// Continuing a film from its mean, variance and samples gives the fresh render to float
// rounding: the sums are rebuilt from stored floats.
void expectContinuesLikeAFreshRender(const Setup& s, uint32_t from, uint32_t to) {
  const Film partial = renderAt(s, int(from));
  StopRule rule;
  rule.maxSpp = to;
  ProgressiveResult result;
  Film continued = renderUntil(s.scene, *s.integrator, s.settings, {.threads = 2}, rule, nullptr,
                               &result, &partial, from);
  EXPECT_EQ(result.spp, to);
  const Film fresh = renderAt(s, int(to));
  ASSERT_EQ(continued.color.size(), fresh.color.size());
  for (size_t i = 0; i < fresh.color.size(); ++i) {
    const std::string px = "pixel " + std::to_string(i);
    ASSERT_EQ(continued.samples[i], fresh.samples[i]) << px;
    for (int c = 0; c < 3; ++c) {
      expectNear(continued.color[i][c], fresh.color[i][c], 1e-5, 1e-3, px + " mean");
      // The variance subtracts sums: its rounding grows with mean² / variance.
      expectNear(continued.variance[i][c], fresh.variance[i][c], 1e-3, 1e-6, px + " variance");
    }
    EXPECT_EQ(continued.alpha[i], fresh.alpha[i]) << px;
    if (fresh.hasAovs) {
      for (int c = 0; c < 3; ++c) {
        expectNear(continued.albedo[i][c], fresh.albedo[i][c], 1e-5, 1e-3, px + " albedo");
        expectNear(continued.normal[i][c], fresh.normal[i][c], 1e-5, 1e-3, px + " normal");
      }
      expectNear(continued.depth[i], fresh.depth[i], 1e-5, 1e-3, px + " depth");
    }
  }
}

TEST(ProgressiveRender, AContinuedRenderMatchesAFreshOne) {
  auto s = build(true);
  expectContinuesLikeAFreshRender(*s, 16, 48);
  expectContinuesLikeAFreshRender(*s, 5, 20);  // off the pass schedule, both ends
}

TEST(ProgressiveRender, AContinuedAdaptiveRenderMatchesAFreshOne) {
  auto s = build(false, 0.05f);
  const Film fresh = renderAt(*s, 256);
  size_t stoppedEarly = 0;
  for (uint32_t k : fresh.samples) stoppedEarly += k < 256;
  ASSERT_GT(stoppedEarly, fresh.samples.size() / 4);  // adaptive sampling did stop pixels
  expectContinuesLikeAFreshRender(*s, 64, 256);
}

TEST(ProgressiveRender, ResumeRejectsAFilmOfAnotherShape) {
  auto s = build(false);
  ProgressiveRender pr(s->scene, *s->integrator, s->settings, {.threads = 1});
  Film other(10, 10, false);
  EXPECT_THROW(pr.resumeFrom(other, 4), InputError);
  Film partial = renderAt(*s, 4);
  partial.samples[7] = 9;  // more than its spp
  EXPECT_THROW(pr.resumeFrom(partial, 4), InputError);
}

// A pixel's camera rays go to the accelerator in batches that never cross a multiple of 16;
// whether a batch of 16 is traced in one pass (render()) or split over the schedule's passes of
// 1, 1, 2, 4 and 8 (a packet of one takes Embree's single-ray kernel, small packets leave
// lanes idle), every ray gets the same hit, so the images are identical. Checked on triangle
// meshes (the Stanford bunny, instances), analytic shapes and CSG, a thin lens and motion.
void expectSplitsGiveTheSameImage(const std::string& path, int spp) {
  SCOPED_TRACE(path);
  SceneDescription desc = loadScene(path);
  desc.render.width = 64;
  desc.render.height = 48;
  desc.render.spp = spp;
  const RenderScene scene = buildRenderScene(desc);
  const auto integrator = makeIntegrator(scene, desc.render);
  const Film once = render(scene, *integrator, desc.render, {.threads = 2}, nullptr);
  StopRule rule;
  rule.maxSpp = uint32_t(spp);
  rule.warmup = true;
  const Film split =
      renderUntil(scene, *integrator, desc.render, {.threads = 1}, rule, nullptr, nullptr);
  expectSameImage(once, split);
}

TEST(PassSplits, TrianglesShapesLensAndMotionGiveTheSameImage) {
  expectSplitsGiveTheSameImage(test::assetsDir() + "/stanford/bun_zipper.glb", 20);
  expectSplitsGiveTheSameImage(test::dataDir() + "/scenes/two_instances.gltf", 16);
  const std::string dir = test::scratchDir("PassSplits");
  const std::string csg = dir + "/csg.json";
  std::ofstream(csg) << R"({
    "render": {"integrator": "whitted", "camera": "c"},
    "cameras": [{"name": "c", "position": [0.3, 0.8, 4], "look_at": [0, 0, 0], "yfov_degrees": 35,
                 "aperture": 0.05, "focus_distance": 4, "shutter": [0, 0.5]}],
    "lights": [{"type": "point", "position": [2, 3, 3], "intensity": 30}],
    "materials": [{"name": "m", "type": "lambert", "diffuse": [0.6, 0.5, 0.4]}],
    "objects": [
      {"name": "cut", "type": "csg", "material": "m", "tree":
        {"op": "difference", "children": [
          {"type": "box", "min": [-0.8, -0.8, -0.8], "max": [0.8, 0.8, 0.8]},
          {"type": "sphere", "radius": 1.0}]}},
      {"name": "ball", "type": "sphere", "center": [1.2, 0, 0], "radius": 0.3, "material": "m",
       "animation": {"translation": {"keys": [[0, [0, 0, 0]], [1, [0, 0.4, 0]]]}}},
      {"type": "plane", "point": [0, -1, 0], "normal": [0, 1, 0], "material": "m"}]})";
  expectSplitsGiveTheSameImage(csg, 16);
}

// The estimate: sqrt(mean over pixels and channels of Var / (mean² + 0.01)).
TEST(EstimatedRelativeError, IsTheRootMeanRelativeVariance) {
  Film film(2, 1, false);
  film.samples = {4, 4};
  film.color = {Rgb{1, 1, 1}, Rgb{0, 0, 0}};
  film.variance = {Rgb{0.0101f, 0.0101f, 0.0101f}, Rgb{0.0001f, 0.0001f, 0.0001f}};
  // Pixel 0: 0.0101 / 1.01 = 0.01; pixel 1: 0.0001 / 0.01 = 0.01.
  EXPECT_NEAR(estimatedRelativeError(film), 0.1, 1e-6);
  film.samples[1] = 1;  // no variance from one sample: no estimate
  EXPECT_EQ(estimatedRelativeError(film), 0.0);
}

}  // namespace
}  // namespace glint
