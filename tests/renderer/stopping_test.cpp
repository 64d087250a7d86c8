// Tests for the stopping policies (renderer/stopping.h), each on its own with made-up sums:
// adaptive sampling stops a pixel only at its checkpoints and cuts batches there; anti-aliasing
// by contrast stops the pixels whose neighbourhood is flat, from the means as of each pixel's
// last checkpoint, and keeps its decisions over a resume; a budget stops a render on spp, noise
// or time in that order, and only asks for the error estimate when it has a noise target.
#include "renderer/stopping.h"

#include <gtest/gtest.h>

#include <vector>

namespace glint {
namespace {

// The moments of `n` samples of radiance `v` each: no variance.
PixelMoments flat(float v, uint32_t n) {
  PixelMoments m;
  for (uint32_t i = 0; i < n; ++i) m.add(Rgb{v, v, v});
  return m;
}

// Moments of `n` samples alternating 0 and 2: mean 1, a large variance.
PixelMoments noisy(uint32_t n) {
  PixelMoments m;
  for (uint32_t i = 0; i < n; ++i) m.add(i % 2 ? Rgb{2, 2, 2} : Rgb{0, 0, 0});
  return m;
}

AdaptiveSettings adaptiveSettings(float threshold, float contrast, int minSpp) {
  AdaptiveSettings s;
  s.threshold = threshold;
  s.contrast = contrast;
  s.minSpp = minSpp;
  return s;
}

TEST(AdaptiveStop, StopsAConvergedPixelOnlyAtItsCheckpointsFromMinSpp) {
  const AdaptiveStop stop(adaptiveSettings(0.05f, 0, 4));
  std::vector<uint32_t> stops;
  for (uint32_t n = 1; n <= 64; ++n)
    if (stop.stopsAt(flat(1, n), n)) stops.push_back(n);
  EXPECT_EQ(stops, (std::vector<uint32_t>{4, 8, 16, 32, 48, 64}));
  EXPECT_FALSE(stop.stopsAt(noisy(32), 32));
  // Batches end at the next checkpoint the pixel is judged at.
  EXPECT_EQ(stop.batchLimit(0), 4u);  // 2 comes before minSpp
  EXPECT_EQ(stop.batchLimit(4), 8u);
  EXPECT_EQ(stop.batchLimit(9), 16u);
  EXPECT_EQ(stop.batchLimit(17), 32u);
}

TEST(AdaptiveStop, WithContrastTheLoopJudgesOnlyPastSixteen) {
  const AdaptiveStop stop(adaptiveSettings(0.05f, 0.1f, 2));
  EXPECT_FALSE(stop.stopsAt(flat(1, 8), 8));
  EXPECT_FALSE(stop.stopsAt(flat(1, 16), 16));
  EXPECT_TRUE(stop.stopsAt(flat(1, 32), 32));
  // The contrast checkpoints ask allowsStop, which holds from minSpp on.
  EXPECT_FALSE(stop.allowsStop(flat(1, 1), 1));
  EXPECT_TRUE(stop.allowsStop(flat(1, 2), 2));
  EXPECT_FALSE(stop.allowsStop(noisy(16), 16));
}

TEST(AdaptiveStop, OffItNeverStopsAndNeverCutsABatch) {
  const AdaptiveStop stop(adaptiveSettings(0, 0, 2));
  EXPECT_FALSE(stop.on());
  for (uint32_t n = 1; n <= 64; ++n) EXPECT_FALSE(stop.stopsAt(flat(1, n), n)) << n;
  EXPECT_EQ(stop.batchLimit(0), UINT32_MAX);
  EXPECT_TRUE(stop.allowsStop(noisy(4), 4));  // contrast alone decides
}

TEST(PassSchedule, AdaptiveCheckpointsAreTheEarlyDoublingsThenEverySixteen) {
  std::vector<uint32_t> checks;
  for (uint32_t n = 1; n <= 48; ++n)
    if (isAdaptiveCheckpoint(n)) checks.push_back(n);
  EXPECT_EQ(checks, (std::vector<uint32_t>{1, 2, 4, 8, 16, 32, 48}));
  EXPECT_EQ(nextAdaptiveCheckpoint(0), 2u);
  EXPECT_EQ(nextAdaptiveCheckpoint(5), 8u);
  EXPECT_EQ(nextAdaptiveCheckpoint(8), 16u);
  EXPECT_EQ(nextAdaptiveCheckpoint(16), 32u);
}

// A w x h grid of pixels that took `taken` samples of radiance `v` each.
PixelSumsGrid grid(int w, int h, uint32_t taken, float v) {
  PixelSumsGrid g;
  g.allocate(size_t(w) * size_t(h), false);
  for (size_t i = 0; i < size_t(w) * size_t(h); ++i) {
    PixelSums s;
    s.moments = flat(v, taken);
    s.taken = taken;
    g.store(i, s);
  }
  return g;
}

void setPixel(PixelSumsGrid& g, int w, int x, int y, PixelMoments m, uint32_t taken) {
  PixelSums s;
  s.moments = m;
  s.taken = taken;
  g.store(size_t(y) * size_t(w) + size_t(x), s);
}

// "#" for a pixel still sampling, "." for a stopped one, row by row.
std::string sampling(const ContrastStop& stop, int w, int h) {
  std::string out;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) out += stop.sampling(size_t(y) * size_t(w) + size_t(x)) ? '#' : '.';
    out += '\n';
  }
  return out;
}

TEST(ContrastStop, StopsThePixelsWhoseNeighbourhoodIsFlat) {
  constexpr int w = 5, h = 5;
  PixelSumsGrid g = grid(w, h, 1, 0.5f);
  setPixel(g, w, 2, 2, flat(10, 1), 1);  // one bright pixel
  const AdaptiveStop adaptive(adaptiveSettings(0, 0.1f, 2));
  ContrastStop stop(adaptiveSettings(0, 0.1f, 2));
  stop.start(size_t(w) * h);
  EXPECT_EQ(sampling(stop, w, h), "#####\n#####\n#####\n#####\n#####\n");
  stop.decide(1, g, w, adaptive);
  EXPECT_EQ(sampling(stop, w, h), ".....\n.###.\n.###.\n.###.\n.....\n");
  // The bright pixel turns out flat at 2 samples: each pixel that took them reads the new
  // means, the stopped ring its means of checkpoint 1, and the whole neighbourhood stops.
  for (int y = 1; y <= 3; ++y)
    for (int x = 1; x <= 3; ++x) setPixel(g, w, x, y, flat(0.5f, 2), 2);
  stop.decide(2, g, w, adaptive);
  EXPECT_EQ(sampling(stop, w, h), ".....\n.....\n.....\n.....\n.....\n");
}

TEST(ContrastStop, APixelStopsOnlyWhereTheAdaptiveRuleLetsIt) {
  constexpr int w = 3, h = 3;
  const PixelSumsGrid g = grid(w, h, 1, 0.5f);
  ContrastStop stop(adaptiveSettings(0.05f, 0.1f, 2));
  stop.start(size_t(w) * h);
  // All flat, but one sample gives no variance for the adaptive rule to judge.
  stop.decide(1, g, w, AdaptiveStop(adaptiveSettings(0.05f, 0.1f, 2)));
  EXPECT_EQ(sampling(stop, w, h), "###\n###\n###\n");
  PixelSumsGrid two = grid(w, h, 2, 0.5f);
  setPixel(two, w, 0, 0, noisy(2), 2);
  stop.decide(2, two, w, AdaptiveStop(adaptiveSettings(0.05f, 0.1f, 2)));
  // The noisy pixel goes on, and so do its neighbours: squeezed, its mean of 1 is 0.5 and
  // theirs of 0.5 is 0.33.
  EXPECT_EQ(sampling(stop, w, h), "##.\n##.\n...\n");
}

TEST(ContrastStop, TheCentreLookIsTheFirstAndIsDroppedByAPixelThatGoesOn) {
  const ContrastStop stop(adaptiveSettings(0, 0.1f, 2));
  PixelSums sums;
  EXPECT_TRUE(stop.beginPixel(sums, 1));
  sums.add(Rgb{3, 3, 3}, PathAovs{});
  PixelSums kept = sums;
  EXPECT_FALSE(stop.beginPixel(kept, 1));  // a pass that ends at 1 again: nothing to drop
  EXPECT_EQ(kept.taken, 1u);
  EXPECT_FALSE(stop.beginPixel(sums, 2));
  EXPECT_EQ(sums.taken, 0u);
  EXPECT_EQ(sums.moments.sum[0], 0.0);
  EXPECT_EQ(stop.looks(1), 1u);
  EXPECT_EQ(stop.looks(2), 3u);  // the dropped centre was traced too
  // Off, there is no centre look.
  const ContrastStop off(adaptiveSettings(0, 0, 2));
  PixelSums none;
  EXPECT_FALSE(off.beginPixel(none, 1));
  EXPECT_EQ(off.looks(2), 2u);
  EXPECT_TRUE(off.sampling(0));
}

TEST(ContrastStop, PassesPauseAtEveryCheckpoint) {
  const ContrastStop stop(adaptiveSettings(0, 0.1f, 2));
  EXPECT_EQ(stop.pauseAt(0, 64), 1u);
  EXPECT_EQ(stop.pauseAt(1, 64), 2u);
  EXPECT_EQ(stop.pauseAt(3, 64), 4u);
  EXPECT_EQ(stop.pauseAt(8, 12), 12u);
  EXPECT_EQ(stop.pauseAt(16, 64), 64u);
  EXPECT_TRUE(stop.isCheckpoint(16));
  EXPECT_FALSE(stop.isCheckpoint(32));
  EXPECT_EQ(stop.margin(), 5);
  const ContrastStop off(adaptiveSettings(0, 0, 2));
  EXPECT_EQ(off.pauseAt(0, 64), 64u);
  EXPECT_FALSE(off.isCheckpoint(1));
  EXPECT_EQ(off.margin(), 0);
}

TEST(ContrastStop, AResumedRenderKeepsItsStoppedPixelsAndDecidesItsCheckpointAgain) {
  constexpr int w = 4, h = 1;
  PixelSumsGrid g = grid(w, h, 4, 0.5f);
  setPixel(g, w, 0, 0, flat(0.5f, 2), 2);  // stopped at checkpoint 2
  setPixel(g, w, 3, 0, flat(10, 4), 4);    // bright: its neighbour goes on
  const AdaptiveSettings settings = adaptiveSettings(0, 0.1f, 2);
  ContrastStop stop(settings);
  stop.start(size_t(w) * h);
  stop.resume(4, g, w, AdaptiveStop(settings));
  EXPECT_EQ(sampling(stop, w, h), "..##\n");
  // Resumed off a checkpoint, nothing is decided: only the stopped pixel stays stopped.
  PixelSumsGrid flatAt5 = grid(w, h, 5, 0.5f);
  setPixel(flatAt5, w, 0, 0, flat(0.5f, 4), 4);
  ContrastStop later(settings);
  later.start(size_t(w) * h);
  later.resume(5, flatAt5, w, AdaptiveStop(settings));
  EXPECT_EQ(sampling(later, w, h), ".###\n");
}

TEST(BudgetStop, StopsOnSppThenNoiseThenTime) {
  StopRule rule;
  rule.maxSpp = 64;
  rule.noiseTarget = 0.01;
  rule.timeLimit = 10;
  BudgetStop budget(rule);
  const auto error = [](double e) { return [e] { return e; }; };
  EXPECT_EQ(budget.stopBefore(64, 64, 100, error(0.001)), StopReason::Spp);
  // The noise target is judged from 16 spp on, and a zero estimate (too few samples) is none.
  EXPECT_EQ(budget.stopBefore(8, 16, 0, error(0.001)), std::nullopt);
  EXPECT_EQ(budget.stopBefore(16, 32, 0, error(0.001)), StopReason::NoiseTarget);
  EXPECT_EQ(budget.stopBefore(16, 32, 0, error(0)), std::nullopt);
  EXPECT_EQ(budget.stopBefore(16, 32, 0, error(0.02)), std::nullopt);
  // The first pass always runs; then the next pass is judged at the last one's rate: 4 spp
  // in 2 s makes 16 more 8 s.
  EXPECT_EQ(budget.stopBefore(0, 1, 100, error(1)), std::nullopt);
  budget.passDone(4, 2);
  EXPECT_DOUBLE_EQ(budget.predictedSeconds(16, 32), 8);
  EXPECT_EQ(budget.stopBefore(16, 32, 1.5, error(1)), std::nullopt);
  EXPECT_EQ(budget.stopBefore(16, 32, 2.5, error(1)), StopReason::TimeLimit);
}

TEST(BudgetStop, AsksForTheErrorOnlyWithANoiseTarget) {
  StopRule rule;
  rule.maxSpp = 64;
  BudgetStop budget(rule);
  int asked = 0;
  EXPECT_EQ(budget.stopBefore(32, 48, 0, [&] { return ++asked, 0.0; }), std::nullopt);
  EXPECT_EQ(asked, 0);
  EXPECT_FALSE(budget.limited());
}

TEST(BudgetStop, PassesFollowTheScheduleOrEverySixteenUpToTheCap) {
  StopRule rule;
  rule.maxSpp = 40;
  EXPECT_EQ(BudgetStop(rule).nextPass(0), 1u);
  EXPECT_EQ(BudgetStop(rule).nextPass(8), 16u);
  EXPECT_EQ(BudgetStop(rule).nextPass(32), 40u);
  rule.warmup = false;
  EXPECT_EQ(BudgetStop(rule).nextPass(0), 16u);
  EXPECT_EQ(BudgetStop(rule).nextPass(5), 16u);
  EXPECT_EQ(BudgetStop(rule).nextPass(32), 40u);
}

TEST(BudgetStop, ExpectsTheEndWhereTheFirstBudgetComes) {
  StopRule rule;
  rule.maxSpp = 1024;
  rule.timeLimit = 10;
  const BudgetStop timed(rule);
  // 100 samples in 2 s: 500 by the limit, under the 1000 to maxSpp.
  EXPECT_DOUBLE_EQ(timed.expectedSamples(100, 1000, 2, 0), 500);
  EXPECT_DOUBLE_EQ(timed.expectedSamples(100, 300, 2, 0), 300);
  rule.timeLimit = 0;
  rule.noiseTarget = 0.01;
  // The error falls as 1/sqrt(samples): twice the target takes four times the samples.
  EXPECT_DOUBLE_EQ(BudgetStop(rule).expectedSamples(100, 1000, 2, 0.02), 400);
  // Never less than what is done.
  EXPECT_DOUBLE_EQ(BudgetStop(rule).expectedSamples(100, 1000, 2, 0.005), 100);
}

}  // namespace
}  // namespace glint
