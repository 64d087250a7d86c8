// glint — participating media along rays: transmittance, in-scattering and free-flight
// sampling over the scene's medium regions.
//
// Media fill REGIONS, not the insides of surfaces: a region is a convex solid (sphere, box,
// capped cylinder or cone, under a transform) or the whole scene (a box around everything the
// builder knows of: geometry, camera, lights). A region's boundary is invisible — it is not in
// the accelerator — and a visible container (a glass bowl of smoke) is a separate object.
// Where regions overlap, their coefficients add. Why regions instead of media bound to
// surfaces (pbrt's interface media, Mitsuba's medium stacks): which media a point lies in is
// then a property of the point, found by clipping the ray against a few solids, so there is
// no stack of "current media" to carry along paths, nothing to go wrong when a surface is
// missed by rounding or when containers intersect, and shadow rays need no bookkeeping at all.
// The cost: media cannot follow arbitrary meshes (a CSG or mesh-shaped medium is a later
// extension of the region, not of the surfaces).
//
// Estimators (IntegratorSettings::volumeEstimator): homogeneous media always use the closed
// forms; heterogeneous media are either marched with fixed steps ("march": one jittered offset
// per camera sample, steps of `volumeStep`, 0 = 1/64 of the region's diagonal; biased by the
// step, consistent) or tracked against the density majorant ("track": ratio tracking for
// transmittance and in-scattering at every tentative collision, or for homogeneous stretches
// exact transmittance and one exponentially distributed in-scattering point; unbiased,
// noisier).
//
// Tracking skips empty space where a density field has a majorant grid (VDB media,
// materials/majorant_grid.h): the ray is cut where it crosses the grid's cells
// (renderer/majorant_dda.h) and each stretch is tracked at its own cell's majorant, so empty
// cells cost no collision at all (pbrt-v4's approach). Where several media overlap, the first
// with a grid contributes its cells and the others their single majorants.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "geometry/shape.h"
#include "materials/medium.h"
#include "renderer/majorant_dda.h"
#include "renderer/sampler.h"
#include "renderer/settings.h"

namespace glint {

class RenderScene;
struct RayCounters;

// What a ray segment adds and lets through: radiance arriving = T * (radiance at the far end)
// + L.
struct VolumeSegment {
  Rgb T{1, 1, 1};
  Rgb L{0, 0, 0};
};

// A free-flight sample (delta tracking): a real scattering event at ray.at(t), or none.
struct MediumEvent {
  bool scattered = false;
  float t = 0;          // ray parameter of the event
  Rgb weight{1, 1, 1};  // multiplies the path throughput (zero: absorbed)
  float g = 0;          // phase asymmetry of the medium that scattered
};

// Spectral MIS over a whole path (MediaScene::heroTrack): the path's hero channel, tracked on
// its own in every segment, and the three channels' trackers' densities of the path so far,
// up to a common factor (pbrt-v4's r_u). Path throughputs already carry R / mean(R), so a
// segment's weight is the change of that ratio.
struct ChannelPath {
  int hero = 0;
  Rgb R{1, 1, 1};
};

// The numbers a path draws for one segment's tracking from its own sample dimensions, which
// are stratified over a pixel's samples, instead of from its tracking stream (path.h): the
// first free flight's optical depth, the event of the first tentative collision, and the
// offset of the emission samples (one jitter shared by the segment's stretches, as a ray
// marcher shares its step offset). The first free flight decides how far into a medium the
// path gets before it collides, and so how much of a flame the camera ray gathers before it
// scatters; stratified (the flight and the event as one 2D sample), it took the fire of
// scenes/volumes from 0.051 to 0.012 variance per sample at depth 0 (benchmarks/README, issue
// 52). Later collisions draw from the stream: stratifying them too gained nothing measurable.
struct SegmentSamples {
  float flight = 0, event = 0, jitter = 0;  // uniform in [0, 1)
  // Gather the emission of the whole segment, past the collision that scatters or absorbs the
  // path, under a ratio-tracked transmittance (where the media emit; MediaScene::deltaTrack).
  // The path tracer asks it for the camera ray. Coloured extinction under spectral MIS
  // (heroTrack) keeps the track-length estimator: see benchmarks/README, issue 52.
  bool wholeSegmentEmission = false;
};

// Tentative collisions of the trackers, summed over all threads since the last reset: how
// much work tracking does, and how much of it was wasted on null collisions.
struct TrackingCounts {
  uint64_t tentative = 0;       // delta tracking's tentative collisions (free-flight sampling)
  uint64_t real = 0;            // of those, real ones (absorption or scattering)
  uint64_t ratioTentative = 0;  // ratio tracking's collisions (transmittance, shadow rays)
  double nullPerReal() const;   // (tentative - real) / real, 0 without real collisions
};
TrackingCounts trackingCounts();
void resetTrackingCounts();

class MediaScene {
 public:
  // One region's overlap with a ray: ray parameters t0 < t1.
  struct Interval {
    float t0, t1;
    uint32_t region;
  };

  explicit MediaScene(const IntegratorSettings& settings);
  MediaScene(const MediaScene&) = delete;
  MediaScene& operator=(const MediaScene&) = delete;

  // Adds a region: `medium` inside the convex solid `shape` (Shape::isSolid) placed by
  // worldFromObject; the density field is evaluated in the shape's object space.
  void addRegion(std::unique_ptr<Medium> medium, std::unique_ptr<Shape> shape,
                 const Transform& worldFromObject);
  // Adds a region filling the world-space box `box` (the whole scene); the density field is
  // evaluated in world space.
  void addSceneRegion(std::unique_ptr<Medium> medium, const Bounds3f& box);

  size_t regionCount() const { return regions_.size(); }
  const Medium& medium(uint32_t region) const { return *regions_[region].medium; }
  // The regions' overlaps with the segment t in [0, tMax] of `ray` (any order), into `out`.
  void intervals(const Ray& ray, float tMax, std::vector<Interval>* out) const;

  // Transmittance along t in [0, tMax] of `ray` (exact for homogeneous media, estimated for
  // heterogeneous ones with the configured estimator).
  Rgb transmittance(const Ray& ray, float tMax, Sampler& sampler) const;
  // The same, but heterogeneous media always by ratio tracking (unbiased, whatever the
  // configured estimator): the path tracer's shadow rays.
  Rgb trackedTransmittance(const Ray& ray, float tMax, Sampler& sampler) const;

  // Emission and (single mode) single scattering of the scene's lights along t in [0, tMax]
  // of `ray` (tMax = kInfinity: up to where the ray leaves the last region), with the
  // transmittance of the segment. Light samples use shadow rays whose transmittance is
  // included (volumetric shadows), counted in `counters`.
  VolumeSegment integrate(const RenderScene& scene, const Ray& ray, float tMax, Sampler& sampler,
                          RayCounters& counters) const;

  // Delta tracking along t in [0, tMax] of `ray` against the density majorants (for path
  // tracers): E[weight * f(event)] = integral of T(t) sigma_s(t) f(t) dt over scattering
  // events, and E[weight] = T(tMax) over rays that pass. Emission is not included.
  MediumEvent sampleScattering(const Ray& ray, float tMax, Sampler& sampler) const;
  // sampleScattering plus the media's emission along the way: `*emitted` receives an unbiased
  // estimate of the integral of T(t) emission(t) dt over t up to the event (or to tMax), by
  // the track-length estimator: over each stretch between tentative collisions (or across a
  // stretch without extinction), the tracking weight so far times the stretch's length times
  // the emission's mean over jittered points of it: one, or where the emitting medium bounds
  // its emission cell by cell (EmissionField::luminanceBound) none in cells that cannot emit
  // and more in proportion to the bound elsewhere (the stretch's integral when constant).
  // Media with coloured extinction under spectral MIS (heroTrack) gather it the same way,
  // each sample weighed by the MIS weight where it lies. Draws the same numbers as
  // sampleScattering where nothing emits.
  // `first`, when given, supplies the segment's first numbers (SegmentSamples); with its
  // wholeSegmentEmission, the estimate is of the integral up to tMax instead, whatever the
  // event (the ratio-tracking weight in place of the tracking weight, tracking going on past
  // the event while some medium ahead emits); the event is the same.
  MediumEvent sampleScatteringAndEmission(const Ray& ray, float tMax, Sampler& sampler,
                                          Rgb* emitted, ChannelPath* path = nullptr,
                                          const SegmentSamples* first = nullptr) const;
  // A path's spectral MIS state, where a medium has coloured extinction: its hero channel is
  // drawn from `sampler` (nothing is drawn otherwise). Passed to every segment's
  // sampleScatteringAndEmission, it makes one MIS over the whole path; without it, each
  // segment draws its own hero and its weight is an MIS over that segment alone (unbiased,
  // but the weights of a path's segments then multiply, up to 3 each).
  ChannelPath startPath(Sampler& sampler) const;

 private:
  struct Region {
    std::unique_ptr<Medium> medium;
    std::unique_ptr<Shape> shape;  // null: `box` in world space
    std::optional<PlacedShape> placed;
    std::optional<Bounds3f> objectBox;  // a Box's object-space bounds: its span is a slab test
    Transform objectFromWorld;
    Bounds3f box;                        // world-space bounds
    float majorant = 0;                  // max over channels of sigma_t, times the max density
    float step = 0;                      // marching step (world units)
    const MajorantGrid* grid = nullptr;  // the density's cell maxima (null: `majorant` only)
    float gridScale = 0;                 // max over channels of sigma_t: grid value -> majorant
    float maxDensity = 0;                // the density's bound over the region
    // The emission's luminance bound over the majorant grid's cells (null: none, or the
    // medium also emits Le x density, which it does not bound), and the emission samples it
    // asks for per object-space unit length per unit of it.
    const MajorantGrid* emissionBound = nullptr;
    float emissionRate = 0;
  };
  struct Coefficients {
    Rgb sigmaT, sigmaS, emission;
  };
  // The majorant along [a, b] of `ray` over the `active` regions: the regions' single
  // majorants added, except that the first region with a majorant grid gives its cells'
  // along the ray.
  MajorantWalk majorantWalk(const Ray& ray, float a, float b,
                            const std::vector<uint32_t>& active) const;
  // The same for one region, plus `constant`.
  MajorantWalk regionWalk(const Region& r, const Ray& ray, float a, float b, float constant) const;
  void finishRegion(Region* r, const Bounds3f& objectBounds);
  float density(const Region& r, Vec3f pWorld) const {
    return r.medium->homogeneous() ? r.medium->density->density(pWorld)
                                   : r.medium->density->density(r.objectFromWorld.point(pWorld));
  }
  // sigma_s at the world point p, per unit density, where the density is d (density(r, p),
  // which every caller also needs): the medium's, times its colour field there.
  Rgb scattering(const Region& r, Vec3f pWorld, float d) const {
    return r.medium->color
               ? r.medium->sigmaS * r.medium->color->color(r.objectFromWorld.point(pWorld), d)
               : r.medium->sigmaS;
  }
  Coefficients coefficients(const std::vector<uint32_t>& active, Vec3f p) const;
  Rgb emission(const std::vector<uint32_t>& active, Vec3f p) const;  // coefficients' emission
  // Transmittance through one region over world-space distance [0, length) from ray.at(t0).
  Rgb regionTransmittance(const Region& r, const Ray& ray, float t0, float t1, Sampler& sampler,
                          bool track) const;
  Rgb transmittance(const Ray& ray, float tMax, Sampler& sampler, bool track) const;
  // Delta tracking; emission gathered into `*emitted` when it is not null.
  MediumEvent deltaTrack(const Ray& ray, float tMax, Sampler& sampler, Rgb* emitted,
                         ChannelPath* path, const SegmentSamples* first) const;
  // At a scattering event at p: the scattering region's phase asymmetry into event->g.
  void pickScatterer(const std::vector<uint32_t>& active, Vec3f p, const Coefficients& c,
                     Sampler& sampler, MediumEvent* event) const;
  // Where a stretch's emission comes from: whether any active region emits, and the emission
  // samples' guide (samples per world unit length per unit of the emission bound, where the
  // one emitting region bounds its emission cell by cell; 0: one per stretch).
  struct EmissionGuide {
    bool emits = false;
    float rate = 0;
  };
  EmissionGuide emissionGuide(const std::vector<uint32_t>& active, Vec3f dUnit) const;
  // The emission integral over [from, to) along unit `dUnit` from `start` (a majorant cell's
  // entry; `bound`: its emission bound), each jittered sample at distance y times weight(y).
  template <class Weight>
  Rgb stretchEmission(const std::vector<uint32_t>& active, Vec3f start, Vec3f dUnit, float from,
                      float to, const EmissionGuide& guide, float bound,
                      const SegmentSamples* first, Sampler& sampler, Weight&& weight) const;
  // The same for coloured extinction: spectral MIS over a hero channel (volume.cpp).
  MediumEvent heroTrack(const Ray& ray, float tMax, Sampler& sampler, Rgb* emitted,
                        ChannelPath* path, const SegmentSamples* first) const;
  // Each channel's majorant over a stretch of majorantWalk(..., active) whose gridded region's
  // cell holds `cell` (the walk's majorant is their largest).
  Rgb channelMajorants(const std::vector<uint32_t>& active, float cell) const;
  // The source term at p (emission + single scattering towards -d), per unit length.
  Rgb source(const RenderScene& scene, const std::vector<uint32_t>& active, Vec3f p, Vec3f d,
             float time, const Coefficients& c, Sampler& sampler, RayCounters& counters) const;

  std::vector<Region> regions_;
  bool single_;                // single scattering (else emission and absorption only)
  bool track_;                 // tracking estimators (else marching)
  bool heroTracking_ = false;  // a medium with coloured extinction asks for heroTrack
  bool emits_ = false;         // some medium emits
  float step_;                 // the configured step; 0 = per region
};

}  // namespace glint
