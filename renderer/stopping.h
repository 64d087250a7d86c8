// glint — when a render stops sampling: a pixel (adaptive sampling by variance, anti-aliasing
// by contrast), the whole render (spp, time and noise budgets), each a policy of its own that
// the render loop (render.cpp) sets up once and asks at fixed sample counts.
//
// Every decision is taken at fixed sample counts (checkpoints, pass ends) from sums that do
// not depend on how the samples were split into passes or tiles, so a render's image is the
// same whatever the thread count, tile order or pass timing, and whether it ran in one go or
// was continued.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "renderer/film.h"
#include "renderer/pixel_sums.h"
#include "renderer/settings.h"

namespace glint {

// Camera rays handed to the accelerator together (Embree's widest packet), and so the step of
// the pass schedule and of the adaptive checkpoints: a pixel's batches never straddle a
// decision.
inline constexpr uint32_t kCameraBatch = 16;

// ---- Passes -----------------------------------------------------------------------------

// The spp the pass after `done` completed spp ends at (before any cap): 0 → 1 → 2 → 4 → 8 →
// 16 spp and then 16 more each.
uint32_t nextPassEnd(uint32_t done);

// ---- Adaptive sampling by variance ------------------------------------------------------

// Where adaptive sampling may stop a pixel (AdaptiveSettings): at 2, 4 and 8 samples, then at
// every multiple of kCameraBatch, from minSpp on. The early doublings let a pixel of a scene
// without noise (hard shadows, mirrors: only its edges need samples) stop after a few samples,
// as supersampling anti-aliasing does.
bool isAdaptiveCheckpoint(uint32_t spp);
// The first checkpoint after `spp`.
uint32_t nextAdaptiveCheckpoint(uint32_t spp);

// AdaptiveSettings::threshold: a pixel stops when its own samples' variance meets the rule.
// Off (threshold 0), it never stops a pixel and never cuts a batch.
class AdaptiveStop {
 public:
  explicit AdaptiveStop(const AdaptiveSettings& settings);
  bool on() const { return on_; }
  // In the pixel loop: whether a pixel with `n` samples summed in `m` stops here, at a
  // checkpoint from minSpp on. With anti-aliasing by contrast the checkpoints up to 16 are
  // ContrastStop's (it asks allowsStop), so this one starts after them.
  bool stopsAt(const PixelMoments& m, uint32_t n) const {
    return n >= loopFrom_ && isAdaptiveCheckpoint(n) && m.converged(n, threshold2_);
  }
  // Whether the rule lets a pixel with `n` samples stop (always, when off).
  bool allowsStop(const PixelMoments& m, uint32_t n) const {
    return !on_ || (n >= minSpp_ && m.converged(n, threshold2_));
  }
  // Where the batch of camera rays starting at sample `first` must end at the latest: the next
  // checkpoint the pixel is judged at (UINT32_MAX when off).
  uint32_t batchLimit(uint32_t first) const {
    if (!on_) return UINT32_MAX;
    uint32_t check = nextAdaptiveCheckpoint(first);
    while (check < minSpp_) check = nextAdaptiveCheckpoint(check);
    return check;
  }

 private:
  bool on_;
  double threshold2_;
  uint32_t minSpp_;    // at least 2: a variance needs two samples
  uint32_t loopFrom_;  // the first count stopsAt judges (UINT32_MAX when off)
};

// ---- Anti-aliasing by contrast ----------------------------------------------------------

// AdaptiveSettings::contrast: at the checkpoints 1, 2, 4, 8 and 16 a pixel stops when no
// neighbour's mean differs from its own by more than the threshold (on squeezed radiance), and
// the adaptive rule, when on, lets it. A pixel's first look goes through its centre; one the
// first checkpoint does not stop drops that look and starts its stratified samples afresh.
// The decisions are taken between passes over the whole region, from means no decision
// changes, so they do not depend on tiles or threads. Off (contrast 0), every pixel samples.
class ContrastStop {
 public:
  static constexpr std::array<uint32_t, 5> kCheckpoints = {1, 2, 4, 8, 16};

  explicit ContrastStop(const AdaptiveSettings& settings) : contrast_(settings.contrast) {}
  bool on() const { return contrast_ > 0; }
  // How far a window's border pixels can depend on pixels outside it (one pixel per
  // checkpoint): the margin a crop or tile renders around its window; 0 when off.
  int margin() const { return on() ? int(kCheckpoints.size()) : 0; }
  bool isCheckpoint(uint32_t spp) const;
  // Where a pass from `done` toward `end` must pause for a decision: the next checkpoint, or
  // `end`.
  uint32_t pauseAt(uint32_t done, uint32_t end) const;

  // Every pixel of a region of `pixels` samples (when on).
  void start(size_t pixels);
  bool sampling(size_t i) const { return active_.empty() || active_[i] != 0; }
  // A pixel about to take samples up to `passEnd`: true when its next look is the centre look
  // (it has none yet); a pixel past its centre look that goes on drops it (its sums are
  // cleared).
  bool beginPixel(PixelSums& sums, uint32_t passEnd) const {
    if (!on()) return false;
    if (sums.taken == 1 && passEnd > 1) {
      sums = PixelSums{};
      return false;
    }
    return sums.taken == 0;
  }
  // At checkpoint `spp`: stops the sampling pixels of the regionWidth-wide grid that took
  // `spp` samples and meet the rule. Rows in parallel (tbb::parallel_for: in the caller's
  // arena).
  void decide(uint32_t spp, const PixelSumsGrid& sums, int regionWidth,
              const AdaptiveStop& adaptive);
  // After `sums` were rebuilt from a render that reached `spp`: a pixel with fewer samples
  // stopped and stays stopped, and a checkpoint at `spp` is decided again (the file cannot
  // tell a pixel that stopped there from one that went on: both hold its samples).
  void resume(uint32_t spp, const PixelSumsGrid& sums, int regionWidth,
              const AdaptiveStop& adaptive);
  // Camera rays a pixel with `taken` samples traced: one more for a dropped centre look.
  uint32_t looks(uint32_t taken) const { return taken + (on() && taken > 1 ? 1 : 0); }

 private:
  float contrast_;
  std::vector<uint8_t> active_;  // still sampling (a checkpoint has not stopped it)
  // Each pixel's mean, squeezed, as of its last checkpoint (a stopped pixel's mean no longer
  // changes), so a checkpoint squeezes each mean once, not once per neighbour.
  std::vector<std::array<float, 3>> squeezedMeans_;
};

// ---- Budgets: when the whole render stops -----------------------------------------------

// Why a progressive render stopped.
enum class StopReason { Spp, TimeLimit, NoiseTarget, Interrupted };
std::string_view stopReasonName(StopReason reason);  // "spp", "time-limit", ...

// The relative error a noise target is measured in (AdaptiveSettings' metric over the whole
// image): sqrt of the mean over pixels and channels of Var[mean] / (mean² + 0.01), from each
// pixel's own sample variance. 0 for an image with fewer than 2 samples per pixel.
double estimatedRelativeError(const Film& film);
// The same number, its rows summed by tbb::parallel_for (in the caller's arena).
double estimatedRelativeErrorInParallel(const Film& film);

// When a render stops: at the end of the first pass that reaches maxSpp, would run past the
// time limit (judged from the previous pass's rate; the first pass always runs), or brings the
// estimated error to the noise target (checked from 16 spp on: fewer samples underestimate
// rare bright paths). `cancel` (Ctrl-C) stops at once and drops the pass in flight.
struct StopRule {
  uint32_t maxSpp = 16;
  // The passes: the schedule from 1 spp (nextPassEnd; quick first images and time estimates,
  // what budgets use), or false: every 16 from the start, the widest camera-ray packets, for a
  // render that only needs to be interruptible. The images at a given spp are the same.
  bool warmup = true;
  double timeLimit = 0;    // seconds of rendering; 0 = none
  double noiseTarget = 0;  // estimatedRelativeError; 0 = none
  const std::atomic<bool>* cancel = nullptr;
};

// What a user asks of a render beyond its settings: a time limit and a noise target (0: none),
// and whether the spp was asked for too (a budget given no spp has no spp cap; the settings'
// spp, from a sidecar, does not cap it). What `glint render` and the Python module both take.
struct RenderBudget {
  double timeLimit = 0;
  double noiseTarget = 0;
  bool sppAsked = false;
  bool given() const { return timeLimit > 0 || noiseTarget > 0; }
};

// The StopRule of a render of `settings` with `budget`: without a budget, settings.spp in passes
// of 16 (the widest packets; interruptible), or the most looks anti-aliasing by subdivision
// can take; with one, the pass schedule from 1 spp until the budget is met, capped at
// settings.spp only when budget.sppAsked.
StopRule stopRuleFor(const RenderSettings& settings, const RenderBudget& budget,
                     const std::atomic<bool>* cancel);

// A StopRule applied pass by pass (Ctrl-C aside: the pass loop sees that).
class BudgetStop {
 public:
  explicit BudgetStop(const StopRule& rule) : rule_(rule) {}
  // Whether a time limit or noise target may end the render before maxSpp.
  bool limited() const { return rule_.timeLimit > 0 || rule_.noiseTarget > 0; }
  // The end of the pass after `spp`: the schedule (or every 16, without warmup), capped.
  uint32_t nextPass(uint32_t spp) const;
  // Why the render stops before the pass from `spp` to `next`, `elapsed` seconds after it
  // began, or nullopt: render it. `error()` gives estimatedRelativeError, asked only for a
  // noise target from 16 spp on.
  template <class Error>
  std::optional<StopReason> stopBefore(uint32_t spp, uint32_t next, double elapsed,
                                       Error&& error) const {
    if (spp >= rule_.maxSpp) return StopReason::Spp;
    if (rule_.noiseTarget > 0 && spp >= kCameraBatch && error() > 0 && error() <= rule_.noiseTarget)
      return StopReason::NoiseTarget;
    if (rule_.timeLimit > 0 && passes_ > 0 &&
        elapsed + predictedSeconds(spp, next) > rule_.timeLimit)
      return StopReason::TimeLimit;
    return std::nullopt;
  }
  // A pass of `spp` samples per pixel took `seconds`.
  void passDone(uint32_t spp, double seconds) {
    ++passes_;
    lastPassSpp_ = spp;
    lastPassSeconds_ = seconds;
  }
  // The seconds the pass from `spp` to `next` will take at the last pass's rate per sample.
  double predictedSeconds(uint32_t spp, uint32_t next) const {
    return secondsPerSpp() * double(next - spp);
  }
  double secondsPerSpp() const { return lastPassSeconds_ / std::max<uint32_t>(lastPassSpp_, 1); }
  // Where a render that has `done` samples in all after `elapsed` seconds and reached `error`
  // will end, in samples, when a budget comes before `total` (the samples up to maxSpp): the
  // progress bar's end.
  double expectedSamples(double done, double total, double elapsed, double error) const;

 private:
  StopRule rule_;
  int passes_ = 0;
  uint32_t lastPassSpp_ = 0;
  double lastPassSeconds_ = 0;
};

}  // namespace glint
