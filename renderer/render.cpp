// glint — tiled, multithreaded rendering.
#include "renderer/render.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <thread>

#include "geometry/error.h"
#include "renderer/filter.h"
#include "renderer/progress.h"

namespace glint {

namespace {

// Per-thread tallies, merged at the end.
struct ThreadTally {
  RayCounters rays;
  uint64_t nonfinite = 0;
};

// Per-pixel sums of radiance and squared radiance, in double: a pixel has at most a few
// thousand samples of bounded magnitude, so sum/sum-of-squares is accurate here and cheaper
// than Welford's update (no division per sample).
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
  Rgb varianceOfMean(double n) const {
    if (n < 2) return {};
    Rgb v;
    for (int c = 0; c < 3; ++c)
      v[c] = float(std::max(0.0, (sumSq[c] - sum[c] * sum[c] / n) / ((n - 1) * n)));
    return v;
  }
};

// Camera rays handed to the accelerator together: Embree's widest packet.
constexpr uint32_t kCameraBatch = 16;

}  // namespace

PixelWindow tileWindow(int width, int height, int index, int count) {
  if (count <= 0 || index < 0 || index >= count || count > height)
    throw InputError(
        fmt::format("tile {}/{}: need 0 <= I < N <= the image height ({})", index, count, height));
  const auto row = [&](int i) { return int(int64_t(i) * height / count); };
  return {0, row(index), width, row(index + 1)};
}

Film render(const RenderScene& scene, const Integrator& integrator, const RenderSettings& settings,
            const RenderOptions& options, RenderStats* stats) {
  const int width = scene.camera.width(), height = scene.camera.height();
  const uint32_t spp = uint32_t(settings.spp);
  const bool aovs = settings.aovs;
  // Adaptive sampling: checked from minSpp on, at batch ends (multiples of kCameraBatch).
  const bool adaptive = settings.adaptive.threshold > 0;
  const double threshold2 = double(settings.adaptive.threshold) * settings.adaptive.threshold;
  const uint32_t minSpp = uint32_t(std::max(2, settings.adaptive.minSpp));
  // The camera decides whether there is a lens to sample (the scene builder reports it as
  // Feature::Lens); time is sampled only when the builder found something moving.
  const bool lens = scene.camera.hasLens();
  const bool motion = scene.features.has(Feature::MotionBlur);
  // Neither: the pinhole rays of before, with no per-ray test.
  const bool plain = !lens && !motion && scene.camera.isStaticPinhole();
  const PixelWindow window = options.crop.value_or(PixelWindow{0, 0, width, height});
  if (window.x0 < 0 || window.y0 < 0 || window.x1 > width || window.y1 > height ||
      window.width() <= 0 || window.height() <= 0)
    throw InputError(fmt::format("crop window {},{},{},{} is empty or outside the {}x{} image",
                                 window.x0, window.y0, window.x1, window.y1, width, height));
  Film film(window.width(), window.height(), aovs);
  film.originX = window.x0, film.originY = window.y0;
  film.fullWidth = width, film.fullHeight = height;
  PixelFilter filter(settings.filter);

  const int tile = options.tileSize;
  const int tilesX = (window.width() + tile - 1) / tile,
            tilesY = (window.height() + tile - 1) / tile;
  int threads = options.threads > 0 ? options.threads : int(std::thread::hardware_concurrency());
  if (threads <= 0) threads = 1;

  ProgressBar progress("rendering", uint64_t(tilesX) * uint64_t(tilesY), options.progress);
  tbb::enumerable_thread_specific<ThreadTally> tallies;
  auto start = std::chrono::steady_clock::now();

  auto renderTile = [&](int tileIndex) {
    ThreadTally& tally = tallies.local();
    const int x0 = window.x0 + (tileIndex % tilesX) * tile,
              y0 = window.y0 + (tileIndex / tilesX) * tile;
    const int x1 = std::min(x0 + tile, window.x1), y1 = std::min(y0 + tile, window.y1);
    // A pixel's batch of camera rays and their hits, constructed once per tile: their default
    // initialisation per pixel was a fifth of this loop's own time at 4 spp. Every element a
    // pixel reads it writes first (closestHits overwrites each hit whole).
    Ray rays[kCameraBatch];
    Hit found[kCameraBatch];
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        // (x, y) is the pixel's place in the whole image, which keys its samples; the film
        // holds the window.
        const size_t index = film.index(x - window.x0, y - window.y0);
        const uint64_t pixelKey =
            pixelSampleKey(settings.seed, size_t(y) * size_t(width) + size_t(x));
        // The film position, and the lens point where there is one, are 2D dimension pairs
        // whose seeds depend on the pixel only.
        const DimensionSeeds filmSeeds(pixelKey, kFilmDimension);
        const DimensionSeeds lensSeeds =
            lens ? DimensionSeeds(pixelKey, kLensDimension) : DimensionSeeds();
        PixelMoments acc;
        double hits = 0, depth = 0;
        Rgb albedo, normal;
        // The pixel's camera rays go to the accelerator in batches, which it may trace as
        // packets (they are coherent); each result is then shaded on its own.
        uint32_t taken = 0;  // samples drawn: spp, or fewer when adaptive sampling stops early
        for (uint32_t first = 0; first < spp; first += kCameraBatch) {
          if (adaptive && first >= minSpp && acc.converged(first, threshold2)) break;
          const uint32_t n = std::min(kCameraBatch, spp - first);
          taken = first + n;
          uint32_t fx[kCameraBatch], fy[kCameraBatch];
          sample2DFractionBatch(first, n, filmSeeds, fx, fy);
          if (plain) {
            for (uint32_t i = 0; i < n; ++i) {
              Vec2f offset = filter.sampleOffsetFraction({fx[i], fy[i]});
              rays[i] = scene.camera.pinholeRay(
                  {float(x) + 0.5f + offset.x, float(y) + 0.5f + offset.y}, 0.0f);
            }
          } else {
            uint32_t lx[kCameraBatch], ly[kCameraBatch];
            if (lens) sample2DFractionBatch(first, n, lensSeeds, lx, ly);
            for (uint32_t i = 0; i < n; ++i) {
              Vec2f offset = filter.sampleOffsetFraction({fx[i], fy[i]});
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
            const Hit* hit = found[i].instance != Hit::kInvalid ? &found[i] : nullptr;
            Rgb L = integrator.LiFromHit(rays[i], hit, sampler, tally.rays, pathAovs);
            if (!isFinite(L)) {
              ++tally.nonfinite;
              L = {};
            }
            acc.add(L);
            if (pathAovs.hit) {
              hits += 1;
              if (aovs) {
                albedo += pathAovs.albedo;
                normal += pathAovs.normal;
                depth += pathAovs.depth;
              }
            }
          }
        }
        film.color[index] = acc.mean(taken);
        film.variance[index] = acc.varianceOfMean(taken);
        film.alpha[index] = float(hits / taken);
        if (aovs) {
          film.albedo[index] = albedo / float(taken);
          film.normal[index] = normal / float(taken);
          film.depth[index] = hits > 0 ? float(depth / hits) : 0.0f;
        }
      }
    progress.advance();
  };

  tbb::task_arena arena(threads);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, tilesX * tilesY, 1),
                      [&](const tbb::blocked_range<int>& r) {
                        for (int t = r.begin(); t != r.end(); ++t) renderTile(t);
                      });
  });
  progress.finish();

  if (stats) {
    stats->renderSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats->threads = threads;
    stats->rays = {};
    stats->nonfiniteSamples = 0;
    for (const ThreadTally& t : tallies) {
      stats->rays += t.rays;
      stats->nonfiniteSamples += t.nonfinite;
    }
    // One camera ray per sample.
    stats->meanSpp = double(stats->rays.camera) / (double(film.width) * double(film.height));
  }
  return film;
}

}  // namespace glint
