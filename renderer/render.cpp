// glint — tiled, multithreaded rendering: passes over tiles, the pixel loop, the film.
//
// The loop's parts have a job each: SampleEvaluator (sample_evaluator.h) evaluates a pixel's
// samples, PixelSumsGrid (pixel_sums.h) keeps its sums between passes, and the policies of
// stopping.h say when a pixel (AdaptiveStop, ContrastStop) and the render (BudgetStop) stop.
// What is left here is the order: passes, tiles, pixels, batches.
#include "renderer/render.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <vector>

#include "geometry/error.h"
#include "renderer/pixel_sums.h"
#include "renderer/progress.h"
#include "renderer/render_setup.h"
#include "renderer/sample_evaluator.h"
#include "renderer/stopping.h"
#include "renderer/subdivide.h"

namespace glint {

static_assert(kCameraBatch <= uint32_t(Camera::kMaxRayBatch), "a batch is one pinholeRays call");

PixelWindow tileWindow(int width, int height, int index, int count) {
  if (count <= 0 || index < 0 || index >= count || count > height)
    throw InputError(
        fmt::format("tile {}/{}: need 0 <= I < N <= the image height ({})", index, count, height));
  const auto row = [&](int i) { return int(int64_t(i) * height / count); };
  return {0, row(index), width, row(index + 1)};
}

namespace {

// The pixels a render samples, cut into square tiles (a worker takes one at a time), and the
// index of a pixel in the per-pixel arrays that cover them.
struct TileGrid {
  PixelWindow region;
  int size = 16, across = 0, down = 0;

  TileGrid(PixelWindow r, int tileSize)
      : region(r),
        size(tileSize),
        across((r.width() + tileSize - 1) / tileSize),
        down((r.height() + tileSize - 1) / tileSize) {}
  int count() const { return across * down; }
  PixelWindow tile(int t) const {
    const int x0 = region.x0 + (t % across) * size, y0 = region.y0 + (t / across) * size;
    return {x0, y0, std::min(x0 + size, region.x1), std::min(y0 + size, region.y1)};
  }
  size_t pixels() const { return size_t(region.width()) * size_t(region.height()); }
  size_t index(int x, int y) const {
    return size_t(y - region.y0) * size_t(region.width()) + size_t(x - region.x0);
  }
};

// `window` grown by `margin` pixels on every side, within a width x height image.
PixelWindow grown(PixelWindow window, int margin, int width, int height) {
  return {std::max(0, window.x0 - margin), std::max(0, window.y0 - margin),
          std::min(width, window.x1 + margin), std::min(height, window.y1 + margin)};
}

// Where a pass's pixel sums go. A progressive render keeps them for the next pass...
struct KeepSums {
  PixelSumsGrid& grid;
  PixelSums load(size_t i) const { return grid.load(i); }
  void store(size_t i, const PixelSums& sums, SampleTally&) { grid.store(i, sums); }
};
// ... render()'s single pass writes each pixel straight to the film from zero, keeping none
// (their memory traffic was a visible share of a short render).
struct WriteFilm {
  Film& film;
  PixelSums load(size_t) const { return {}; }
  void store(size_t i, const PixelSums& sums, SampleTally& tally) {
    sums.writeTo(film, i);
    tally.samples += sums.taken;
  }
};

using Tallies = tbb::enumerable_thread_specific<SampleTally>;

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

struct ProgressiveRender::State {
  // Set up once: the pixels, how a sample is evaluated, when a pixel stops, the threads.
  SampleEvaluator evaluator;
  PixelWindow window;  // the film's pixels
  ContrastStop contrast;
  AdaptiveStop adaptive;
  // The pixels sampled: the window, grown by the contrast margin (the per-pixel arrays cover
  // these; the film covers the window).
  TileGrid tiles;
  RenderThreads threads;

  // Where the render is.
  PixelSumsGrid sums;  // per pixel, across passes (none in render()'s single pass)
  Film film;           // the image after the completed passes
  uint32_t spp = 0;
  int passes = 0;
  bool broken = false;  // a dropped pass left the sums part-way, or renderOnce kept none
  // estimatedRelativeError(film), computed when first asked after a pass (a render that only
  // wants its image never pays for it).
  mutable std::optional<double> error;
  RenderStats stats;

  State(const RenderScene& scene, const Integrator& integrator, const RenderSettings& settings,
        const RenderOptions& options)
      : evaluator(scene, integrator, settings),
        window(renderWindow(options, scene.camera().width(), scene.camera().height())),
        contrast(settings.adaptive),
        adaptive(settings.adaptive),
        tiles(grown(window, contrast.margin(), scene.camera().width(), scene.camera().height()),
              options.tileSize),
        threads(options.threads),
        film(window.width(), window.height(), settings.aovs) {
    film.originX = window.x0, film.originY = window.y0;
    film.fullWidth = scene.camera().width(), film.fullHeight = scene.camera().height();
    contrast.start(tiles.pixels());
    stats.threads = threads.count;
  }

  // The pixel loop of one tile, up to `passEnd` samples per pixel; returns the samples taken.
  template <class Sums>
  uint64_t renderTile(int tile, uint32_t passEnd, Sums& sums, const std::atomic<bool>* cancel,
                      SampleTally& tally) const;
  // Every tile, in parallel.
  template <class Sums>
  void renderTiles(uint32_t passEnd, Sums& sums, const std::atomic<bool>* cancel, Tallies& tallies,
                   const std::function<void(uint64_t)>& onTile) {
    threads.arena->execute([&] {
      tbb::parallel_for(
          tbb::blocked_range<int>(0, tiles.count(), 1), [&](const tbb::blocked_range<int>& r) {
            for (int t = r.begin(); t != r.end(); ++t) {
              const uint64_t drawn = renderTile(t, passEnd, sums, cancel, tallies.local());
              if (onTile) onTile(drawn);
            }
          });
    });
  }
  // The per-pixel sums, zero, on the first pass or resume.
  void allocateSums() {
    if (sums.empty()) sums.allocate(tiles.pixels(), film.hasAovs);
  }
  // A pass's time and tallies into the statistics; returns the samples its pixels took where
  // no sums were kept.
  uint64_t addTallies(const Tallies& tallies, std::chrono::steady_clock::time_point start);
  // Every film pixel from the sums.
  void updateFilm();
  // At a contrast checkpoint: the pixels that took `at` samples and meet its rule stop.
  void decide(uint32_t at) {
    threads.arena->execute([&] { contrast.decide(at, sums, tiles.region.width(), adaptive); });
  }
};

template <class Sums>
uint64_t ProgressiveRender::State::renderTile(int tile, uint32_t passEnd, Sums& pixelSums,
                                              const std::atomic<bool>* cancel,
                                              SampleTally& tally) const {
  const PixelWindow t = tiles.tile(tile);
  SampleEvaluator::Batch batch;
  uint64_t drawn = 0;
  for (int y = t.y0; y < t.y1; ++y)
    for (int x = t.x0; x < t.x1; ++x) {
      // A dropped pass: the caller keeps the last completed film.
      if (cancel && cancel->load(std::memory_order_relaxed)) return drawn;
      const size_t i = tiles.index(x, y);
      if (!contrast.sampling(i)) continue;
      PixelSums sums = pixelSums.load(i);
      const bool centre = contrast.beginPixel(sums, passEnd);
      const uint32_t from = sums.taken;
      const PixelKeys keys = evaluator.keys(x, y);
      // Batches never cross a multiple of kCameraBatch, nor a checkpoint where adaptive
      // sampling judges the pixel, so its decisions are the same however the samples are split
      // into passes.
      while (sums.taken < passEnd && !adaptive.stopsAt(sums.moments, sums.taken)) {
        const uint32_t first = sums.taken;
        const uint32_t n = std::min({kCameraBatch - first % kCameraBatch, passEnd - first,
                                     adaptive.batchLimit(first) - first});
        evaluator.evaluate(keys, n, centre, batch, sums, tally);
      }
      drawn += sums.taken - from;
      pixelSums.store(i, sums, tally);
    }
  return drawn;
}

uint64_t ProgressiveRender::State::addTallies(const Tallies& tallies,
                                              std::chrono::steady_clock::time_point start) {
  stats.renderSeconds += secondsSince(start);
  uint64_t samples = 0;
  for (const SampleTally& t : tallies) {
    stats.rays += t.rays;
    t.checks.mergeInto(stats);
    samples += t.samples;
  }
  return samples;
}

void ProgressiveRender::State::updateFilm() {
  // Row by row in parallel: a serial pass over the film was a visible share of a short render.
  const size_t w = size_t(window.width()), h = size_t(window.height());
  std::vector<uint64_t> rowSamples(h, 0);
  threads.arena->execute([&] {
    tbb::parallel_for(size_t(0), h, [&](size_t y) {
      // The film row's pixels in the region (the same indices when the region is the window).
      const size_t r0 = tiles.index(window.x0, window.y0 + int(y));
      uint64_t samples = 0;
      for (size_t x = 0; x < w; ++x) {
        const PixelSums s = sums.load(r0 + x);
        s.writeTo(film, y * w + x);
        samples += contrast.looks(s.taken);
      }
      rowSamples[y] = samples;
    });
  });
  uint64_t samplesTotal = 0;
  for (uint64_t s : rowSamples) samplesTotal += s;
  error.reset();
  stats.meanSpp = w * h > 0 ? double(samplesTotal) / double(w * h) : 0.0;
}

ProgressiveRender::ProgressiveRender(const RenderScene& scene, const Integrator& integrator,
                                     const RenderSettings& settings, const RenderOptions& options)
    : state_(std::make_unique<State>(scene, integrator, settings, options)) {}

ProgressiveRender::~ProgressiveRender() = default;

void ProgressiveRender::resumeFrom(const Film& partial, uint32_t spp) {
  State& st = *state_;
  if (st.tiles.region != st.window)
    throw InputError(
        "cannot continue a crop or tile rendered with anti-aliasing by contrast: its margin "
        "pixels are not in the image");
  const size_t n = st.tiles.pixels();
  if (partial.width != st.film.width || partial.height != st.film.height ||
      partial.originX != st.film.originX || partial.originY != st.film.originY)
    throw InputError(
        fmt::format("cannot continue a {}x{} image at {},{}: this render is {}x{} at {},{}",
                    partial.width, partial.height, partial.originX, partial.originY, st.film.width,
                    st.film.height, st.film.originX, st.film.originY));
  if (partial.samples.size() != n || partial.variance.size() != n || partial.alpha.size() != n)
    throw InputError("cannot continue an image without per-pixel samples and variance");
  if (st.film.hasAovs && !partial.hasAovs)
    throw InputError("cannot continue an image without AOVs into one with them");
  st.allocateSums();
  for (size_t i = 0; i < n; ++i) {
    if (partial.samples[i] > spp)
      throw InputError("an image's pixel holds more samples than its spp");
    st.sums.store(i, PixelSums::readFrom(partial, i));
  }
  st.threads.arena->execute(
      [&] { st.contrast.resume(spp, st.sums, st.tiles.region.width(), st.adaptive); });
  st.spp = spp;
  st.updateFilm();
}

bool ProgressiveRender::renderPass(uint32_t cap, const std::atomic<bool>* cancel,
                                   const std::function<void(uint64_t)>& onTile) {
  return renderTo(std::min(nextPassEnd(state_->spp), cap), cancel, onTile);
}

bool ProgressiveRender::renderTo(uint32_t end, const std::atomic<bool>* cancel,
                                 const std::function<void(uint64_t)>& onTile) {
  State& st = *state_;
  if (st.broken) throw std::logic_error("ProgressiveRender: a dropped pass ended this render");
  if (end <= st.spp) return true;
  st.allocateSums();
  KeepSums sums{st.sums};
  Tallies tallies;
  const auto start = std::chrono::steady_clock::now();
  // With contrast, the pass pauses at every contrast checkpoint on the way (however the caller
  // splits the render, the decisions are taken at the same sample counts).
  for (uint32_t done = st.spp; done < end;) {
    const uint32_t to = st.contrast.pauseAt(done, end);
    st.renderTiles(to, sums, cancel, tallies, onTile);
    if (cancel && cancel->load()) {
      st.broken = true;
      return false;
    }
    if (st.contrast.isCheckpoint(to)) st.decide(to);
    done = to;
  }
  st.addTallies(tallies, start);
  st.spp = end;
  ++st.passes;
  st.updateFilm();
  return true;
}

void ProgressiveRender::renderOnce(uint32_t spp, const std::function<void(uint64_t)>& onTile) {
  State& st = *state_;
  if (st.broken) throw std::logic_error("ProgressiveRender: a dropped pass ended this render");
  // Anti-aliasing by contrast decides at checkpoints from the neighbours' sums, and a resumed
  // or rendered state has sums to continue: those take the passes' way.
  if (st.contrast.on() || st.spp > 0 || !st.sums.empty()) {
    renderTo(spp, nullptr, onTile);
    st.broken = true;
    return;
  }
  st.broken = true;  // no sums: this render cannot go on
  WriteFilm sums{st.film};
  Tallies tallies;
  const auto start = std::chrono::steady_clock::now();
  st.renderTiles(spp, sums, nullptr, tallies, onTile);
  const uint64_t samples = st.addTallies(tallies, start);
  st.spp = spp;
  ++st.passes;
  const size_t n = st.film.color.size();
  st.stats.meanSpp = n ? double(samples) / double(n) : 0.0;
  st.error.reset();
}

uint32_t ProgressiveRender::spp() const { return state_->spp; }
int ProgressiveRender::passes() const { return state_->passes; }
const Film& ProgressiveRender::film() const { return state_->film; }
Film ProgressiveRender::takeFilm() {
  state_->broken = true;
  return std::move(state_->film);
}
double ProgressiveRender::estimatedError() const {
  const State& st = *state_;
  if (!st.error)
    st.threads.arena->execute([&] { st.error = estimatedRelativeErrorInParallel(st.film); });
  return *st.error;
}
const RenderStats& ProgressiveRender::stats() const { return state_->stats; }

namespace {

// renderUntil and render with anti-aliasing by subdivision: one pass, which only Ctrl-C stops.
Film renderSubdividedUntil(const RenderScene& scene, const Integrator& integrator,
                           const RenderSettings& settings, const RenderOptions& options,
                           const StopRule& rule, RenderStats* stats, ProgressiveResult* result,
                           bool resuming) {
  if (resuming)
    throw InputError(
        "cannot continue an image rendered with anti-aliasing by subdivision: it "
        "is rendered in one pass");
  if (rule.timeLimit > 0 || rule.noiseTarget > 0)
    throw InputError(
        "anti-aliasing by subdivision renders in one pass: it takes no time limit "
        "or noise target");
  const uint64_t pixels = options.crop ? uint64_t(options.crop->width()) * options.crop->height()
                                       : uint64_t(scene.camera().width()) * scene.camera().height();
  ProgressBar bar("rendering", 2 * std::max<uint64_t>(pixels, 1), options.progress);
  Film film;
  RenderStats st;
  const bool done = renderSubdivided(scene, integrator, settings, options, &film, &st, rule.cancel,
                                     [&](uint64_t n) { bar.advance(n); });
  if (done) bar.finish();
  if (result) {
    // The most looks a pixel can hold: what "spp" means here.
    result->reason = done ? StopReason::Spp : StopReason::Interrupted;
    result->spp = done ? subdivisionMaxLooks(settings.adaptive.subdivide) : 0;
    result->error = 0;  // a quadrature, not a mean of samples: no noise estimate
    result->passes = done ? 1 : 0;
  }
  if (stats) *stats = st;
  return film;
}

// renderUntil's progress bar, measured in samples: its end the samples up to maxSpp, or
// sooner where a budget will stop the render first; its note the spp reached (and the error,
// under a budget). A render without a budget that will take over a minute says so once, after
// its first pass.
class PassProgress {
 public:
  PassProgress(const StopRule& rule, uint32_t startSpp, double pixels, bool enabled)
      : maxSpp_(rule.maxSpp),
        startSpp_(startSpp),
        pixels_(pixels),
        total_(uint64_t(double(maxSpp_ > startSpp ? maxSpp_ - startSpp : 0) * pixels)),
        enabled_(enabled),
        bar_("rendering", std::max<uint64_t>(total_, 1), enabled) {}
  void advance(uint64_t samples) { bar_.advance(samples); }
  void finish() { bar_.finish(); }
  void passDone(const ProgressiveRender& pr, const BudgetStop& budget, double elapsed) {
    if (budget.limited()) {
      const double done = double(pr.spp() - startSpp_) * pixels_;
      bar_.setTotal(
          uint64_t(budget.expectedSamples(done, double(total_), elapsed, pr.estimatedError())));
      bar_.setNote(fmt::format("{} spp, error {:.2g}%", pr.spp(), 100 * pr.estimatedError()));
      return;
    }
    bar_.setNote(fmt::format("{} spp", pr.spp()));
    if (!enabled_ || warned_) return;
    warned_ = true;
    const double perSpp = budget.secondsPerSpp();
    const double remaining = perSpp * double(maxSpp_ - pr.spp());
    if (remaining > 60)
      bar_.message(fmt::format(
          "glint: {} spp will take about {} more ({} per sample per pixel); Ctrl-C stops "
          "and writes what is done",
          maxSpp_, readableDuration(remaining), readableDuration(perSpp)));
  }

 private:
  uint32_t maxSpp_, startSpp_;
  double pixels_;
  uint64_t total_;
  bool enabled_, warned_ = false;
  ProgressBar bar_;
};

}  // namespace

BudgetedRender::BudgetedRender(const RenderScene& scene, const Integrator& integrator,
                               const RenderSettings& settings, const RenderOptions& options,
                               const StopRule& rule)
    : render_(scene, integrator, settings, options),
      budget_(rule),
      cancel_(rule.cancel),
      began_(std::chrono::steady_clock::now()) {}

std::optional<StopReason> BudgetedRender::stopBeforeNextPass() {
  if (!decided_) {
    const auto error = [&] { return render_.estimatedError(); };
    decision_ =
        budget_.stopBefore(render_.spp(), budget_.nextPass(render_.spp()), seconds(), error);
    if (decision_) reason_ = *decision_;
    decided_ = true;
  }
  return decision_;
}

bool BudgetedRender::nextPass(const std::function<void(uint64_t)>& onTile) {
  if (stopBeforeNextPass()) return false;
  decided_ = false;
  const uint32_t before = render_.spp();
  const auto passStart = std::chrono::steady_clock::now();
  if (!render_.renderTo(budget_.nextPass(before), cancel_, onTile)) {
    reason_ = StopReason::Interrupted;
    return false;
  }
  budget_.passDone(render_.spp() - before, secondsSince(passStart));
  return true;
}

double BudgetedRender::seconds() const { return secondsSince(began_); }

ProgressiveResult BudgetedRender::result() const {
  return {reason_, render_.spp(), render_.estimatedError(), render_.passes()};
}

Film renderUntil(const RenderScene& scene, const Integrator& integrator,
                 const RenderSettings& settings, const RenderOptions& options, const StopRule& rule,
                 RenderStats* stats, ProgressiveResult* result, const Film* resume,
                 uint32_t resumeSpp, const std::function<void(const ProgressiveRender&)>& onPass) {
  if (settings.adaptive.subdivide > 0)
    return renderSubdividedUntil(scene, integrator, settings, options, rule, stats, result,
                                 resume != nullptr);
  BudgetedRender budgeted(scene, integrator, settings, options, rule);
  ProgressiveRender& pr = budgeted.progressive();
  if (resume) pr.resumeFrom(*resume, resumeSpp);
  PassProgress progress(rule, pr.spp(), double(pr.film().width) * double(pr.film().height),
                        options.progress);
  const auto onTile = [&](uint64_t samples) { progress.advance(samples); };
  while (budgeted.nextPass(onTile)) {
    if (onPass) onPass(pr);
    progress.passDone(pr, budgeted.budget(), budgeted.seconds());
  }
  const ProgressiveResult ended = budgeted.result();
  if (ended.reason != StopReason::Interrupted) progress.finish();
  if (result) *result = ended;
  if (stats) *stats = pr.stats();
  return pr.takeFilm();
}

Film render(const RenderScene& scene, const Integrator& integrator, const RenderSettings& settings,
            const RenderOptions& options, RenderStats* stats) {
  if (settings.adaptive.subdivide > 0)
    return renderSubdividedUntil(scene, integrator, settings, options, StopRule{}, stats, nullptr,
                                 false);
  ProgressiveRender pr(scene, integrator, settings, options);
  const uint32_t spp = uint32_t(std::max(settings.spp, 1));
  ProgressBar bar("rendering", uint64_t(spp) * pr.film().color.size(), options.progress);
  pr.renderOnce(spp, [&](uint64_t samples) { bar.advance(samples); });
  bar.finish();
  if (stats) *stats = pr.stats();
  return pr.takeFilm();
}

}  // namespace glint
