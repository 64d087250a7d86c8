// glint — tiled, multithreaded rendering.
#include "renderer/render.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <optional>
#include <vector>

#include "geometry/error.h"
#include "renderer/filter.h"
#include "renderer/progress.h"
#include "renderer/render_setup.h"
#include "renderer/subdivide.h"

namespace glint {

namespace {

// Per-thread tallies, merged at the end.
struct ThreadTally {
  RayCounters rays;
  SampleChecks checks;
  uint64_t samples = 0;  // renderOnce: samples its pixels took (for RenderStats::meanSpp)
};

// Per-pixel sums of radiance and squared radiance, in double: a pixel has at most a few
// thousand samples of bounded magnitude, so sum/sum-of-squares is accurate here and cheaper
// than Welford's update (no division per sample). Kept across passes: adding a pass's samples
// in sample order gives the sums a single run gives.
struct PixelMoments {
  double sum[3] = {0, 0, 0}, sumSq[3] = {0, 0, 0};
  void add(Rgb v) {
    for (int c = 0; c < 3; ++c) {
      sum[c] += v[c];
      sumSq[c] += double(v[c]) * v[c];
    }
  }
  Rgb mean(double n) const { return {float(sum[0] / n), float(sum[1] / n), float(sum[2] / n)}; }
  // The adaptive stopping rule (AdaptiveSettings): every channel's Var[mean] within
  // threshold² · (mean² + 0.01).
  bool converged(double n, double threshold2) const {
    for (int c = 0; c < 3; ++c) {
      const double mean = sum[c] / n;
      const double var = std::max(0.0, (sumSq[c] - sum[c] * mean) / ((n - 1) * n));
      if (var > threshold2 * (mean * mean + 0.01)) return false;
    }
    return true;
  }
  // The mean, and the variance of the mean (sumSq - sum² / n) / ((n - 1) n), from 1/n and
  // 1/((n - 1) n): the film update's form, two divisions a pixel instead of seven.
  Rgb meanTimes(double invN) const {
    return {float(sum[0] * invN), float(sum[1] * invN), float(sum[2] * invN)};
  }
  Rgb varianceOfMeanTimes(double invN, double invNN1) const {
    Rgb v;
    for (int c = 0; c < 3; ++c)
      v[c] = float(std::max(0.0, (sumSq[c] - sum[c] * sum[c] * invN) * invNN1));
    return v;
  }
};

// Camera rays handed to the accelerator together: Embree's widest packet.
constexpr uint32_t kCameraBatch = 16;

// Where adaptive sampling may stop a pixel (AdaptiveSettings): at 2, 4 and 8 samples, then at
// every multiple of kCameraBatch, from minSpp on. The early doublings let a pixel of a scene
// without noise (hard shadows, mirrors: only its edges need samples) stop after a few samples,
// as supersampling anti-aliasing does; the checkpoints are fixed sample counts, so a pixel's
// decisions do not depend on how the samples were split into passes.
bool isAdaptiveCheckpoint(uint32_t spp) {
  return spp % kCameraBatch == 0 || (spp < kCameraBatch && (spp & (spp - 1)) == 0);
}
// Anti-aliasing by contrast (AdaptiveSettings::contrast): the checkpoints where a pixel looks at
// its neighbours, and so how far a window's border pixels can depend on pixels outside it (one
// pixel per checkpoint): the margin a crop or tile renders around its window.
constexpr uint32_t kContrastCheckpoints[] = {1, 2, 4, 8, 16};
constexpr int kContrastApron = int(std::size(kContrastCheckpoints));
bool isContrastCheckpoint(uint32_t spp) {
  return std::find(std::begin(kContrastCheckpoints), std::end(kContrastCheckpoints), spp) !=
         std::end(kContrastCheckpoints);
}

// The first checkpoint after `spp`: camera-ray batches stop there.
uint32_t nextAdaptiveCheckpoint(uint32_t spp) {
  if (spp >= kCameraBatch / 2) return (spp / kCameraBatch + 1) * kCameraBatch;
  uint32_t next = 2;
  while (next <= spp) next *= 2;
  return next;
}
static_assert(kCameraBatch <= uint32_t(Camera::kMaxRayBatch), "a batch is one pinholeRays call");

}  // namespace

PixelWindow tileWindow(int width, int height, int index, int count) {
  if (count <= 0 || index < 0 || index >= count || count > height)
    throw InputError(
        fmt::format("tile {}/{}: need 0 <= I < N <= the image height ({})", index, count, height));
  const auto row = [&](int i) { return int(int64_t(i) * height / count); };
  return {0, row(index), width, row(index + 1)};
}

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

struct ProgressiveRender::State {
  const RenderScene& scene;
  const Integrator& integrator;
  const RenderSettings& settings;
  RenderOptions options;
  PixelWindow window;
  PixelFilter filter;
  bool adaptive, lens, motion, plain, aovs;
  double threshold2;
  uint32_t minSpp;
  // Anti-aliasing by contrast: the threshold (0: off), and the pixels rendered: the window, or
  // with contrast the window grown by kContrastApron (within the image). The per-pixel arrays
  // below cover `region`; the film covers `window`.
  float contrast = 0;
  PixelWindow region;
  std::vector<uint8_t> active;  // with contrast: still sampling (a checkpoint has not stopped it)
  // With contrast: each pixel's mean, squeezed, as of its last checkpoint (a stopped pixel's
  // mean no longer changes), so a checkpoint squeezes each mean once, not once per neighbour.
  std::vector<std::array<float, 3>> squeezedMeans;
  int tilesX = 0, tilesY = 0;
  std::unique_ptr<RenderThreads> threads;

  // Per pixel of the region, across passes.
  std::vector<PixelMoments> moments;
  std::vector<uint32_t> taken;  // samples drawn (fewer than spp where adaptive sampling stopped)
  std::vector<uint32_t> hits;   // camera rays that hit geometry
  std::vector<Rgb> albedo, normal;  // AOV sums (float, as a single pass adds them)
  std::vector<double> depth;

  uint32_t spp = 0;
  int passes = 0;
  // render()'s single pass (renderOnce): each pixel's samples go from zero straight to the
  // film, and no sums are kept.
  bool direct = false;
  bool broken = false;  // a dropped pass left the sums part-way, or renderOnce kept none
  Film film;
  // estimatedRelativeError(film), computed when first asked after a pass (a render that only
  // wants its image never pays for it).
  mutable std::optional<double> error;
  RenderStats stats;

  State(const RenderScene& s, const Integrator& i, const RenderSettings& st, const RenderOptions& o)
      : scene(s), integrator(i), settings(st), options(o), filter(st.filter) {}

  void renderTile(int tileIndex, uint32_t passEnd, const std::atomic<bool>* cancel,
                  ThreadTally& tally, uint64_t* samplesTaken);
  // Every tile up to `passEnd` samples per pixel, in parallel, counting into `tallies`.
  void renderTiles(uint32_t passEnd, const std::atomic<bool>* cancel,
                   tbb::enumerable_thread_specific<ThreadTally>& tallies,
                   const std::function<void(uint64_t)>& onTile) {
    threads->arena->execute([&] {
      tbb::parallel_for(tbb::blocked_range<int>(0, tilesX * tilesY, 1),
                        [&](const tbb::blocked_range<int>& r) {
                          for (int t = r.begin(); t != r.end(); ++t) {
                            uint64_t drawn = 0;
                            renderTile(t, passEnd, cancel, tallies.local(), &drawn);
                            if (onTile) onTile(drawn);
                          }
                        });
    });
  }
  // The per-pixel sums, zero, on the first pass or resume (render()'s single pass keeps none).
  void allocateSums();
  // Film pixel i from a pixel's sums: k samples, `hitCount` of them on geometry, and the AOV
  // sums.
  void writeFilmPixel(size_t i, const PixelMoments& m, uint32_t k, uint32_t hitCount, Rgb albedoSum,
                      Rgb normalSum, double depthSum);
  // Film pixel i from region pixel r's sums.
  void setFilmPixel(size_t i, size_t r) {
    writeFilmPixel(i, moments[r], taken[r], hits[r], aovs ? albedo[r] : Rgb{},
                   aovs ? normal[r] : Rgb{}, aovs ? depth[r] : 0.0);
  }
  // Every film pixel from the sums.
  void updateFilm();
  // At a contrast checkpoint: stops the active pixels that took `spp` samples and meet the rule.
  void stopQuietPixels(uint32_t spp);
  size_t regionIndex(int x, int y) const {
    return size_t(y - region.y0) * size_t(region.width()) + size_t(x - region.x0);
  }
};

ProgressiveRender::ProgressiveRender(const RenderScene& scene, const Integrator& integrator,
                                     const RenderSettings& settings, const RenderOptions& options)
    : state_(std::make_unique<State>(scene, integrator, settings, options)) {
  State& st = *state_;
  const int width = scene.camera.width(), height = scene.camera.height();
  st.aovs = settings.aovs;
  // Adaptive sampling: checked from minSpp on, at the checkpoints (isAdaptiveCheckpoint).
  st.adaptive = settings.adaptive.threshold > 0;
  st.threshold2 = double(settings.adaptive.threshold) * settings.adaptive.threshold;
  st.minSpp = uint32_t(std::max(2, settings.adaptive.minSpp));
  // The camera decides whether there is a lens to sample (the scene builder reports it as
  // Feature::Lens); time is sampled only when the builder found something moving.
  st.lens = scene.camera.hasLens();
  st.motion = scene.features.has(Feature::MotionBlur);
  // Neither: the pinhole rays of before, with no per-ray test.
  st.plain = !st.lens && !st.motion && scene.camera.isStaticPinhole();
  const PixelWindow window = renderWindow(options, width, height);
  st.window = window;
  st.film = Film(window.width(), window.height(), st.aovs);
  st.film.originX = window.x0, st.film.originY = window.y0;
  st.film.fullWidth = width, st.film.fullHeight = height;
  st.contrast = settings.adaptive.contrast;
  st.region = window;
  if (st.contrast > 0) {
    const int a = kContrastApron;
    st.region = {std::max(0, window.x0 - a), std::max(0, window.y0 - a),
                 std::min(width, window.x1 + a), std::min(height, window.y1 + a)};
  }
  if (st.contrast > 0) st.active.assign(size_t(st.region.width()) * size_t(st.region.height()), 1);
  const int tile = options.tileSize;
  st.tilesX = (st.region.width() + tile - 1) / tile;
  st.tilesY = (st.region.height() + tile - 1) / tile;
  st.threads = std::make_unique<RenderThreads>(options.threads);
  st.stats.threads = st.threads->count;
}

ProgressiveRender::~ProgressiveRender() = default;

void ProgressiveRender::resumeFrom(const Film& partial, uint32_t spp) {
  State& st = *state_;
  if (st.region.x0 != st.window.x0 || st.region.y0 != st.window.y0 ||
      st.region.x1 != st.window.x1 || st.region.y1 != st.window.y1)
    throw InputError(
        "cannot continue a crop or tile rendered with anti-aliasing by contrast: its margin "
        "pixels are not in the image");
  const size_t n = size_t(st.region.width()) * size_t(st.region.height());
  if (partial.width != st.film.width || partial.height != st.film.height ||
      partial.originX != st.film.originX || partial.originY != st.film.originY)
    throw InputError(
        fmt::format("cannot continue a {}x{} image at {},{}: this render is {}x{} at {},{}",
                    partial.width, partial.height, partial.originX, partial.originY, st.film.width,
                    st.film.height, st.film.originX, st.film.originY));
  if (partial.samples.size() != n || partial.variance.size() != n || partial.alpha.size() != n)
    throw InputError("cannot continue an image without per-pixel samples and variance");
  if (st.aovs && !partial.hasAovs)
    throw InputError("cannot continue an image without AOVs into one with them");
  st.allocateSums();
  for (size_t i = 0; i < n; ++i) {
    const uint32_t k = partial.samples[i];
    if (k > spp) throw InputError("an image's pixel holds more samples than its spp");
    // Undo mean = sum / k and Var[mean] = (sumSq - sum² / k) / ((k - 1) k).
    PixelMoments m;
    for (int c = 0; c < 3; ++c) {
      const double mean = partial.color[i][c];
      m.sum[c] = mean * k;
      m.sumSq[c] = k >= 2 ? double(partial.variance[i][c]) * double(k - 1) * k + mean * mean * k
                          : mean * mean * k;
    }
    st.moments[i] = m;
    st.taken[i] = k;
    if (!st.active.empty()) st.active[i] = k >= spp;  // a pixel that stopped stays stopped
    st.hits[i] = uint32_t(std::lround(double(partial.alpha[i]) * k));
    if (st.aovs) {
      st.albedo[i] = partial.albedo[i] * float(k);
      st.normal[i] = partial.normal[i] * float(k);
      st.depth[i] = double(partial.depth[i]) * st.hits[i];
    }
  }
  // A pixel that stopped at a contrast checkpoint holds exactly that checkpoint's samples, like
  // one that went on: the file cannot tell them apart, so the checkpoint is decided again, from
  // the same means (up to the rounding of the sums rebuilt above).
  if (st.contrast > 0 && isContrastCheckpoint(spp)) st.stopQuietPixels(spp);
  st.spp = spp;
  st.updateFilm();
}

void ProgressiveRender::State::renderTile(int tileIndex, uint32_t passEnd,
                                          const std::atomic<bool>* cancel, ThreadTally& tally,
                                          uint64_t* samplesTaken) {
  const int width = scene.camera.width();
  const int tile = options.tileSize;
  const int x0 = region.x0 + (tileIndex % tilesX) * tile,
            y0 = region.y0 + (tileIndex / tilesX) * tile;
  const int x1 = std::min(x0 + tile, region.x1), y1 = std::min(y0 + tile, region.y1);
  // A pixel's batch of camera rays and their hits, constructed once per tile: their default
  // initialisation per pixel was a fifth of this loop's own time at 4 spp. Every element a
  // pixel reads it writes first (closestHits overwrites each hit whole).
  Ray rays[kCameraBatch];
  Hit found[kCameraBatch];
  uint64_t drawn = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      // A dropped pass: the caller keeps the last completed film.
      if (cancel && cancel->load(std::memory_order_relaxed)) {
        *samplesTaken = drawn;
        return;
      }
      // (x, y) is the pixel's place in the whole image, which keys its samples; the arrays
      // hold the region.
      const size_t index = regionIndex(x, y);
      if (!active.empty() && !active[index]) continue;
      const uint64_t pixelKey =
          pixelSampleKey(settings.seed, size_t(y) * size_t(width) + size_t(x));
      // The film position, and the lens point where there is one, are 2D dimension pairs
      // whose seeds depend on the pixel only.
      const DimensionSeeds filmSeeds(pixelKey, kFilmDimension);
      const DimensionSeeds lensSeeds =
          lens ? DimensionSeeds(pixelKey, kLensDimension) : DimensionSeeds();
      // Anti-aliasing by contrast: the first look goes through the pixel's centre; a pixel the
      // first checkpoint does not stop drops it and takes its stratified samples from the
      // start (AdaptiveSettings). The first pass ends at that checkpoint (renderTo), so the
      // centre is always a batch of its own.
      const bool dropsCentre = contrast > 0 && !direct && taken[index] == 1 && passEnd > 1;
      const bool fromZero = direct || dropsCentre;  // the pixel's sums start empty
      PixelMoments acc = fromZero ? PixelMoments{} : moments[index];
      uint32_t pixelHits = fromZero ? 0 : hits[index];
      double pixelDepth = aovs && !fromZero ? depth[index] : 0.0;
      Rgb pixelAlbedo = aovs && !fromZero ? albedo[index] : Rgb{},
          pixelNormal = aovs && !fromZero ? normal[index] : Rgb{};
      // The pixel's camera rays go to the accelerator in batches, which it may trace as
      // packets (they are coherent); each result is then shaded on its own. Batches never
      // cross a multiple of kCameraBatch, nor a checkpoint where adaptive sampling checks the
      // pixel, so its decisions are the same however the samples are split into passes.
      uint32_t first = fromZero ? 0 : taken[index];
      const bool centreLook = contrast > 0 && !direct && taken[index] == 0;
      while (first < passEnd) {
        // (With contrast, checkpoints up to 16 are decided between passes: stopQuietPixels.)
        if (adaptive && first >= minSpp && isAdaptiveCheckpoint(first) &&
            (contrast <= 0 || first > kCameraBatch) && acc.converged(first, threshold2))
          break;
        uint32_t n = std::min(kCameraBatch - first % kCameraBatch, passEnd - first);
        if (adaptive) {
          uint32_t check = nextAdaptiveCheckpoint(first);
          while (check < minSpp) check = nextAdaptiveCheckpoint(check);
          n = std::min(n, check - first);
        }
        uint32_t fx[kCameraBatch], fy[kCameraBatch];
        sample2DFractionBatch(first, n, filmSeeds, fx, fy);
        if (plain) {
          float filmX[kCameraBatch], filmY[kCameraBatch];
          for (uint32_t i = 0; i < n; ++i) {
            const Vec2f offset = centreLook ? Vec2f{} : filter.sampleOffsetFraction({fx[i], fy[i]});
            filmX[i] = float(x) + 0.5f + offset.x, filmY[i] = float(y) + 0.5f + offset.y;
          }
          scene.camera.pinholeRays(filmX, filmY, int(n), rays);
        } else {
          uint32_t lx[kCameraBatch], ly[kCameraBatch];
          if (lens) sample2DFractionBatch(first, n, lensSeeds, lx, ly);
          for (uint32_t i = 0; i < n; ++i) {
            const Vec2f offset = centreLook ? Vec2f{} : filter.sampleOffsetFraction({fx[i], fy[i]});
            CameraSample cs;
            cs.pFilm = {float(x) + 0.5f + offset.x, float(y) + 0.5f + offset.y};
            if (lens) cs.pLens = Fraction2{lx[i], ly[i]}.toFloat();
            // A 1D Owen-scrambled Sobol dimension: stratified over the pixel's samples.
            if (motion) cs.time = Sampler(pixelKey, first + i, kTimeDimension).get1D();
            rays[i] = scene.camera.generateRay(cs);
          }
        }
        scene.accel->closestHits(rays, found, int(n));
        tally.rays.camera += n;
        for (uint32_t i = 0; i < n; ++i) {
          Sampler sampler(pixelKey, first + i, kIntegratorDimension);
          PathAovs pathAovs;
          pathAovs.wanted = aovs;
          const Rgb L = cameraRadiance(integrator, rays[i], found[i], sampler, tally.rays, pathAovs,
                                       &tally.checks);
          acc.add(L);
          if (pathAovs.hit) {
            pixelHits += 1;
            if (aovs) {
              pixelAlbedo += pathAovs.albedo;
              pixelNormal += pathAovs.normal;
              pixelDepth += pathAovs.depth;
            }
          }
        }
        first += n;
        drawn += n;
      }
      if (direct) {
        // The region is the film's window (renderOnce has no contrast margin).
        writeFilmPixel(index, acc, first, pixelHits, pixelAlbedo, pixelNormal, pixelDepth);
        tally.samples += first;
        continue;
      }
      moments[index] = acc;
      taken[index] = first;
      hits[index] = pixelHits;
      if (aovs) {
        albedo[index] = pixelAlbedo;
        normal[index] = pixelNormal;
        depth[index] = pixelDepth;
      }
    }
  *samplesTaken = drawn;
}

void ProgressiveRender::State::allocateSums() {
  if (!moments.empty()) return;
  const size_t n = size_t(region.width()) * size_t(region.height());
  moments.assign(n, PixelMoments{});
  taken.assign(n, 0);
  hits.assign(n, 0);
  if (aovs) {
    albedo.assign(n, Rgb{});
    normal.assign(n, Rgb{});
    depth.assign(n, 0.0);
  }
}

void ProgressiveRender::State::writeFilmPixel(size_t i, const PixelMoments& m, uint32_t k,
                                              uint32_t hitCount, Rgb albedoSum, Rgb normalSum,
                                              double depthSum) {
  film.samples[i] = k;
  if (k == 0) {
    film.color[i] = film.variance[i] = Rgb{};
    film.alpha[i] = 0;
    return;
  }
  const double invK = 1.0 / k;
  film.color[i] = m.meanTimes(invK);
  film.variance[i] = k >= 2 ? m.varianceOfMeanTimes(invK, 1.0 / (double(k - 1) * k)) : Rgb{};
  film.alpha[i] = float(double(hitCount) * invK);
  if (aovs) {
    film.albedo[i] = albedoSum / float(k);
    film.normal[i] = normalSum / float(k);
    film.depth[i] = hitCount > 0 ? float(depthSum / hitCount) : 0.0f;
  }
}

void ProgressiveRender::State::updateFilm() {
  // Row by row in parallel: a serial pass over the film was a visible share of a short render.
  const size_t w = size_t(window.width()), h = size_t(window.height());
  std::vector<uint64_t> rowSamples(h, 0);
  threads->arena->execute([&] {
    tbb::parallel_for(size_t(0), h, [&](size_t y) {
      // The film row's pixels in the region (the same indices when the region is the window).
      const size_t r0 = regionIndex(window.x0, window.y0 + int(y));
      uint64_t samples = 0;
      for (size_t x = 0; x < w; ++x) {
        setFilmPixel(y * w + x, r0 + x);
        // With contrast, a pixel that went on past its centre look dropped it: one more.
        samples += taken[r0 + x] + (contrast > 0 && taken[r0 + x] > 1 ? 1 : 0);
      }
      rowSamples[y] = samples;
    });
  });
  uint64_t samplesTotal = 0;
  for (uint64_t s : rowSamples) samplesTotal += s;
  error.reset();
  stats.meanSpp = w * h > 0 ? double(samplesTotal) / double(w * h) : 0.0;
}

void ProgressiveRender::State::stopQuietPixels(uint32_t spp) {
  const int w = region.width(), h = region.height();
  // The pixels that sampled up to this checkpoint bring their squeezed means up to date; the
  // others stopped earlier, with the mean they have (all of them, at a render's first
  // checkpoint: a resumed render's pixels may have stopped in the run it continues). A pixel
  // with no samples, only possible in a resumed render, compares as equal to every neighbour.
  const bool first = squeezedMeans.empty();
  if (first) squeezedMeans.resize(size_t(w) * size_t(h));
  threads->arena->execute([&] {
    tbb::parallel_for(0, h, [&](int y) {
      for (size_t i = size_t(y) * size_t(w), end = i + size_t(w); i < end; ++i) {
        if (taken[i] == 0 || (!first && taken[i] != spp)) continue;
        const Rgb mean = moments[i].mean(taken[i]);
        for (int c = 0; c < 3; ++c) squeezedMeans[i][c] = squeezedRadiance(mean[c]);
      }
    });
  });
  // Decided from the means as they are at this checkpoint, which no decision changes: a pixel
  // reads its neighbours' means, never their flags, so each row clears its own flags in place.
  threads->arena->execute([&] {
    tbb::parallel_for(0, h, [&](int y) {
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * size_t(w) + size_t(x);
        if (!active[i] || taken[i] != spp) continue;
        if (adaptive && (spp < std::max(2u, minSpp) || !moments[i].converged(spp, threshold2)))
          continue;
        const std::array<float, 3>& mean = squeezedMeans[i];
        bool quiet = true;
        for (int dy = -1; dy <= 1 && quiet; ++dy)
          for (int dx = -1; dx <= 1 && quiet; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
            const size_t j = size_t(ny) * size_t(w) + size_t(nx);
            if (!taken[j]) continue;
            const std::array<float, 3>& other = squeezedMeans[j];
            for (int c = 0; c < 3; ++c) quiet = quiet && std::abs(mean[c] - other[c]) <= contrast;
          }
        if (quiet) active[i] = 0;
      }
    });
  });
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
  tbb::enumerable_thread_specific<ThreadTally> tallies;
  const auto start = std::chrono::steady_clock::now();
  // With contrast, the pass stops at every contrast checkpoint on the way (however the caller
  // splits the render, the decisions are taken at the same sample counts).
  for (uint32_t done = st.spp; done < end;) {
    uint32_t to = end;
    if (st.contrast > 0)
      for (uint32_t c : kContrastCheckpoints)
        if (c > done) {
          to = std::min(to, c);
          break;
        }
    st.renderTiles(to, cancel, tallies, onTile);
    if (cancel && cancel->load()) {
      st.broken = true;
      return false;
    }
    if (st.contrast > 0 && isContrastCheckpoint(to)) st.stopQuietPixels(to);
    done = to;
  }
  st.stats.renderSeconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (const ThreadTally& t : tallies) {
    st.stats.rays += t.rays;
    t.checks.mergeInto(st.stats);
  }
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
  if (st.contrast > 0 || st.spp > 0 || !st.moments.empty()) {
    renderTo(spp, nullptr, onTile);
    st.broken = true;
    return;
  }
  st.direct = true;
  st.broken = true;  // no sums: this render cannot go on
  tbb::enumerable_thread_specific<ThreadTally> tallies;
  const auto start = std::chrono::steady_clock::now();
  st.renderTiles(spp, nullptr, tallies, onTile);
  st.stats.renderSeconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  uint64_t samples = 0;
  for (const ThreadTally& t : tallies) {
    st.stats.rays += t.rays;
    t.checks.mergeInto(st.stats);
    samples += t.samples;
  }
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
    st.error = relativeError(st.film, [&](size_t count, const auto& body) {
      st.threads->arena->execute([&] { tbb::parallel_for(size_t(0), count, body); });
    });
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
                                       : uint64_t(scene.camera.width()) * scene.camera.height();
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

}  // namespace

Film renderUntil(const RenderScene& scene, const Integrator& integrator,
                 const RenderSettings& settings, const RenderOptions& options, const StopRule& rule,
                 RenderStats* stats, ProgressiveResult* result, const Film* resume,
                 uint32_t resumeSpp, const std::function<void(const ProgressiveRender&)>& onPass) {
  if (settings.adaptive.subdivide > 0)
    return renderSubdividedUntil(scene, integrator, settings, options, rule, stats, result,
                                 resume != nullptr);
  ProgressiveRender pr(scene, integrator, settings, options);
  if (resume) pr.resumeFrom(*resume, resumeSpp);
  const uint32_t startSpp = pr.spp();
  const double pixels = double(pr.film().width) * double(pr.film().height);
  const bool budget = rule.timeLimit > 0 || rule.noiseTarget > 0;
  const uint64_t sppTotal =
      uint64_t(double(rule.maxSpp > startSpp ? rule.maxSpp - startSpp : 0) * pixels);
  ProgressBar bar("rendering", std::max<uint64_t>(sppTotal, 1), options.progress);
  const auto onTile = [&](uint64_t samples) { bar.advance(samples); };
  const auto began = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
  };
  StopReason reason = StopReason::Spp;
  double lastPassSeconds = 0;
  uint32_t lastPassSpp = 0;
  bool warned = false;
  while (true) {
    if (pr.spp() >= rule.maxSpp) {
      reason = StopReason::Spp;
      break;
    }
    if (rule.noiseTarget > 0 && pr.spp() >= kCameraBatch && pr.estimatedError() > 0 &&
        pr.estimatedError() <= rule.noiseTarget) {
      reason = StopReason::NoiseTarget;
      break;
    }
    const uint32_t next =
        std::min(rule.warmup ? nextPassEnd(pr.spp()) : (pr.spp() / kCameraBatch + 1) * kCameraBatch,
                 rule.maxSpp);
    if (rule.timeLimit > 0 && pr.passes() > 0) {
      // The next pass at the last pass's rate per sample.
      const double predicted =
          lastPassSeconds / std::max<uint32_t>(lastPassSpp, 1) * double(next - pr.spp());
      if (elapsed() + predicted > rule.timeLimit) {
        reason = StopReason::TimeLimit;
        break;
      }
    }
    const uint32_t before = pr.spp();
    const double passStart = elapsed();
    if (!pr.renderTo(next, rule.cancel, onTile)) {
      reason = StopReason::Interrupted;
      break;
    }
    lastPassSeconds = elapsed() - passStart;
    lastPassSpp = pr.spp() - before;
    if (onPass) onPass(pr);
    // The bar's end: the spp, or sooner where a budget will stop the render first.
    if (budget) {
      const double done = double(pr.spp() - startSpp) * pixels;
      double total = double(sppTotal);
      if (rule.timeLimit > 0)
        total = std::min(total, done * rule.timeLimit / std::max(elapsed(), 1e-3));
      if (rule.noiseTarget > 0 && pr.estimatedError() > 0) {
        const double ratio = pr.estimatedError() / rule.noiseTarget;
        total = std::min(total, done * std::max(1.0, ratio * ratio));
      }
      bar.setTotal(uint64_t(std::max(total, done)));
      bar.setNote(fmt::format("{} spp, error {:.2g}%", pr.spp(), 100 * pr.estimatedError()));
    } else {
      bar.setNote(fmt::format("{} spp", pr.spp()));
    }
    // A render that will take long says so once, after its first pass.
    if (options.progress && !warned && !budget) {
      warned = true;
      const double perSpp = lastPassSeconds / std::max<uint32_t>(lastPassSpp, 1);
      const double remaining = perSpp * double(rule.maxSpp - pr.spp());
      if (remaining > 60)
        bar.message(fmt::format(
            "glint: {} spp will take about {} more ({} per sample per pixel); Ctrl-C stops "
            "and writes what is done",
            rule.maxSpp, readableDuration(remaining), readableDuration(perSpp)));
    }
  }
  if (reason != StopReason::Interrupted) bar.finish();
  if (result) {
    result->reason = reason;
    result->spp = pr.spp();
    result->error = pr.estimatedError();
    result->passes = pr.passes();
  }
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
