// glint — media along rays.
#include "renderer/volume.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "geometry/shapes/box.h"
#include "materials/phase.h"
#include "renderer/direct_light.h"
#include "renderer/integrator.h"
#include "renderer/majorant_dda.h"
#include "renderer/scene.h"

namespace glint {

namespace {

// Steps per region diagonal when no step is configured.
constexpr float kAutoStepsPerDiagonal = 64;
// A bound on marching steps per interval, so a tiny step on a huge region cannot hang a render.
constexpr int kMaxSteps = 1 << 14;
// Tracking: below this throughput, Russian roulette decides whether the walk goes on.
constexpr float kRouletteThreshold = 0.05f;
// The path tracer's emission samples across a majorant cell where an emission bound is largest
// (proportionally fewer where it is smaller), and the most per stretch between collisions.
constexpr float kEmissionSamplesPerCell = 2;
constexpr int kMaxEmissionSamples = 64;

// The ray's parameters inside a world-space box; false when it misses.
bool clipToBox(const Ray& ray, const Bounds3f& box, float* t0, float* t1) {
  for (int a = 0; a < 3; ++a) {
    const float inv = 1 / ray.d[a];
    float tNear = (box.lower[a] - ray.o[a]) * inv;
    float tFar = (box.upper[a] - ray.o[a]) * inv;
    if (tNear > tFar) std::swap(tNear, tFar);
    // NaN (origin on a slab plane of a parallel ray) leaves the bounds as they are.
    if (tNear > *t0) *t0 = tNear;
    if (tFar < *t1) *t1 = tFar;
    if (*t0 > *t1) return false;
  }
  return true;
}

// (1 - exp(-sigma_t s)) / sigma_t per channel: what a constant source of 1 per unit length
// adds over a homogeneous stretch of length s (s itself where sigma_t = 0).
Rgb sourceIntegral(Rgb sigmaT, float s) {
  Rgb out;
  for (int c = 0; c < 3; ++c)
    out[c] = sigmaT[c] * s > 1e-6f ? -std::expm1(-sigmaT[c] * s) / sigmaT[c] : s;
  return out;
}

Rgb expNeg(Rgb x) { return {std::exp(-x.x), std::exp(-x.y), std::exp(-x.z)}; }

// R *= exp(-M x) per channel, with R kept up to a common factor: the exponents are shifted by
// their largest, then R is rescaled to a largest component of 1.
void attenuate(Rgb* R, Rgb M, float x) {
  const Rgb e = M * -x;
  const float top = maxComponent(e);
  *R *= expNeg(Rgb{top, top, top} - e);
  const float big = maxComponent(*R);
  if (big > 0) *R = *R / big;
}

float mean(Rgb c) { return (c.x + c.y + c.z) / 3; }

// Ratio tracking's roulette on its transmittance estimate *T: false when the estimate has run
// out or loses below kRouletteThreshold (the walk ends there); a survivor is weighed up.
bool survivesRoulette(Rgb* T, Sampler& sampler) {
  const float q = maxComponent(*T);
  if (q <= 0) return false;
  if (q < kRouletteThreshold) {
    const float survive = q / kRouletteThreshold;
    if (sampler.get1D() >= survive) return false;
    *T = *T / survive;
  }
  return true;
}

// a / b per channel, 0 where b is 0 (a channel the path has already lost).
Rgb safeDivide(Rgb a, Rgb b) {
  Rgb out;
  for (int c = 0; c < 3; ++c) out[c] = b[c] > 0 ? a[c] / b[c] : 0.0f;
  return out;
}

// Sorted distinct interval ends: the pieces between consecutive ones have a fixed set of
// active regions.
void breakpoints(const std::vector<MediaScene::Interval>& iv, std::vector<float>* out) {
  out->clear();
  for (const auto& i : iv) out->push_back(i.t0), out->push_back(i.t1);
  std::sort(out->begin(), out->end());
  out->erase(std::unique(out->begin(), out->end()), out->end());
}

void activeIn(const std::vector<MediaScene::Interval>& iv, float a, float b,
              std::vector<uint32_t>* out) {
  out->clear();
  for (const auto& i : iv)
    if (i.t0 <= a && i.t1 >= b) out->push_back(i.region);
}

// The trackers' collision counts (TrackingCounts), added once per tracked ray, not per
// collision, so threads seldom meet on them.
std::atomic<uint64_t> gTentative{0}, gReal{0}, gRatioTentative{0};

// Counts one tracked ray's collisions and adds them when it goes out of scope.
struct CollisionTally {
  std::atomic<uint64_t>& total;
  uint64_t n = 0;
  explicit CollisionTally(std::atomic<uint64_t>& t) : total(t) {}
  CollisionTally(const CollisionTally&) = delete;
  CollisionTally& operator=(const CollisionTally&) = delete;
  ~CollisionTally() {
    if (n) total.fetch_add(n, std::memory_order_relaxed);
  }
};

// Per-thread scratch lists: no allocation per ray once warm. `integrate` and `transmittance`
// (which it calls for shadow rays) use separate ones.
struct Scratch {
  std::vector<MediaScene::Interval> intervals;
  std::vector<float> cuts;
  std::vector<uint32_t> active;

  // The regions along t in [0, tMax] of `ray` and the cuts where the set of them changes;
  // false when the ray meets none.
  bool along(const MediaScene& media, const Ray& ray, float tMax) {
    media.intervals(ray, tMax, &intervals);
    if (intervals.empty()) return false;
    breakpoints(intervals, &cuts);
    return true;
  }
  // Stretch k between two cuts, [*a, *b], with its regions in `active`; false when it is empty
  // or no region is active there.
  bool stretch(size_t k, float* a, float* b) {
    *a = cuts[k], *b = cuts[k + 1];
    activeIn(intervals, *a, *b, &active);
    return !active.empty() && *b > *a;
  }
};
Scratch& integrateScratch() {
  thread_local Scratch s;
  return s;
}
Scratch& transmittanceScratch() {
  thread_local Scratch s;
  return s;
}

}  // namespace

double TrackingCounts::nullPerReal() const {
  return real ? double(tentative - real) / double(real) : 0.0;
}

TrackingCounts trackingCounts() {
  return {gTentative.load(), gReal.load(), gRatioTentative.load()};
}

void resetTrackingCounts() { gTentative = 0, gReal = 0, gRatioTentative = 0; }

// ---------------------------------------------------------------------------------------------
// Regions
// ---------------------------------------------------------------------------------------------

MediaScene::MediaScene(const IntegratorSettings& settings)
    : single_(settings.volume != "emission"),
      track_(settings.volumeEstimator == "track"),
      step_(settings.volumeStep) {}

void MediaScene::finishRegion(Region* r, const Bounds3f& objectBounds) {
  r->maxDensity = r->medium->density->maxDensity(objectBounds);
  r->majorant = maxComponent(r->medium->sigmaTBound()) * r->maxDensity;
  r->step = step_ > 0 ? step_ : length(r->box.diagonal()) / kAutoStepsPerDiagonal;
  r->grid = r->medium->density->majorantGrid();
  r->gridScale = maxComponent(r->medium->sigmaTBound());
  const Rgb sigmaT = r->medium->sigmaTBound();
  const bool coloured = sigmaT.x != sigmaT.y || sigmaT.y != sigmaT.z;
  if (coloured && r->medium->heroTracking) heroTracking_ = true;
  if (r->medium->emits()) emits_ = true;
  const MajorantGrid* bound =
      r->medium->emissionField ? r->medium->emissionField->luminanceBound() : nullptr;
  if (bound && r->grid && maxComponent(r->medium->Le) <= 0 && bound->maxValue() > 0) {
    const MajorantGrid& g = *r->grid;
    bool sameCells = true;
    for (int a = 0; a < 3; ++a)
      sameCells = sameCells && g.res(a) == bound->res(a) &&
                  g.bounds().lower[a] == bound->bounds().lower[a] &&
                  g.bounds().upper[a] == bound->bounds().upper[a];
    if (sameCells) {
      const Vec3f extent = g.bounds().diagonal();
      const float cell =
          (extent.x / float(g.res(0)) + extent.y / float(g.res(1)) + extent.z / float(g.res(2))) /
          3;
      r->emissionBound = bound;
      r->emissionRate = kEmissionSamplesPerCell / (bound->maxValue() * cell);
    }
  }
}

void MediaScene::addRegion(std::unique_ptr<Medium> medium, std::unique_ptr<Shape> shape,
                           const Transform& worldFromObject) {
  Region r;
  r.medium = std::move(medium);
  r.shape = std::move(shape);
  r.placed.emplace(r.shape.get(), worldFromObject);
  r.objectFromWorld = worldFromObject.inverse();
  r.box = r.placed->bounds();
  if (dynamic_cast<const Box*>(r.shape.get())) r.objectBox = r.shape->bounds();
  const Bounds3f objectBounds = r.shape->bounds();
  finishRegion(&r, objectBounds);
  regions_.push_back(std::move(r));
}

void MediaScene::addSceneRegion(std::unique_ptr<Medium> medium, const Bounds3f& box) {
  Region r;
  r.medium = std::move(medium);
  r.box = box;
  finishRegion(&r, box);
  regions_.push_back(std::move(r));
}

void MediaScene::intervals(const Ray& ray, float tMax, std::vector<Interval>* out) const {
  out->clear();
  for (uint32_t i = 0; i < regions_.size(); ++i) {
    const Region& r = regions_[i];
    float t0 = std::max(0.0f, ray.tMin), t1 = tMax;
    if (r.placed) {
      // Most rays pass a bounded region by: its box settles them before the exact span.
      if (segmentMissesBox(ray, reciprocalDirection(ray.d), r.box, t0, t1)) continue;
      if (r.objectBox) {
        // A box (every VDB medium's region): a slab test in its object space, where t means
        // what it does here (an affine map keeps a ray's parameter). The exact span's error
        // bounds and normals serve surfaces; a medium's edge needs neither, and this is most of
        // the cost of a ray that enters a medium.
        const Ray local{r.objectFromWorld.point(ray.o), r.objectFromWorld.vector(ray.d)};
        if (!clipToBox(local, *r.objectBox, &t0, &t1)) continue;
      } else {
        Span span;
        if (!r.placed->span(ray, {}, &span)) continue;
        t0 = std::max(t0, span.enter.t), t1 = std::min(t1, span.exit.t);
      }
    } else if (!clipToBox(ray, r.box, &t0, &t1)) {
      continue;
    }
    // An unbounded end (a ray that never leaves) would make every estimator diverge; regions
    // are bounded, so this only guards degenerate rays.
    if (t0 < t1 && std::isfinite(t1)) out->push_back({t0, t1, i});
  }
}

Rgb MediaScene::emission(const std::vector<uint32_t>& active, Vec3f p) const {
  Rgb L;
  for (uint32_t i : active) {
    const Region& r = regions_[i];
    if (maxComponent(r.medium->Le) > 0) L += r.medium->Le * density(r, p);
    if (r.medium->emissionField) L += r.medium->emissionField->emission(r.objectFromWorld.point(p));
  }
  return L;
}

MediaScene::Coefficients MediaScene::coefficients(const std::vector<uint32_t>& active,
                                                  Vec3f p) const {
  Coefficients c;
  for (uint32_t i : active) {
    const Region& r = regions_[i];
    const float d = density(r, p);
    const Rgb sigmaS = scattering(r, p, d);
    c.sigmaT += r.medium->sigmaT(sigmaS) * d;
    c.sigmaS += sigmaS * d;
    c.emission += r.medium->Le * d;
    if (r.medium->emissionField)
      c.emission += r.medium->emissionField->emission(r.objectFromWorld.point(p));
  }
  return c;
}

MajorantWalk MediaScene::majorantWalk(const Ray& ray, float a, float b,
                                      const std::vector<uint32_t>& active) const {
  const Region* gridded = nullptr;
  float constant = 0;
  for (uint32_t i : active) {
    const Region& r = regions_[i];
    if (!gridded && r.grid)
      gridded = &r;
    else
      constant += r.majorant;
  }
  return gridded ? regionWalk(*gridded, ray, a, b, constant) : MajorantWalk(a, b, constant);
}

MajorantWalk MediaScene::regionWalk(const Region& r, const Ray& ray, float a, float b,
                                    float constant) const {
  if (!r.grid) return MajorantWalk(a, b, constant + r.majorant);
  return MajorantWalk(*r.grid, r.gridScale, r.objectFromWorld.point(ray.o),
                      r.objectFromWorld.vector(ray.d), a, b, constant, r.emissionBound);
}

// ---------------------------------------------------------------------------------------------
// Transmittance
// ---------------------------------------------------------------------------------------------

Rgb MediaScene::regionTransmittance(const Region& r, const Ray& ray, float t0, float t1,
                                    Sampler& sampler, bool track) const {
  const float len = length(ray.d);
  const float s = (t1 - t0) * len;  // world-space length
  const Medium& m = *r.medium;
  if (m.homogeneous()) return expNeg(m.sigmaT() * (m.density->density({}) * s));
  if (r.majorant <= 0) return {1, 1, 1};
  const Vec3f dUnit = ray.d / len;
  const Vec3f start = ray.at(t0);
  if (track) {
    // Ratio tracking (Novák et al. 2014): tentative collisions at the majorant's rate, each
    // multiplying by the probability of it being a null collision; cell by cell where the
    // density has a majorant grid.
    MajorantWalk walk = regionWalk(r, ray, t0, t1, 0);
    CollisionTally tally(gRatioTentative);
    Rgb T{1, 1, 1};
    MajorantSegment seg;
    CollisionStepper stepper;
    while (walk.next(&seg)) {
      if (seg.majorant <= 0) continue;
      const float segLength = (seg.t1 - seg.t0) * len;
      const Vec3f segStart = ray.at(seg.t0);
      float x = 0;
      while (stepper.next(seg.majorant, segLength, &x, sampler)) {
        ++tally.n;
        const Vec3f p = segStart + dUnit * x;
        const float d = density(r, p);
        const Rgb sigmaT = m.color ? m.sigmaT(scattering(r, p, d)) : m.sigmaT();
        T *= max(Rgb{0, 0, 0}, Rgb{1, 1, 1} - sigmaT * (d / seg.majorant));
        if (!survivesRoulette(&T, sampler)) return {};
      }
    }
    return T;
  }
  // Fixed steps, all shifted by one jittered offset.
  const int n = std::clamp(int(std::ceil(s / r.step)), 1, kMaxSteps);
  const float ds = s / float(n);
  const float u = sampler.get1D();
  if (m.color) {  // sigma_t varies in colour as well
    Rgb depth;
    for (int k = 0; k < n; ++k) {
      const Vec3f p = start + dUnit * ((float(k) + u) * ds);
      const float d = density(r, p);
      depth += m.sigmaT(scattering(r, p, d)) * d;
    }
    return expNeg(depth * ds);
  }
  float depth = 0;
  for (int k = 0; k < n; ++k) depth += density(r, start + dUnit * ((float(k) + u) * ds));
  return expNeg(m.sigmaT() * (depth * ds));
}

Rgb MediaScene::transmittance(const Ray& ray, float tMax, Sampler& sampler) const {
  return transmittance(ray, tMax, sampler, track_);
}

Rgb MediaScene::trackedTransmittance(const Ray& ray, float tMax, Sampler& sampler) const {
  return transmittance(ray, tMax, sampler, true);
}

Rgb MediaScene::transmittance(const Ray& ray, float tMax, Sampler& sampler, bool track) const {
  Scratch& scratch = transmittanceScratch();
  intervals(ray, tMax, &scratch.intervals);
  // Coefficients of overlapping regions add, so their transmittances multiply.
  Rgb T{1, 1, 1};
  for (const Interval& i : scratch.intervals) {
    T *= regionTransmittance(regions_[i.region], ray, i.t0, i.t1, sampler, track);
    if (maxComponent(T) <= 0) return {};
  }
  return T;
}

// ---------------------------------------------------------------------------------------------
// In-scattering
// ---------------------------------------------------------------------------------------------

Rgb MediaScene::source(const RenderScene& scene, const std::vector<uint32_t>& active, Vec3f p,
                       Vec3f d, float time, const Coefficients& c, Sampler& sampler,
                       RayCounters& counters) const {
  Rgb S = c.emission;
  if (!single_ || maxComponent(c.sigmaS) <= 0) return S;
  const LightSampleContext ctx = LightSampleContext::inMedium(p, time);
  // Each region scatters with its own phase function.
  auto scatter = [&](Vec3f wi, float*) -> Rgb {
    Rgb sum;
    const float cosTheta = dot(wi, d);
    for (uint32_t i : active) {
      const Region& r = regions_[i];
      if (!r.medium->scatters()) continue;
      const float rho = density(r, p);
      sum += scattering(r, p, rho) * (rho * henyeyGreenstein(cosTheta, r.medium->g));
    }
    return sum;
  };
  auto tr = [&](const Ray& shadow) { return transmittance(shadow, shadow.tMax, sampler); };
  for (const auto& light : scene.lights()) {
    const Vec2f u = light->isDelta() ? Vec2f{0.5f, 0.5f} : sampler.get2D();
    S += sampleDirectLight(scene, ctx, *light, u, DirectLightOptions{}, scatter, tr, counters);
  }
  return S;
}

VolumeSegment MediaScene::integrate(const RenderScene& scene, const Ray& ray, float tMax,
                                    Sampler& sampler, RayCounters& counters) const {
  VolumeSegment seg;
  Scratch& scratch = integrateScratch();
  if (!scratch.along(*this, ray, tMax)) return seg;
  const float len = length(ray.d);
  const Vec3f dUnit = ray.d / len;
  // One jittered offset for every marched stretch of this camera sample.
  const float jitter = track_ ? 0 : sampler.get1D();
  for (size_t k = 0; k + 1 < scratch.cuts.size(); ++k) {
    float a, b;
    if (!scratch.stretch(k, &a, &b)) continue;
    const float s = (b - a) * len;
    const Vec3f start = ray.at(a);
    bool homogeneous = true, scatters = false;
    float step = kInfinity;
    for (uint32_t i : scratch.active) {
      const Region& r = regions_[i];
      homogeneous = homogeneous && r.medium->homogeneous();
      scatters = scatters || r.medium->scatters();
      step = std::min(step, r.step);
    }
    const bool sourceVaries = single_ && scatters;
    if (homogeneous && !sourceVaries) {
      // Constant coefficients and source: the closed form, exactly.
      const Coefficients c = coefficients(scratch.active, start);
      seg.L += seg.T * c.emission * sourceIntegral(c.sigmaT, s);
      seg.T *= expNeg(c.sigmaT * s);
    } else if (track_ && homogeneous) {
      // Exact transmittance; the in-scattering integral from one distance sample with density
      // proportional to exp(-mu x) on [0, s], mu the channels' mean sigma_t.
      const Coefficients c = coefficients(scratch.active, start);
      const float mu = (c.sigmaT.x + c.sigmaT.y + c.sigmaT.z) / 3;
      const float u = sampler.get1D();
      float x = u * s, pdf = 1 / s;
      if (mu * s > 1e-4f) {
        const float norm = -std::expm1(-mu * s);
        x = std::min(s, -std::log1p(-u * norm) / mu);
        pdf = mu * std::exp(-mu * x) / norm;
      }
      const Vec3f p = start + dUnit * x;
      const Rgb S = source(scene, scratch.active, p, dUnit, ray.time, c, sampler, counters);
      seg.L += seg.T * S * expNeg(c.sigmaT * x) / pdf;
      seg.T *= expNeg(c.sigmaT * s);
    } else if (track_) {
      // Ratio tracking with the source gathered at every tentative collision: the collisions
      // form a Poisson process of rate `majorant`, so sum T(x_i) S(x_i) / majorant estimates
      // the integral of T S, with T(x_i) the ratio-tracking estimate up to x_i. Stretch by
      // stretch of the majorant grid, where there is one.
      MajorantWalk walk = majorantWalk(ray, a, b, scratch.active);
      CollisionTally tally(gRatioTentative);
      MajorantSegment m;
      CollisionStepper stepper;
      while (walk.next(&m)) {
        const float segLength = (m.t1 - m.t0) * len;
        const Vec3f segStart = ray.at(m.t0);
        if (m.majorant <= 0) {
          // No extinction here (T stays), so no collisions: emission from one uniformly
          // placed sample of its integral.
          const Vec3f p = segStart + dUnit * (sampler.get1D() * segLength);
          seg.L += seg.T * coefficients(scratch.active, p).emission * segLength;
          continue;
        }
        float x = 0;
        while (stepper.next(m.majorant, segLength, &x, sampler)) {
          ++tally.n;
          const Vec3f p = segStart + dUnit * x;
          const Coefficients c = coefficients(scratch.active, p);
          seg.L += seg.T * source(scene, scratch.active, p, dUnit, ray.time, c, sampler, counters) /
                   m.majorant;
          seg.T *= max(Rgb{0, 0, 0}, Rgb{1, 1, 1} - c.sigmaT / m.majorant);
          if (!survivesRoulette(&seg.T, sampler)) return {Rgb{0, 0, 0}, seg.L};
        }
      }
    } else {
      // Fixed steps: coefficients and source from one jittered point per step, integrated
      // exactly over the step as if constant there.
      const int n = std::clamp(int(std::ceil(s / step)), 1, kMaxSteps);
      const float ds = s / float(n);
      for (int j = 0; j < n; ++j) {
        const Vec3f p = start + dUnit * ((float(j) + jitter) * ds);
        const Coefficients c = coefficients(scratch.active, p);
        const Rgb S = source(scene, scratch.active, p, dUnit, ray.time, c, sampler, counters);
        seg.L += seg.T * S * sourceIntegral(c.sigmaT, ds);
        seg.T *= expNeg(c.sigmaT * ds);
      }
    }
    if (maxComponent(seg.T) <= 0) return {Rgb{0, 0, 0}, seg.L};
  }
  return seg;
}

// ---------------------------------------------------------------------------------------------
// Free-flight sampling
// ---------------------------------------------------------------------------------------------

void MediaScene::pickScatterer(const std::vector<uint32_t>& active, Vec3f p, const Coefficients& c,
                               Sampler& sampler, MediumEvent* event) const {
  // The scattering region (whose phase function the path takes), in proportion to its share
  // of sigma_s. The number is drawn even for one region, so the stream does not depend on it.
  float pick = sampler.get1D() * mean(c.sigmaS);
  if (active.size() == 1) {
    event->g = regions_[active[0]].medium->g;
    return;
  }
  for (uint32_t i : active) {
    const Region& r = regions_[i];
    event->g = r.medium->g;
    const float d = density(r, p);
    pick -= mean(scattering(r, p, d)) * d;
    if (pick < 0) break;
  }
}

MediaScene::EmissionGuide MediaScene::emissionGuide(const std::vector<uint32_t>& active,
                                                    Vec3f dUnit) const {
  EmissionGuide g;
  const Region* gridded = nullptr;  // the region whose cells majorantWalk walks
  int emitters = 0;
  for (uint32_t i : active) {
    const Region& r = regions_[i];
    if (!gridded && r.grid) gridded = &r;
    emitters += r.medium->emits() ? 1 : 0;
  }
  g.emits = emitters > 0;
  if (emitters == 1 && gridded && gridded->emissionBound && gridded->medium->emits())
    g.rate = gridded->emissionRate * length(gridded->objectFromWorld.vector(dUnit));
  return g;
}

template <class Weight>
Rgb MediaScene::stretchEmission(const std::vector<uint32_t>& active, Vec3f start, Vec3f dUnit,
                                float from, float to, const EmissionGuide& guide, float bound,
                                const SegmentSamples* first, Sampler& sampler,
                                Weight&& weight) const {
  int n = 1;
  if (guide.rate > 0) {
    if (!(bound > 0)) return {};  // the bound says nothing is emitted in this cell
    n = int(
        std::clamp(std::ceil(guide.rate * bound * (to - from)), 1.0f, float(kMaxEmissionSamples)));
  }
  // n jittered points, one in each nth of the stretch (all at the segment's offset where it
  // has one).
  const float h = (to - from) / float(n);
  Rgb sum;
  for (int i = 0; i < n; ++i) {
    const float u = first ? first->jitter : sampler.get1D();
    const float y = from + (float(i) + u) * h;
    sum += emission(active, start + dUnit * y) * weight(y);
  }
  return sum * h;
}

MediumEvent MediaScene::sampleScattering(const Ray& ray, float tMax, Sampler& sampler) const {
  return deltaTrack(ray, tMax, sampler, nullptr, nullptr, nullptr);
}

MediumEvent MediaScene::sampleScatteringAndEmission(const Ray& ray, float tMax, Sampler& sampler,
                                                    Rgb* emitted, ChannelPath* path,
                                                    const SegmentSamples* first) const {
  *emitted = {};
  return deltaTrack(ray, tMax, sampler, emitted, path, first);
}

MediumEvent MediaScene::deltaTrack(const Ray& ray, float tMax, Sampler& sampler, Rgb* emitted,
                                   ChannelPath* path, const SegmentSamples* first) const {
  if (heroTracking_) return heroTrack(ray, tMax, sampler, emitted, path, first);
  MediumEvent event;
  Scratch& scratch = integrateScratch();
  if (!scratch.along(*this, ray, tMax)) return event;
  const float len = length(ray.d);
  const Vec3f dUnit = ray.d / len;
  CollisionTally tentative(gTentative), real(gReal);
  // One optical depth per collision, carried across the regions' stretches and the grid's
  // cells (the gaps between regions have no extinction, so what is left of it stays valid).
  CollisionStepper stepper;
  if (first) stepper.start(first->flight);
  bool firstEvent = first != nullptr;
  // The whole segment's emission (SegmentSamples::wholeSegmentEmission): the same tentative
  // collisions weigh a ratio-tracking estimate of the transmittance, under which the emission
  // is gathered; once a collision has decided the event, tracking goes on for the emission
  // alone, with roulette, to the end of the last stretch where a medium emits.
  bool whole = emitted && first && first->wholeSegmentEmission && emits_;
  Rgb ratio{1, 1, 1};    // the ratio-tracking estimate of the transmittance so far
  bool decided = false;  // the event is found: the rest is emission
  // The last stretch where a medium emits: past it, once the event is decided, tracking ends
  // (a fog beyond a fire is not tracked for the fire's sake); none on this ray: no whole
  // segment.
  size_t lastEmitting = 0;
  if (whole) {
    whole = false;
    for (size_t k = 0; k + 1 < scratch.cuts.size(); ++k) {
      float a, b;
      if (scratch.stretch(k, &a, &b) && emissionGuide(scratch.active, dUnit).emits)
        lastEmitting = k, whole = true;
    }
  }
  // Past the event: whether tracking goes on for the emission, in stretch k (roulette on the
  // ratio, as on a shadow ray's). Its collisions are ratio tracking's, and counted so.
  CollisionTally ratioOnly(gRatioTentative);
  auto goesOn = [&](size_t k) { return k <= lastEmitting && survivesRoulette(&ratio, sampler); };
  for (size_t k = 0; k + 1 < scratch.cuts.size(); ++k) {
    if (decided && k > lastEmitting) return event;
    float a, b;
    if (!scratch.stretch(k, &a, &b)) continue;
    bool homogeneous = true;
    for (uint32_t i : scratch.active)
      homogeneous = homogeneous && regions_[i].medium->homogeneous();
    const EmissionGuide guide = emissionGuide(scratch.active, dUnit);
    const bool emits = guide.emits;
    MajorantWalk walk = majorantWalk(ray, a, b, scratch.active);
    MajorantSegment seg;
    while (walk.next(&seg)) {
      const float majorant = seg.majorant;
      const float s = (seg.t1 - seg.t0) * len;
      const Vec3f start = ray.at(seg.t0);
      // Emission by the track-length estimator: between two tentative collisions the path is
      // alive with the weight it has, so each stretch's emission integral times that weight
      // sums to an unbiased estimate of the integral of T emission; jittered samples (one,
      // or as many as the emission bound asks for) estimate each stretch's integral (the
      // integral itself when constant). Where
      // the density is thin and the emission strong (a fire), this gathers emission along the
      // whole ray, where weighing it at the collisions (pbrt-v4's estimator) gathered a few
      // large samples or none: 5x less error at equal time on scenes/volumes' fire. For the
      // whole segment the weight is the ratio-tracked transmittance instead: the same
      // integral, without the noise of where the path happens to stop.
      auto gather = [&](float from, float to) {
        if (!emitted || !emits || !(to > from)) return;
        const Rgb& w = whole ? ratio : event.weight;
        if (homogeneous) {
          *emitted += w * emission(scratch.active, start + dUnit * from) * (to - from);
          return;
        }
        *emitted += w * stretchEmission(scratch.active, start, dUnit, from, to, guide, seg.emission,
                                        first, sampler, [](float) {
                                          return Rgb{1, 1, 1};
                                        });
      };
      if (majorant <= 0) {  // no extinction (T = 1 here), so no collisions
        gather(0, s);
        continue;
      }
      float x = 0;
      for (;;) {
        const float from = x;
        const bool collided = stepper.next(majorant, s, &x, sampler);
        gather(from, collided ? x : s);
        if (!collided) break;
        ++(decided ? ratioOnly : tentative).n;
        const Coefficients c = coefficients(scratch.active, start + dUnit * x);
        if (whole) {
          ratio *= max(Rgb{0, 0, 0}, Rgb{1, 1, 1} - c.sigmaT / majorant);
          if (decided) {
            if (!goesOn(k)) return event;
            continue;
          }
        }
        // Channel-averaged event probabilities (majorant >= every channel's sigma_t, so they
        // sum to <= 1); each event weighs its true coefficient over majorant * its probability,
        // which keeps every channel unbiased. Where the medium scatters at all, absorption is
        // weighed rather than sampled (as Mitsuba and Cycles do; pbrt-v4 ends the path): every
        // real collision scatters, with the weight sigma_s / mean(sigma_t), the albedo for
        // grey media, and Russian roulette ends paths whose weight has run down. A path that
        // absorption ended carried no light from beyond: in the fire of scenes/volumes (albedo
        // 0.5) half the collisions ended paths, and weighing them made it 1.3x as efficient
        // (benchmarks/README, issue 52).
        const float pReal = mean(c.sigmaT) / majorant;
        const float pScatter = mean(c.sigmaS) > 0 ? pReal : 0.0f;
        const float pAbsorb = pReal - pScatter;
        const float u = firstEvent ? first->event : sampler.get1D();
        firstEvent = false;
        if (u < pAbsorb) {
          ++real.n;
          if (!whole) return {false, 0, Rgb{0, 0, 0}, 0};
          event = {false, 0, Rgb{0, 0, 0}, 0};
          decided = true;
          if (!goesOn(k)) return event;
          continue;
        }
        if (u < pAbsorb + pScatter) {
          ++real.n;
          event.scattered = true;
          event.t = seg.t0 + x / len;
          event.weight *= c.sigmaS / (majorant * pScatter);
          pickScatterer(scratch.active, start + dUnit * x, c, sampler, &event);
          if (!whole) return event;
          decided = true;
          if (!goesOn(k)) return event;
          continue;
        }
        const float pNull = 1 - pAbsorb - pScatter;
        if (pNull <= 0) continue;  // only by rounding: then sigma_t = majorant, a weight of 1
        event.weight *=
            max(Rgb{0, 0, 0}, Rgb{majorant, majorant, majorant} - c.sigmaT) / (majorant * pNull);
      }
    }
  }
  return event;
}

// ---------------------------------------------------------------------------------------------
// Coloured extinction: spectral MIS over a hero channel
// ---------------------------------------------------------------------------------------------
//
// deltaTrack samples collisions at the largest channel's majorant and picks events by the
// channels' mean probabilities; each null collision then weighs (majorant - sigma_t) /
// (majorant pNull) per channel, which for sigma_t = (1, 4, 16) is far from 1 in every channel
// but the largest, and the product over a ray's null collisions is heavy-tailed. heroTrack
// follows the null-scattering path integral (Miller, Georgiev and Jarosz 2019) as pbrt-v4's
// VolPathIntegrator does with its hero wavelength: one channel h, chosen uniformly per ray,
// is tracked on its own (its own majorant, its own absorption, scattering and null
// probabilities), and every channel c is weighed by one-sample MIS (the balance heuristic)
// over the three channels' trackers:
//   weight_c = f_c / ((p_0 + p_1 + p_2) / 3),
// where p_k is the density with which channel k's tracker makes the same collisions and
// events. For a tracker that follows its own channel exactly, f_c = p_c (analogue tracking),
// so weight_c = p_c / mean(p): never above 3, whatever the channels. Only ratios of the p_k
// matter, so R = (p_0, p_1, p_2) is kept up to a common factor (pbrt-v4's r_u), renormalised
// so that it neither overflows nor underflows. Per collision and stretch:
//   a stretch of length x without collision: p_k *= exp(-M_k x) (M_k: channel k's majorant);
//   a collision: p_k *= M_k (its rate), then the event's probability: where the medium
//     scatters, absorption is weighed as in deltaTrack (a real collision scatters with
//     probability sigma_t,k / M_k, and the path takes the albedo sigma_s,c / sigma_t,c), else
//     it absorbs with sigma_a,k / M_k; null sigma_n,k / M_k = (M_k - sigma_t,k) / M_k. So
//     p_k *= sigma_n,k for a null collision and sigma_t,k (sigma_s,k) for a scattering one;
//   emission, by the track-length estimator as in deltaTrack: a sample at y between two
//     collisions weighs R_c(y) / mean(R(y)), R(y) its value at the stretch's start times
//     exp(-M y) (the channels' densities of the hero being alive there). It was gathered at
//     the collisions (emission_c R_c / mean(R M), pbrt-v4's estimator) until a fire with
//     coloured smoke came out 8x noisier under spectral MIS than under max_channel, which
//     had these estimators (benchmarks/README, issue 52).
// Grey extinction keeps deltaTrack: there all channels' trackers are the same one.

Rgb MediaScene::channelMajorants(const std::vector<uint32_t>& active, float cell) const {
  Rgb M;
  bool gridded = false;
  for (uint32_t i : active) {
    const Region& r = regions_[i];
    if (!gridded && r.grid)
      gridded = true, M += r.medium->sigmaTBound() * cell;
    else
      M += r.medium->sigmaTBound() * r.maxDensity;
  }
  return M;
}

ChannelPath MediaScene::startPath(Sampler& sampler) const {
  ChannelPath path;
  if (heroTracking_) path.hero = std::min(2, int(sampler.get1D() * 3));
  return path;
}

MediumEvent MediaScene::heroTrack(const Ray& ray, float tMax, Sampler& sampler, Rgb* emitted,
                                  ChannelPath* path, const SegmentSamples* first) const {
  MediumEvent event;
  Scratch& scratch = integrateScratch();
  if (!scratch.along(*this, ray, tMax)) return event;
  const float len = length(ray.d);
  const Vec3f dUnit = ray.d / len;
  CollisionTally tentative(gTentative), real(gReal);
  ChannelPath own;
  if (!path) own = startPath(sampler), path = &own;
  const int h = path->hero;
  // R: the channels' trackers' densities of the path so far, up to a factor. The caller's
  // throughput already holds Rin / mean(Rin); what this segment returns turns that into
  // R / mean(R): weights (R / Rin) mean(Rin) / mean(R), and emission likewise.
  const Rgb Rin = path->R;
  const Rgb RinMean = Rgb{1, 1, 1} * mean(Rin);
  auto change = [&](Rgb R) { return safeDivide(R, Rin) * RinMean; };
  Rgb& R = path->R;
  CollisionStepper stepper;  // as in deltaTrack, across stretches and cells
  if (first) stepper.start(first->flight);
  bool firstEvent = first != nullptr;
  for (size_t k = 0; k + 1 < scratch.cuts.size(); ++k) {
    float a, b;
    if (!scratch.stretch(k, &a, &b)) continue;
    const EmissionGuide guide = emissionGuide(scratch.active, dUnit);
    MajorantWalk walk = majorantWalk(ray, a, b, scratch.active);
    MajorantSegment seg;
    while (walk.next(&seg)) {
      const Rgb M = channelMajorants(scratch.active, seg.cell);
      const float s = (seg.t1 - seg.t0) * len;
      const Vec3f start = ray.at(seg.t0);
      // Emission by the track-length estimator, as in deltaTrack: along a stretch from a
      // collision (or the cell's start) the trackers' densities fall as exp(-M y), so each
      // emission sample weighs the MIS weight R / mean(R) where it lies.
      auto gather = [&](float from, float to) {
        if (!emitted || !guide.emits || !(to > from)) return;
        *emitted += stretchEmission(scratch.active, start, dUnit, from, to, guide, seg.emission,
                                    first, sampler, [&](float y) {
                                      Rgb Ry = R;
                                      attenuate(&Ry, M, y - from);
                                      return change(Ry) / mean(Ry);
                                    });
      };
      float x = 0, last = 0;
      for (;;) {
        // A hero without extinction here makes no collision: its tracker passes.
        const float from = x;
        const bool collided = M[h] > 0 && stepper.next(M[h], s, &x, sampler);
        gather(from, collided ? x : s);
        if (!collided) break;
        ++tentative.n;
        attenuate(&R, M, x - last);
        last = x;
        const Coefficients c = coefficients(scratch.active, start + dUnit * x);
        // As in deltaTrack, absorption is weighed where the medium scatters: every real
        // collision of the hero scatters (each channel's tracker with probability
        // sigma_t / M, so its density takes sigma_t) and the path takes the albedo.
        const bool weighs = mean(c.sigmaS) > 0;
        const float pScatter = (weighs ? c.sigmaT[h] : c.sigmaS[h]) / M[h];
        const float pAbsorb = (c.sigmaT[h] - c.sigmaS[h]) / M[h] * (weighs ? 0.0f : 1.0f);
        const float u = firstEvent ? first->event : sampler.get1D();
        firstEvent = false;
        if (u < pAbsorb) {
          ++real.n;
          return {false, 0, Rgb{0, 0, 0}, 0};
        }
        if (u < pAbsorb + pScatter) {
          ++real.n;
          R *= weighs ? c.sigmaT : c.sigmaS;
          if (!(maxComponent(R) > 0)) return {false, 0, Rgb{0, 0, 0}, 0};
          R = R / maxComponent(R);
          event.scattered = true;
          event.t = seg.t0 + x / len;
          event.weight = change(R) / mean(R);
          if (weighs) event.weight *= safeDivide(c.sigmaS, c.sigmaT);
          pickScatterer(scratch.active, start + dUnit * x, c, sampler, &event);
          return event;
        }
        R *= max(Rgb{0, 0, 0}, M - c.sigmaT);
        const float big = maxComponent(R);
        if (!(big > 0)) return {false, 0, Rgb{0, 0, 0}, 0};
        R = R / big;
      }
      attenuate(&R, M, s - last);
    }
  }
  event.weight = change(R) / mean(R);
  return event;
}

}  // namespace glint
