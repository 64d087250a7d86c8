// glint — when a render stops sampling (see stopping.h).
#include "renderer/stopping.h"

#include <tbb/parallel_for.h>

#include <cmath>

#include "renderer/subdivide.h"

namespace glint {

// ---- Passes -----------------------------------------------------------------------------

uint32_t nextPassEnd(uint32_t done) {
  constexpr uint32_t kStep = kCameraBatch;  // 16: passes after the first doublings
  if (done >= UINT32_MAX - kStep) return UINT32_MAX;
  if (done < kStep) {
    uint32_t end = 1;
    while (end <= done) end *= 2;
    return end;
  }
  return (done / kStep + 1) * kStep;
}

// ---- Adaptive sampling by variance ------------------------------------------------------

bool isAdaptiveCheckpoint(uint32_t spp) {
  return spp % kCameraBatch == 0 || (spp < kCameraBatch && (spp & (spp - 1)) == 0);
}

uint32_t nextAdaptiveCheckpoint(uint32_t spp) {
  if (spp >= kCameraBatch / 2) return (spp / kCameraBatch + 1) * kCameraBatch;
  uint32_t next = 2;
  while (next <= spp) next *= 2;
  return next;
}

AdaptiveStop::AdaptiveStop(const AdaptiveSettings& settings)
    : on_(settings.threshold > 0),
      threshold2_(double(settings.threshold) * settings.threshold),
      minSpp_(uint32_t(std::max(2, settings.minSpp))) {
  // With contrast, the checkpoints up to kCameraBatch are decided between passes.
  loopFrom_ = !on_                    ? UINT32_MAX
              : settings.contrast > 0 ? std::max(minSpp_, kCameraBatch + 1)
                                      : minSpp_;
}

// ---- Anti-aliasing by contrast ----------------------------------------------------------

bool ContrastStop::isCheckpoint(uint32_t spp) const {
  return on() && std::find(kCheckpoints.begin(), kCheckpoints.end(), spp) != kCheckpoints.end();
}

uint32_t ContrastStop::pauseAt(uint32_t done, uint32_t end) const {
  if (on())
    for (uint32_t c : kCheckpoints)
      if (c > done) return std::min(end, c);
  return end;
}

void ContrastStop::start(size_t pixels) {
  if (on()) active_.assign(pixels, 1);
}

void ContrastStop::decide(uint32_t spp, const PixelSumsGrid& sums, int regionWidth,
                          const AdaptiveStop& adaptive) {
  const int w = regionWidth, h = int(active_.size() / size_t(w));
  // The pixels that sampled up to this checkpoint bring their squeezed means up to date; the
  // others stopped earlier, with the mean they have (all of them, at a render's first
  // checkpoint: a resumed render's pixels may have stopped in the run it continues). A pixel
  // with no samples, only possible in a resumed render, compares as equal to every neighbour.
  const bool first = squeezedMeans_.empty();
  if (first) squeezedMeans_.resize(active_.size());
  tbb::parallel_for(0, h, [&](int y) {
    for (size_t i = size_t(y) * size_t(w), end = i + size_t(w); i < end; ++i) {
      const uint32_t taken = sums.taken(i);
      if (taken == 0 || (!first && taken != spp)) continue;
      const Rgb mean = sums.moments(i).mean(taken);
      for (int c = 0; c < 3; ++c) squeezedMeans_[i][c] = squeezedRadiance(mean[c]);
    }
  });
  // Decided from the means as they are at this checkpoint, which no decision changes: a pixel
  // reads its neighbours' means, never their flags, so each row clears its own flags in place.
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      if (!active_[i] || sums.taken(i) != spp) continue;
      if (!adaptive.allowsStop(sums.moments(i), spp)) continue;
      const std::array<float, 3>& mean = squeezedMeans_[i];
      bool quiet = true;
      for (int dy = -1; dy <= 1 && quiet; ++dy)
        for (int dx = -1; dx <= 1 && quiet; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          const size_t j = size_t(ny) * size_t(w) + size_t(nx);
          if (!sums.taken(j)) continue;
          const std::array<float, 3>& other = squeezedMeans_[j];
          for (int c = 0; c < 3; ++c) quiet = quiet && std::abs(mean[c] - other[c]) <= contrast_;
        }
      if (quiet) active_[i] = 0;
    }
  });
}

void ContrastStop::resume(uint32_t spp, const PixelSumsGrid& sums, int regionWidth,
                          const AdaptiveStop& adaptive) {
  if (!on()) return;
  for (size_t i = 0; i < active_.size(); ++i) active_[i] = sums.taken(i) >= spp;
  if (isCheckpoint(spp)) decide(spp, sums, regionWidth, adaptive);
}

// ---- Budgets ----------------------------------------------------------------------------

StopRule stopRuleFor(const RenderSettings& settings, const RenderBudget& budget,
                     const std::atomic<bool>* cancel) {
  // The spp cap of a budgeted render given no spp: none, in effect (glint:spp is an int).
  constexpr uint32_t kNoSppCap = 0x7fffffff;
  StopRule rule;
  rule.cancel = cancel;
  rule.timeLimit = budget.timeLimit;
  rule.noiseTarget = budget.noiseTarget;
  rule.maxSpp = budget.given() && !budget.sppAsked ? kNoSppCap : uint32_t(settings.spp);
  // Anti-aliasing by subdivision records the most looks a pixel can hold as its spp (what
  // --resume compares); it refuses budgets itself.
  if (settings.adaptive.subdivide > 0 && !budget.given())
    rule.maxSpp = subdivisionMaxLooks(settings.adaptive.subdivide);
  // A budget needs small first passes to fit a short limit; a plain render passes every 16 spp
  // (the widest packets), which keeps it interruptible.
  rule.warmup = budget.given();
  return rule;
}

std::string_view stopReasonName(StopReason reason) {
  switch (reason) {
    case StopReason::Spp:
      return "spp";
    case StopReason::TimeLimit:
      return "time-limit";
    case StopReason::NoiseTarget:
      return "noise-target";
    case StopReason::Interrupted:
      return "interrupted";
  }
  return "spp";
}

namespace {

// Row y's share of estimatedRelativeError: the sum over its pixels of Var[mean] / (mean² + 0.01)
// per channel; nullopt when a pixel has fewer than 2 samples (no variance yet).
std::optional<double> rowRelativeError(const Film& film, size_t y) {
  const size_t w = size_t(film.width);
  double sum = 0;
  for (size_t i = y * w; i < (y + 1) * w; ++i) {
    if (!film.samples.empty() && film.samples[i] < 2) return std::nullopt;
    for (int c = 0; c < 3; ++c) {
      const double mean = film.color[i][c];
      sum += double(film.variance[i][c]) / (mean * mean + 0.01);
    }
  }
  return sum;
}

// estimatedRelativeError with the rows visited by `forEachRow(count, body)`, serially or in
// parallel: the sums go row by row and then over the rows in order, so every way of visiting
// them gives the same number.
template <class ForEachRow>
double relativeError(const Film& film, ForEachRow&& forEachRow) {
  const size_t n = film.color.size();
  if (n == 0 || film.variance.size() != n || size_t(film.width) * size_t(film.height) != n)
    return 0;
  std::vector<std::optional<double>> rows(size_t(film.height));
  forEachRow(rows.size(), [&](size_t y) { rows[y] = rowRelativeError(film, y); });
  double sum = 0;
  for (const std::optional<double>& r : rows) {
    if (!r) return 0;
    sum += *r;
  }
  return std::sqrt(sum / (3.0 * double(n)));
}

}  // namespace

double estimatedRelativeError(const Film& film) {
  return relativeError(film, [](size_t count, const auto& body) {
    for (size_t y = 0; y < count; ++y) body(y);
  });
}

double estimatedRelativeErrorInParallel(const Film& film) {
  return relativeError(
      film, [](size_t count, const auto& body) { tbb::parallel_for(size_t(0), count, body); });
}

uint32_t BudgetStop::nextPass(uint32_t spp) const {
  return std::min(rule_.warmup ? nextPassEnd(spp) : (spp / kCameraBatch + 1) * kCameraBatch,
                  rule_.maxSpp);
}

double BudgetStop::expectedSamples(double done, double total, double elapsed, double error) const {
  if (rule_.timeLimit > 0)
    total = std::min(total, done * rule_.timeLimit / std::max(elapsed, 1e-3));
  if (rule_.noiseTarget > 0 && error > 0) {
    const double ratio = error / rule_.noiseTarget;
    total = std::min(total, done * std::max(1.0, ratio * ratio));
  }
  return std::max(total, done);
}

}  // namespace glint
