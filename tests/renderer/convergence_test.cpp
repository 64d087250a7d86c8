// Convergence rates: an unbiased estimator's RMSE falls like spp^-1/2, so RMSE(N) / RMSE(4N)
// is 2; a biased one converges to its own limit at that rate while its error against the
// unbiased answer levels off at the bias (the ratio falls towards 1).
//
// Each check renders a converged reference once, then the same scene at N and 4N spp for
// kSeeds seeds, and compares the mean of the per-seed ratios with its expectation. That is not
// exactly 2: the reference (M spp, an independent seed) carries noise of its own, so
// E[MSE(N)] = v/N + v/M for a per-sample variance v, and the ratio is
// sqrt((1/N + 1/M) / (1/4N + 1/M)) (1.997 for N = 4, M = 4096; 1.915 for N = 32, M = 1024).
//
// Tolerance. RMSE² is a mean of squared pixel errors; for independent Gaussian pixel errors of
// variances v_i its relative standard deviation is sqrt(2 / n_eff), n_eff = (Σ v_i)² / Σ v_i²
// (printed; 360 to 1,400 here, read from the reference's per-pixel variance), so a ratio of two
// RMSEs scatters by about 1 / sqrt(n_eff) = 2.7–5% and the mean of 6 seeds by 1.1–2.2%; the
// heavy-tailed errors of a few spp about double that. The test measures the scatter of its
// seeds and asserts it below kMaxRelativeSpread = 5% of the mean (measured 1.7–3.8%), so that
// kTolerance = 0.25 (12.5% of 2) is at least 2.5 standard deviations of the mean.
//
// The sampler is Owen-scrambled Sobol, padded per dimension pair (renderer/sampler.h), so
// estimators converge *at least* at Monte Carlo's rate, and faster where one low-dimensional
// pair carries the variance: Whitted's soft shadows (the light sample's pair, ratio 2.95 here),
// single scattering's distance sample (3.96), instant radiosity's direct light (2.19). Those
// checks assert ratio >= expected − kTolerance (never slower than Monte Carlo) and <= 8 +
// kTolerance (4^(3/2): RMSE ~ N^-3/2, the best a scrambled net reaches for smooth integrands;
// more would mean the films are not independent of the reference). The path tracer's variance
// is mostly in its decorrelated later bounces: it measures 2.22 at N = 4 (2.13 at N = 16), the
// excess being the stratified pixel and first light sample, and is held to
// [expected − kTolerance, 2.5].
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "renderer/instant_radiosity.h"
#include "renderer/render.h"
#include "scenes/build.h"
#include "scenes/sidecar.h"
#include "test_support.h"

namespace glint {
namespace {

constexpr int kSeeds = 6;
constexpr double kTolerance = 0.25;
constexpr double kMaxRelativeSpread = 0.05;
constexpr double kPathTracerMaxRatio = 2.5;
constexpr double kStratifiedMaxRatio = 8;

// ---------------------------------------------------------------------------------------------
// Scenes and renders
// ---------------------------------------------------------------------------------------------

// A cube of bright, forward-scattering fog (albedo 0.95, optical depth 2.4 across) over a grey
// floor, lit by a point light above and beside it: much of the light leaving the fog has
// scattered more than once.
std::string fogCube(int size, const std::string& integrator) {
  const std::string n = std::to_string(size);
  return R"({
    "render": {"width": )" +
         n + R"(, "height": )" + n + R"(, "camera": "c", "integrator": )" + integrator + R"(},
    "cameras": [{"name": "c", "position": [0, 1.2, 3.2], "look_at": [0, 0.5, 0],
                 "yfov_degrees": 40}],
    "lights": [{"type": "point", "position": [1.5, 2.5, 1], "intensity": 12}],
    "materials": [{"name": "floor", "type": "lambert", "diffuse": [0.5, 0.5, 0.5]}],
    "objects": [{"type": "quad", "corner": [-2, 0, -2], "edge_u": [0, 0, 4], "edge_v": [4, 0, 0],
                 "material": "floor"}],
    "media": [{"name": "fog", "region": {"type": "box", "min": [-0.6, 0, -0.6], "max": [0.6, 1.2, 0.6]},
               "sigma_a": 0.1, "sigma_s": 1.9, "g": 0.3}]})";
}

struct Setup {
  SceneDescription desc;
  RenderScene scene;
};
std::unique_ptr<Setup> build(const std::string& json) {
  auto s = std::make_unique<Setup>();
  s->desc.file = "convergence_test (in code)";
  applySceneJsonText(json, s->desc.file, SceneJsonKind::Scene, &s->desc);
  s->scene = buildRenderScene(s->desc);
  return s;
}

Film renderFilm(const Setup& s, const Integrator& integrator, int spp, uint64_t seed) {
  RenderSettings settings = s.desc.render;
  settings.spp = spp;
  settings.seed = seed;
  RenderStats stats;
  Film film = render(s.scene, integrator, settings, {.threads = 2}, &stats);
  EXPECT_EQ(stats.nonfiniteSamples, 0u);
  return film;
}
Film renderFilm(const Setup& s, int spp, uint64_t seed) {
  RenderSettings settings = s.desc.render;
  settings.seed = seed;
  return renderFilm(s, *makeIntegrator(s.scene, settings), spp, seed);
}

// RMSE over pixels and the three channels, as `glint diff` computes it for colour.
double rmse(const Film& a, const Film& b) {
  double sum = 0;
  for (size_t i = 0; i < a.color.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double d = double(a.color[i][c]) - b.color[i][c];
      sum += d * d;
    }
  return std::sqrt(sum / double(3 * a.color.size()));
}

// n_eff = (Σ v)² / Σ v² over pixels and channels, v the film's variance of the mean.
double effectivePixels(const Film& f) {
  double sum = 0, sumSq = 0;
  for (const Rgb& v : f.variance)
    for (int c = 0; c < 3; ++c) sum += v[c], sumSq += double(v[c]) * v[c];
  return sumSq > 0 ? sum * sum / sumSq : 0;
}

// What Monte Carlo predicts for RMSE(N) / RMSE(4N) against an independent reference of M spp.
double expectedRatio(int n, int m) {
  return std::sqrt((1.0 / n + 1.0 / m) / (1.0 / (4.0 * n) + 1.0 / m));
}

struct Rate {
  double mean = 0;                 // mean over seeds of RMSE(N) / RMSE(4N)
  double spread = 0;               // standard deviation of that mean, from the seeds' scatter
  double errorN = 0, error4N = 0;  // mean RMSEs
};

// RMSE(N) / RMSE(4N) against each of `references` (named by `names`) for seeds 1..kSeeds;
// `film(spp, seed)` renders. Each film is rendered once and compared with every reference.
template <typename Render>
std::vector<Rate> measureRates(const std::vector<const char*>& names,
                               const std::vector<const Film*>& references, int n, Render film) {
  const size_t k = references.size();
  std::vector<Rate> rates(k);
  std::vector<double> sum(k, 0), sumSq(k, 0);
  std::vector<std::string> ratios(k);
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const Film a = film(n, uint64_t(seed)), b = film(4 * n, uint64_t(seed));
    for (size_t r = 0; r < k; ++r) {
      const double eN = rmse(a, *references[r]), e4N = rmse(b, *references[r]);
      const double q = eN / e4N;
      sum[r] += q, sumSq[r] += q * q;
      rates[r].errorN += eN / kSeeds, rates[r].error4N += e4N / kSeeds;
      char buf[32];
      std::snprintf(buf, sizeof buf, " %.3f", q);
      ratios[r] += buf;
    }
  }
  for (size_t r = 0; r < k; ++r) {
    Rate& q = rates[r];
    q.mean = sum[r] / kSeeds;
    q.spread = std::sqrt(std::max(0.0, (sumSq[r] - sum[r] * q.mean) / (kSeeds - 1)) / kSeeds);
    std::printf(
        "[ rate     ] %s: RMSE %d spp %.5f, %d spp %.5f; ratio per seed%s; mean %.3f ± %.3f\n",
        names[r], n, q.errorN, 4 * n, q.error4N, ratios[r].c_str(), q.mean, q.spread);
  }
  return rates;
}

// The rate of an unbiased estimator (or of a biased one against its own limit): not slower
// than Monte Carlo's `expected`, not faster than `maxRatio`, and seeds that agree well enough
// for kTolerance to mean something (see the file comment).
void expectRate(const Rate& r, double expected, double maxRatio) {
  EXPECT_GE(r.mean, expected - kTolerance) << "slower than Monte Carlo's 1/sqrt(spp)";
  EXPECT_LE(r.mean, maxRatio + kTolerance);
  EXPECT_LT(r.spread, kMaxRelativeSpread * r.mean)
      << "the seeds scatter more than kTolerance assumes";
}

// ---------------------------------------------------------------------------------------------
// Unbiased estimators
// ---------------------------------------------------------------------------------------------

constexpr int kSize = 24;
constexpr int kReferenceSpp = 4096;
constexpr uint64_t kReferenceSeed = 1000;  // independent of the ladder's seeds 1..kSeeds

// The path tracer's converged image of the Cornell box: the unbiased answer of two tests.
const Setup& pathBox() {
  static const std::unique_ptr<Setup> s =
      build(test::cornellBoxJson(kSize, 1, 0, R"({"type": "path", "max_depth": 6})"));
  return *s;
}
const Film& pathBoxReference() {
  static const Film f = renderFilm(pathBox(), kReferenceSpp, kReferenceSeed);
  return f;
}

TEST(Convergence, PathTracerErrorFallsAsOneOverSqrtSpp) {
  const Film& reference = pathBoxReference();
  const double nEff = effectivePixels(reference);
  const int n = 4;
  const Rate r =
      measureRates({"path tracer, Cornell box"}, {&reference}, n,
                   [](int spp, uint64_t seed) { return renderFilm(pathBox(), spp, seed); })[0];
  std::printf("[ rate     ] n_eff %.0f, expected ratio %.3f\n", nEff,
              expectedRatio(n, kReferenceSpp));
  expectRate(r, expectedRatio(n, kReferenceSpp), kPathTracerMaxRatio);
}

// Whitted with a quad light estimates the direct light (soft shadows) without bias: one light
// sample per camera sample. Its variance sits mostly in the light sample's dimension pair,
// which the (0,2)-net stratifies: the ratio is at least Monte Carlo's.
TEST(Convergence, WhittedAreaLightErrorFallsAtLeastAsOneOverSqrtSpp) {
  const auto box =
      build(test::cornellBoxJson(kSize, 1, 0, R"({"type": "whitted", "max_depth": 6})"));
  const Film reference = renderFilm(*box, kReferenceSpp, kReferenceSeed);
  const double nEff = effectivePixels(reference);
  const int n = 4;
  const Rate r =
      measureRates({"Whitted, quad light"}, {&reference}, n,
                   [&](int spp, uint64_t seed) { return renderFilm(*box, spp, seed); })[0];
  const double expected = expectedRatio(n, kReferenceSpp);
  std::printf("[ rate     ] n_eff %.0f, Monte Carlo ratio %.3f\n", nEff, expected);
  expectRate(r, expected, kStratifiedMaxRatio);
}

// ---------------------------------------------------------------------------------------------
// Biased estimators: their own limit at 1/sqrt(N), a floor against the unbiased answer
// ---------------------------------------------------------------------------------------------

// Instant radiosity with few light paths and a clamped geometry term: one VPL set (its seed
// fixed) is a fixed, biased approximation of the indirect light; the camera samples then
// estimate that approximation without further bias. Against its own converged image the error
// keeps Monte Carlo's rate; against the path tracer it stops at the VPL set's error plus the
// clamp's lost energy.
TEST(Convergence, ClampedInstantRadiosityLevelsOffAtItsBias) {
  const auto box = build(test::cornellBoxJson(
      kSize, 1, 0,
      R"({"type": "instant-radiosity", "max_depth": 6, "vpl_paths": 16, "vpl_clamp": 10})"));
  const InstantRadiosityIntegrator ir(box->scene, box->desc.render.integrator, /*seed=*/7);
  const int ownSpp = 1024;
  const Film own = renderFilm(*box, ir, ownSpp, kReferenceSeed);
  const double nEff = effectivePixels(own);
  const double gap = rmse(own, pathBoxReference());

  const int n = 32;
  auto film = [&](int spp, uint64_t seed) { return renderFilm(*box, ir, spp, seed); };
  const std::vector<Rate> rates =
      measureRates({"instant radiosity vs its own limit", "instant radiosity vs the path tracer"},
                   {&own, &pathBoxReference()}, n, film);
  const Rate &self = rates[0], &unbiased = rates[1];
  std::printf(
      "[ rate     ] gap to the path tracer (RMSE of the converged images) %.5f; n_eff %.0f\n", gap,
      nEff);

  expectRate(self, expectedRatio(n, ownSpp), kStratifiedMaxRatio);
  // The floor: at 4N spp the error is within 10% of the gap, and the ratio near 1.
  EXPECT_LT(unbiased.mean, 1.2);
  EXPECT_NEAR(unbiased.error4N, gap, 0.1 * gap);
  // A real bias: many times the camera noise left at 4N spp against its own limit.
  EXPECT_GT(gap, 5 * self.error4N);
}

// Whitted's single scattering (ratio tracking: unbiased for single scattering) against the
// path tracer, which scatters any number of times in the same fog.
TEST(Convergence, SingleScatteringLevelsOffBelowMultipleScattering) {
  const auto single = build(
      fogCube(kSize, R"({"type": "whitted", "volume": "single", "volume_estimator": "track"})"));
  const auto multiple = build(fogCube(kSize, R"({"type": "path", "max_depth": 32})"));
  const int referenceSpp = 2048;
  const Film own = renderFilm(*single, referenceSpp, kReferenceSeed);
  const Film full = renderFilm(*multiple, referenceSpp, kReferenceSeed);
  const double nEff = effectivePixels(own);
  const double gap = rmse(own, full);

  const int n = 8;
  auto film = [&](int spp, uint64_t seed) { return renderFilm(*single, spp, seed); };
  const std::vector<Rate> rates = measureRates(
      {"single scattering vs its own limit", "single scattering vs multiple scattering"},
      {&own, &full}, n, film);
  const Rate &self = rates[0], &unbiased = rates[1];
  double sumOwn = 0, sumFull = 0;
  for (size_t i = 0; i < own.color.size(); ++i)
    sumOwn += own.color[i].y, sumFull += full.color[i].y;
  std::printf(
      "[ rate     ] gap single vs multiple scattering: RMSE %.5f, image mean %.4f vs %.4f; "
      "n_eff %.0f\n",
      gap, sumOwn / double(own.color.size()), sumFull / double(full.color.size()), nEff);

  expectRate(self, expectedRatio(n, referenceSpp), kStratifiedMaxRatio);
  EXPECT_LT(unbiased.mean, 1.2);
  EXPECT_NEAR(unbiased.error4N, gap, 0.1 * gap);
  EXPECT_GT(gap, 5 * self.error4N);
  EXPECT_LT(sumOwn, sumFull) << "single scattering only loses light";
}

}  // namespace
}  // namespace glint
