// glint — anti-aliasing by recursive subdivision (see subdivide.h).
#include "renderer/subdivide.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <vector>

#include "geometry/error.h"
#include "renderer/render_setup.h"

namespace glint {

namespace {

// One camera path through a lattice point of the film, and what the film needs of it.
struct Look {
  Rgb L;
  std::array<float, 3> squeezed{};  // squeezedRadiance(L), what contrast compares
  bool hit = false;
  Rgb albedo;  // AOVs, filled when wanted
  Vec3f normal;
  float depth = 0;
};

// A pixel's estimate as it is summed: each uncut square adds its corners, a quarter of its
// area each.
struct AreaSums {
  double sum[3] = {0, 0, 0}, sumSq[3] = {0, 0, 0};
  double hitArea = 0, depth = 0;
  Rgb albedo;
  Vec3f normal;
  void add(const Look& look, double w) {
    for (int c = 0; c < 3; ++c) {
      sum[c] += w * look.L[c];
      sumSq[c] += w * double(look.L[c]) * look.L[c];
    }
    if (look.hit) {
      hitArea += w;
      depth += w * look.depth;
      albedo += look.albedo * float(w);
      normal += look.normal * float(w);
    }
  }
};

// The looks a tile traced inside its pixels, by lattice point: an open-addressing table whose
// slots are stamped with the tile they belong to, so starting a tile clears nothing.
class LookCache {
 public:
  void startTile() {
    looks_.clear();
    if (++stamp_ == 0) {  // wrapped: forget every old stamp
      for (Slot& s : slots_) s.stamp = 0;
      stamp_ = 1;
    }
    if (slots_.empty()) resize(1024);
  }
  const Look* find(uint64_t key) const {
    for (size_t i = mixBits(key) & mask_;; i = (i + 1) & mask_) {
      const Slot& s = slots_[i];
      if (s.stamp != stamp_) return nullptr;
      if (s.key == key) return &looks_[s.look];
    }
  }
  void insert(uint64_t key, const Look& look) {
    if (2 * (looks_.size() + 1) > slots_.size()) resize(2 * slots_.size());
    place(key, uint32_t(looks_.size()));
    looks_.push_back(look);
  }

 private:
  struct Slot {
    uint64_t key = 0;
    uint32_t stamp = 0, look = 0;
  };
  void place(uint64_t key, uint32_t look) {
    size_t i = mixBits(key) & mask_;
    while (slots_[i].stamp == stamp_) i = (i + 1) & mask_;
    slots_[i] = {key, stamp_, look};
  }
  void resize(size_t count) {
    std::vector<Slot> old = std::move(slots_);
    slots_.assign(count, Slot{});
    mask_ = count - 1;
    for (const Slot& s : old)
      if (s.stamp == stamp_) place(s.key, s.look);
  }
  std::vector<Slot> slots_;
  std::vector<Look> looks_;
  size_t mask_ = 0;
  uint32_t stamp_ = 0;
};

// What a worker thread keeps: its cache, its tallies, and which lattice points of the pixel in
// hand it has counted.
struct Worker {
  LookCache cache;
  RayCounters rays;
  SampleChecks checks;
  std::vector<uint32_t> counted;  // per lattice point of a pixel: the pixel stamp that counted it
  uint32_t pixelStamp = 0;
  uint32_t looksInPixel = 0;
};

class Subdivider {
 public:
  Subdivider(const RenderScene& scene, const Integrator& integrator, const RenderSettings& settings)
      : scene_(scene),
        integrator_(integrator),
        seed_(settings.seed),
        side_(1u << settings.adaptive.subdivide),
        keyScale_(1u << (kMaxSubdivision - settings.adaptive.subdivide)),
        contrast_(settings.adaptive.contrast),
        jitter_(settings.adaptive.jitter),
        aovs_(settings.aovs),
        lens_(scene.camera().hasLens()),
        motion_(scene.features().has(Feature::MotionBlur)),
        plain_(!lens_ && !motion_ && scene.camera().isStaticPinhole()),
        keyRow_(uint64_t(scene.camera().width()) * (1u << kMaxSubdivision) + 1) {}

  uint32_t side() const { return side_; }

  // The looks at lattice points (gx[i], gy[i]) (units of 1/side pixels) whose keys are
  // keys[i] (key()), n <= kMaxRayBatch.
  void trace(const uint32_t* gx, const uint32_t* gy, const uint64_t* keys, int n, Look* out,
             Worker& w) const {
    Ray rays[Camera::kMaxRayBatch];
    Hit found[Camera::kMaxRayBatch];
    const float inv = 1.0f / float(side_);
    float filmX[Camera::kMaxRayBatch], filmY[Camera::kMaxRayBatch];
    for (int i = 0; i < n; ++i) {
      filmX[i] = float(gx[i]) * inv, filmY[i] = float(gy[i]) * inv;
      if (jitter_ > 0) {
        const Vec2f u = Sampler(keys[i], 0, kFilmDimension).get2D();
        filmX[i] += (u.x - 0.5f) * jitter_ * inv, filmY[i] += (u.y - 0.5f) * jitter_ * inv;
      }
    }
    if (plain_) {
      scene_.camera().pinholeRays(filmX, filmY, n, rays);
    } else {
      for (int i = 0; i < n; ++i) {
        CameraSample cs;
        cs.pFilm = {filmX[i], filmY[i]};
        if (lens_) cs.pLens = Sampler(keys[i], 0, kLensDimension).get2D();
        if (motion_) cs.time = Sampler(keys[i], 0, kTimeDimension).get1D();
        rays[i] = scene_.camera().generateRay(cs);
      }
    }
    scene_.accel().closestHits(rays, found, n);
    w.rays.camera += uint64_t(n);
    for (int i = 0; i < n; ++i) {
      Sampler sampler(keys[i], 0, kIntegratorDimension);
      PathAovs pathAovs;
      pathAovs.wanted = aovs_;
      const Rgb L =
          cameraRadiance(integrator_, rays[i], found[i], sampler, w.rays, pathAovs, &w.checks);
      Look& look = out[i];
      look.L = L;
      for (int c = 0; c < 3; ++c) look.squeezed[c] = squeezedRadiance(L[c]);
      look.hit = pathAovs.hit;
      if (aovs_) {
        look.albedo = pathAovs.albedo;
        look.normal = pathAovs.normal;
        look.depth = pathAovs.depth;
      }
    }
  }

  // Pixel (x, y) from its corner looks: its estimate into `sums`, its distinct looks counted in
  // w.looksInPixel.
  void pixel(int x, int y, const std::array<Look, 4>& corners, Worker& w, AreaSums* sums) const {
    if (++w.pixelStamp == 0) {
      std::fill(w.counted.begin(), w.counted.end(), 0u);
      w.pixelStamp = 1;
    }
    w.counted.resize(size_t(side_ + 1) * (side_ + 1), 0u);
    w.looksInPixel = 4;
    refine(uint32_t(x) * side_, uint32_t(y) * side_, uint32_t(x) * side_, uint32_t(y) * side_,
           side_, corners, 1.0, w, sums);
  }

  // A lattice point's key: its place in the whole image on the finest lattice, so a point has
  // the same key (and look) at every depth that has it.
  uint64_t key(uint32_t gx, uint32_t gy) const {
    return pixelSampleKey(seed_, uint64_t(gy) * keyScale_ * keyRow_ + uint64_t(gx) * keyScale_);
  }

 private:
  bool differ(const std::array<Look, 4>& c) const {
    if (contrast_ <= 0) return true;
    for (int ch = 0; ch < 3; ++ch) {
      const float a = c[0].squeezed[ch], b = c[1].squeezed[ch], d = c[2].squeezed[ch],
                  e = c[3].squeezed[ch];
      if (std::max(std::max(a, b), std::max(d, e)) - std::min(std::min(a, b), std::min(d, e)) >
          contrast_)
        return true;
    }
    return false;
  }

  // The square of `size` lattice steps at (gx, gy) with corners c = {top-left, top-right,
  // bottom-left, bottom-right} and `area` (a share of its pixel); (px, py) is the pixel's
  // top-left lattice point.
  void refine(uint32_t px, uint32_t py, uint32_t gx, uint32_t gy, uint32_t size,
              const std::array<Look, 4>& c, double area, Worker& w, AreaSums* sums) const {
    if (size == 1 || !differ(c)) {
      for (const Look& look : c) sums->add(look, area * 0.25);
      return;
    }
    const uint32_t h = size / 2;
    // Top, left, centre, right and bottom midpoints.
    const uint32_t mx[5] = {gx + h, gx, gx + h, gx + size, gx + h};
    const uint32_t my[5] = {gy, gy + h, gy + h, gy + h, gy + size};
    std::array<Look, 5> m;
    uint32_t tx[5], ty[5];
    uint64_t tkey[5];
    int missing[5], n = 0;
    for (int i = 0; i < 5; ++i) {
      const uint32_t local = (my[i] - py) * (side_ + 1) + (mx[i] - px);
      if (w.counted[local] != w.pixelStamp) w.counted[local] = w.pixelStamp, ++w.looksInPixel;
      const uint64_t k = key(mx[i], my[i]);
      if (const Look* cached = w.cache.find(k)) {
        m[size_t(i)] = *cached;
      } else {
        tx[n] = mx[i], ty[n] = my[i], tkey[n] = k, missing[n++] = i;
      }
    }
    if (n > 0) {
      Look traced[5];
      trace(tx, ty, tkey, n, traced, w);
      for (int j = 0; j < n; ++j) {
        m[size_t(missing[j])] = traced[j];
        w.cache.insert(tkey[j], traced[j]);
      }
    }
    const double quarter = area * 0.25;
    refine(px, py, gx, gy, h, {c[0], m[0], m[1], m[2]}, quarter, w, sums);
    refine(px, py, gx + h, gy, h, {m[0], c[1], m[2], m[3]}, quarter, w, sums);
    refine(px, py, gx, gy + h, h, {m[1], m[2], c[2], m[4]}, quarter, w, sums);
    refine(px, py, gx + h, gy + h, h, {m[2], m[3], m[4], c[3]}, quarter, w, sums);
  }

  const RenderScene& scene_;
  const Integrator& integrator_;
  uint64_t seed_;
  uint32_t side_, keyScale_;
  float contrast_, jitter_;
  bool aovs_, lens_, motion_, plain_;
  uint64_t keyRow_;
};

// Rows of pixels whose corner looks are traced together before their squares are refined.
constexpr int kBandRows = 32;

}  // namespace

bool renderSubdivided(const RenderScene& scene, const Integrator& integrator,
                      const RenderSettings& settings, const RenderOptions& options, Film* film,
                      RenderStats* stats, const std::atomic<bool>* cancel,
                      const std::function<void(uint64_t)>& onPixels) {
  const int width = scene.camera().width(), height = scene.camera().height();
  const int depth = settings.adaptive.subdivide;
  if (depth < 1 || depth > kMaxSubdivision)
    throw InputError(fmt::format("anti-aliasing by subdivision: {} levels, must be 1 to {}", depth,
                                 kMaxSubdivision));
  if (settings.adaptive.threshold > 0)
    throw InputError(
        "anti-aliasing by subdivision cannot be combined with adaptive sampling by noise "
        "(render.adaptive.threshold, --adaptive): its looks are not samples of a pixel's mean");
  const PixelWindow window = renderWindow(options, width, height);
  const RenderThreads threads(options.threads);
  tbb::task_arena& arena = *threads.arena;

  const Subdivider sub(scene, integrator, settings);
  const uint32_t side = sub.side();
  Film out(window.width(), window.height(), settings.aovs);
  out.originX = window.x0, out.originY = window.y0;
  out.fullWidth = width, out.fullHeight = height;
  tbb::enumerable_thread_specific<Worker> workers;
  const auto start = std::chrono::steady_clock::now();
  const auto cancelled = [&] { return cancel && cancel->load(std::memory_order_relaxed); };

  // The corner looks of a band's rows of pixels: (rows + 1) x (columns + 1), the first row
  // carried over from the band above.
  const int columns = window.width();
  const size_t cornerRow = size_t(columns) + 1;
  std::vector<Look> corners;
  const int tile = std::max(1, options.tileSize);
  const int tilesAcross = (columns + tile - 1) / tile;
  for (int y0 = window.y0; y0 < window.y1; y0 += kBandRows) {
    const int y1 = std::min(y0 + kBandRows, window.y1);
    const int firstRow = y0 == window.y0 ? 0 : 1;
    if (firstRow == 1)
      std::copy(corners.end() - std::ptrdiff_t(cornerRow), corners.end(), corners.begin());
    corners.resize(size_t(y1 - y0 + 1) * cornerRow);
    arena.execute([&] {
      tbb::parallel_for(firstRow, y1 - y0 + 1, [&](int r) {
        if (cancelled()) return;
        Worker& w = workers.local();
        uint32_t gx[Camera::kMaxRayBatch], gy[Camera::kMaxRayBatch];
        uint64_t keys[Camera::kMaxRayBatch];
        for (int c0 = 0; c0 <= columns; c0 += Camera::kMaxRayBatch) {
          const int n = std::min(Camera::kMaxRayBatch, columns + 1 - c0);
          for (int i = 0; i < n; ++i) {
            gx[i] = uint32_t(window.x0 + c0 + i) * side, gy[i] = uint32_t(y0 + r) * side;
            keys[i] = sub.key(gx[i], gy[i]);
          }
          sub.trace(gx, gy, keys, n, &corners[size_t(r) * cornerRow + size_t(c0)], w);
        }
      });
    });
    if (cancelled()) return false;
    if (onPixels) onPixels(uint64_t(columns) * uint64_t(y1 - y0));
    arena.execute([&] {
      tbb::parallel_for(0, tilesAcross, [&](int t) {
        if (cancelled()) return;
        Worker& w = workers.local();
        w.cache.startTile();
        const int x0 = window.x0 + t * tile, x1 = std::min(x0 + tile, window.x1);
        for (int y = y0; y < y1; ++y)
          for (int x = x0; x < x1; ++x) {
            const size_t c = size_t(y - y0) * cornerRow + size_t(x - window.x0);
            const std::array<Look, 4> quad = {corners[c], corners[c + 1], corners[c + cornerRow],
                                              corners[c + cornerRow + 1]};
            AreaSums s;
            sub.pixel(x, y, quad, w, &s);
            const size_t i = out.index(x - window.x0, y - window.y0);
            Rgb mean, spread;
            for (int ch = 0; ch < 3; ++ch) {
              mean[ch] = float(s.sum[ch]);
              spread[ch] = float(std::max(0.0, s.sumSq[ch] - s.sum[ch] * s.sum[ch]) /
                                 double(w.looksInPixel));
            }
            out.color[i] = mean;
            out.variance[i] = spread;
            out.samples[i] = w.looksInPixel;
            out.alpha[i] = float(s.hitArea);
            if (settings.aovs) {
              out.albedo[i] = s.albedo;
              out.normal[i] = s.normal;
              out.depth[i] = s.hitArea > 0 ? float(s.depth / s.hitArea) : 0.0f;
            }
          }
        if (onPixels) onPixels(uint64_t(x1 - x0) * uint64_t(y1 - y0));
      });
    });
    if (cancelled()) return false;
  }
  RenderStats st;
  st.renderSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  st.threads = threads.count;
  for (const Worker& w : workers) {
    st.rays += w.rays;
    w.checks.mergeInto(st);
  }
  st.meanSpp = double(st.rays.camera) / (double(window.width()) * double(window.height()));
  if (stats) *stats = st;
  *film = std::move(out);
  return true;
}

}  // namespace glint
