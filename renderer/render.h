// glint — the render loop: tiles over threads, samples per pixel, statistics.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>

#include "renderer/film.h"
#include "renderer/integrator.h"
#include "renderer/scene.h"
#include "renderer/settings.h"
#include "renderer/stopping.h"

namespace glint {

// The sampler dimensions of one camera path, the same for every scene so that switching depth
// of field or motion blur on or off changes the camera ray and nothing else (an aperture of 0
// renders the pinhole image exactly). The lens pair and the time are drawn only when the scene
// needs them (a camera with an aperture; Feature::MotionBlur), otherwise the lens centre and
// time 0 are used and the dimensions stay unused.
inline constexpr uint32_t kFilmDimension = 0;        // 0-1: position in the pixel (filter)
inline constexpr uint32_t kLensDimension = 2;        // 2-3: point on the aperture
inline constexpr uint32_t kTimeDimension = 4;        // 4: shutter time, stratified per pixel
inline constexpr uint32_t kIntegratorDimension = 5;  // 5-: the integrator's

struct RenderStats {
  double renderSeconds = 0;
  int threads = 0;
  RayCounters rays;
  uint64_t nonfiniteSamples = 0;  // NaN/Inf radiance samples: counted, replaced by zero
  // The largest channel of any one sample that reached the film: the tail a mean hides. Under
  // a sky of radiance 1 a bounce adds at most about 2.25 to a sample of a surface without
  // emission (tests/renderer/energy_bound_test.cpp derives the bound and reads this).
  float brightestSample = 0;
  double meanSpp = 0;  // camera rays a pixel traced on average (< spp when adaptive)
};

// What the film's guard saw of the samples it let through or dropped.
struct SampleChecks {
  uint64_t nonfinite = 0;
  float brightest = 0;
  void mergeInto(RenderStats& stats) const {
    stats.nonfiniteSamples += nonfinite;
    stats.brightestSample = std::max(stats.brightestSample, brightest);
  }
};

// The radiance a camera ray brings to the film once the accelerator has traced it (`found`:
// its hit, instance Hit::kInvalid when it escaped): the integrator's LiFromHit, with a NaN/Inf
// result counted in checks->nonfinite and replaced by zero, so it never reaches the film, and
// the brightest channel of the rest kept in checks->brightest.
inline Rgb cameraRadiance(const Integrator& integrator, const Ray& ray, const Hit& found,
                          Sampler& sampler, RayCounters& rays, PathAovs& aovs,
                          SampleChecks* checks) {
  const Hit* hit = found.instance != Hit::kInvalid ? &found : nullptr;
  const Rgb L = integrator.LiFromHit(ray, hit, sampler, rays, aovs);
  if (isFinite(L)) {
    checks->brightest = std::max(checks->brightest, maxComponent(L));
    return L;
  }
  ++checks->nonfinite;
  return {};
}

// A rectangle of pixels [x0, x1) x [y0, y1) of the image.
struct PixelWindow {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
  friend bool operator==(const PixelWindow&, const PixelWindow&) = default;
};

// The I-th of N horizontal bands of a width x height image (0 <= index < count <= height):
// rows [floor(I H / N), floor((I + 1) H / N)). A fixed layout, so N tasks rendering tiles 0..N-1
// cover the frame exactly once. Throws InputError for an index or count outside those bounds.
PixelWindow tileWindow(int width, int height, int index, int count);

struct RenderOptions {
  int threads = 0;        // 0 = all hardware threads
  bool progress = false;  // draw a progress bar on stderr
  int tileSize = 16;
  // Render only these pixels (inside the image; not empty). Samples are keyed by the pixel's
  // place in the whole image, so each pixel is exactly what a whole-frame render gives.
  std::optional<PixelWindow> crop;
};

// Renders `scene` with `integrator` at the camera's resolution (or its options.crop window: a
// film of that size at that origin), settings.spp samples per pixel. Each pixel's samples are
// addressed by (pixel, sample, seed), so the result does not depend on thread count, tile
// order or cropping. NaN/Inf samples never reach the film. Throws InputError for a crop
// outside the image. One pass of ProgressiveRender (below) to settings.spp: a progressive or
// budgeted render that reached N spp is this function's image at N spp.
Film render(const RenderScene& scene, const Integrator& integrator, const RenderSettings& settings,
            const RenderOptions& options, RenderStats* stats);

// ---- Progressive rendering: passes, budgets, interruption ----------------------------------
//
// A render is a sequence of passes over the whole image. Pass boundaries are fixed: a pass
// takes every pixel from one boundary to the next, 0 → 1 → 2 → 4 → 8 → 16 spp and then 16
// more each (nextPassEnd), the last pass cut short at the render's spp. Each pixel keeps its
// sums in double across passes in sample order, and a pixel's camera rays go to the
// accelerator in batches that never cross a multiple of 16, so the image after a pass is a
// pure function of the scene, seed and spp reached: whatever the thread count, pass timing, or
// whether the render ran in one go, stopped on a budget, or was continued (to float rounding,
// there: the continued sums are rebuilt from the stored mean and variance). When pixels and
// renders stop (adaptive sampling, contrast, StopRule's budgets) is stopping.h's.

// The per-pixel sums of a render in progress and the film of its last completed pass.
class ProgressiveRender {
 public:
  // Throws InputError for a crop outside the image (as render()).
  ProgressiveRender(const RenderScene& scene, const Integrator& integrator,
                    const RenderSettings& settings, const RenderOptions& options);
  ~ProgressiveRender();
  ProgressiveRender(const ProgressiveRender&) = delete;
  ProgressiveRender& operator=(const ProgressiveRender&) = delete;

  // Starts from `partial`, an earlier render of the same scene, seed and window that reached
  // `spp` (its per-pixel samples, mean, variance, alpha and AOVs; the sums are rebuilt from
  // them). Throws InputError when its size or channels do not fit this render.
  void resumeFrom(const Film& partial, uint32_t spp);

  // Renders the next pass, up to min(nextPassEnd(spp()), cap). Returns false when `cancel`
  // became true during the pass: the pass is dropped, film() stays at the last completed pass
  // and this render cannot go on. `onTile` (may be empty) is called from worker threads with
  // the samples each finished tile took.
  bool renderPass(uint32_t cap, const std::atomic<bool>* cancel = nullptr,
                  const std::function<void(uint64_t)>& onTile = {});
  // One pass from spp() to `end`, off the schedule: what render() does (its camera rays go to
  // the accelerator 16 at a time from the first sample, the widest packets). The image does
  // not depend on how samples are split into passes (tests PassSplits.*), so it is the
  // schedule's image at `end`.
  bool renderTo(uint32_t end, const std::atomic<bool>* cancel = nullptr,
                const std::function<void(uint64_t)>& onTile = {});

  // What render() does: `spp` samples per pixel in one pass from nothing, each pixel's
  // samples summed on the stack and written straight to the film, with no per-pixel sums kept
  // (their memory traffic was a visible share of a short render). The same image as
  // renderTo(spp); the render cannot go on afterwards. With anti-aliasing by contrast (whose
  // checkpoints need the sums), or after a resume or a pass, it is renderTo(spp).
  void renderOnce(uint32_t spp, const std::function<void(uint64_t)>& onTile = {});

  uint32_t spp() const;              // samples per pixel of the completed passes
  int passes() const;                // passes completed by this object (not counting a resume)
  const Film& film() const;          // the image after the completed passes
  Film takeFilm();                   // moves it out; the render cannot go on
  double estimatedError() const;     // estimatedRelativeError(film())
  const RenderStats& stats() const;  // summed over the completed passes

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// What renderUntil did.
struct ProgressiveResult {
  StopReason reason = StopReason::Spp;
  uint32_t spp = 0;  // reached
  double error = 0;  // estimatedRelativeError at the end
  int passes = 0;
};

// renderUntil one pass at a time: the passes `rule` allows, for a caller that looks at the image
// after each (the Python module's progressive render; renderUntil is this loop with a progress
// bar).
class BudgetedRender {
 public:
  // Throws InputError for a crop outside the image (as render()).
  BudgetedRender(const RenderScene& scene, const Integrator& integrator,
                 const RenderSettings& settings, const RenderOptions& options,
                 const StopRule& rule);
  // Whether the rule ends the render before the next pass, and why. Decided once per pass (a
  // time limit's answer changes with time), and nextPass() follows the decision.
  std::optional<StopReason> stopBeforeNextPass();
  // Renders the next pass, or returns false when the render is over: the rule stops it before
  // the pass, or its `cancel` during it (the pass is dropped). result() says why.
  bool nextPass(const std::function<void(uint64_t)>& onTile = {});
  ProgressiveRender& progressive() { return render_; }
  const ProgressiveRender& progressive() const { return render_; }
  const BudgetStop& budget() const { return budget_; }
  double seconds() const;            // since construction
  ProgressiveResult result() const;  // the passes so far, and why the render stopped

 private:
  ProgressiveRender render_;
  BudgetStop budget_;
  const std::atomic<bool>* cancel_;
  std::chrono::steady_clock::time_point began_;
  StopReason reason_ = StopReason::Spp;
  bool decided_ = false;  // stopBeforeNextPass() decided for the pass after the last one
  std::optional<StopReason> decision_;
};

// Renders passes until `rule` says stop (from `resume`'s state when given: a film that
// reached `resumeSpp`). With options.progress, a bar on stderr measured in samples (its end
// estimated from the time limit or noise target when they come first), and, after the first
// pass, the estimated time of a render expected to take over a minute. `onPass` (may be
// empty) sees each completed pass: a preview shows it.
Film renderUntil(const RenderScene& scene, const Integrator& integrator,
                 const RenderSettings& settings, const RenderOptions& options, const StopRule& rule,
                 RenderStats* stats, ProgressiveResult* result, const Film* resume = nullptr,
                 uint32_t resumeSpp = 0,
                 const std::function<void(const ProgressiveRender&)>& onPass = {});

}  // namespace glint
