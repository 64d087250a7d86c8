// glint — unidirectional path tracing: the reference integrator the others are checked against.
//
// Estimates the radiance arriving at the camera, L = Le + ∫ f Li |cos|, by following one path
// per camera sample. At every vertex it adds light two ways and weights them against each
// other with multiple importance sampling (Veach's power heuristic, beta = 2):
//   next-event estimation — one light picked by scene.lightSampler(), one point or direction on
//     it (Light::sampleLi) and a shadow ray; weighted by pmf x pdfLi against the BSDF's pdf
//     (delta lights, and area lights that are not geometry — the sidecar's quad, disk and
//     sphere lights — weight 1: no BSDF sample can find them);
//   BSDF sampling — the path's next direction (Bsdf::sample); when it finds an emitting
//     surface that is a light (RenderScene::areaLight) or escapes into an environment light,
//     that emission is weighted by the BSDF's pdf against the previous vertex's
//     pmf x pdfLi. Camera rays and delta (mirror, glass) bounces take emission with weight 1,
//     as do emitting surfaces that are not lights and the plain background (NEE never
//     samples them).
// Paths end after `maxDepth` bounces (0: only what the camera sees emitting; the last bounce
// is not traced when nothing in the scene can be found by it) or by Russian roulette from
// `rrDepth` bounces on (renderer/roulette.h: survival probability = the square root of the
// largest throughput component, undoing radiance's 1/eta^2 at refractions, clamped to
// [0.05, 1]).
//
// Shared with Whitted: unlit (eyelight) materials return colour x |cos| and end the path;
// partly transparent surfaces (opacity < 1) let the path pass straight through with
// probability 1 - opacity (a pass counts as a bounce, as in Whitted); AOVs are the first
// hit's; a hit is shaded through ShadedHit (renderer/shading.h).
//
// Every vertex draws the same kVertexDimensions sampler dimensions in the same order
// (pass-through, light choice, light point, BSDF direction, BSDF lobe, roulette), whichever
// branch it takes, so bounce k always reads the same dimensions: stratification carries over
// and results depend only on (pixel, sample, seed).
//
// Participating media (only when the scene has them: the constructor keeps `media_`, and
// LiFromHit then follows the camera sample's path with volumetricPath instead of surfacePath;
// a scene without media runs surfacePath, with no volume code in it). Every segment of the path
// (camera ray, bounce, up to the hit or to where it leaves the media) is crossed by delta
// tracking against the density majorants (MediaScene::sampleScatteringAndEmission):
//   emission — the track-length estimator: up to the segment's collision, the path adds
//     beta x tracking weight x the emission integrated over each stretch between tentative
//     collisions (unbiased for any majorant), so glowing media are found by the camera and by
//     every bounce, never by next-event estimation; the camera ray instead gathers its whole
//     segment under a ratio-tracked transmittance (SegmentSamples::wholeSegmentEmission,
//     integrator.whole_segment_emission);
//   passing — beta takes the tracking weight (an unbiased estimate of the transmittance; 1 for
//     grey media), and the path goes on at the surface or the environment as without media:
//     emission found there keeps its MIS weight, now times that transmittance estimate;
//   scattering — a medium vertex (it counts as a bounce against `maxDepth`, so max_depth 1 is
//     single scattering of direct light): next-event estimation from the medium point
//     (LightSampleContext::inMedium) with the Henyey–Greenstein phase function in place of
//     f |cos|, then a phase-sampled direction (weight 1); the two are MIS-weighted against
//     each other as at surfaces (power heuristic on the directional pdfs, which is unbiased
//     because both strategies estimate the transmittance on their own: ratio tracking on the
//     shadow ray, delta tracking on the sampled ray). Roulette as at surfaces.
// Shadow rays, from surfaces and from medium points, carry the transmittance of the media
// they cross (MediaScene::trackedTransmittance: ratio tracking whatever volume_estimator says,
// so the path tracer stays unbiased; homogeneous media exactly). IntegratorSettings::volume:
// "emission" makes media absorb and emit only (a scattering event ends the path, as Whitted's
// emission mode); "single" and "multiple" scatter fully, bounded only by maxDepth and
// roulette — "single" is the settings' default, and the path tracer is the full answer;
// single scattering is max_depth 1 (or the Whitted integrator).
//
// Tracking needs a variable count of random numbers per segment, which would shift the
// sampler dimensions of every later vertex. So the media instantiation draws one 2D sample at
// the start of the path (after the integrator's first dimension) and hashes it into the key of
// a private Sampler whose successive dimensions at sample 0 serve as a hashed random stream
// (Sampler is a pure function of (key, dimension)): tracking decisions and ratio-tracking
// shadow rays read that stream. Only a fixed few numbers per segment come from the path's
// own dimensions, stratified over the pixel's samples (SegmentSamples, volume.h: the first
// free flight, the first event, the emission offset), as Cycles' scatter distance does.
// Vertices still read fixed dimensions, and results depend only on (pixel, sample, seed).
//
// Not yet: path regularisation, and ray cones after diffuse bounces (texture footprints keep
// the camera cone's spread).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "renderer/integrator.h"

namespace glint {

class PathIntegrator final : public Integrator {
 public:
  // Dimensions each path vertex reads from the sampler.
  static constexpr uint32_t kVertexDimensions = 8;

  PathIntegrator(const RenderScene& scene, const IntegratorSettings& settings);
  Rgb LiFromHit(const Ray& ray, const Hit* hit, Sampler& sampler, RayCounters& counters,
                PathAovs& aovs) const override;

 private:
  struct Path;  // what a path carries from vertex to vertex (path.cpp)

  // The path of a camera sample in a scene without media, vertex by vertex: what escapes, or
  // the surface it finds. Records the AOVs at the first hit.
  Rgb surfacePath(const Ray& ray, const Hit* hit, Sampler& sampler, RayCounters& counters,
                  PathAovs& aovs) const;
  // The same in a scene with media: every segment first crosses them (their emission, and
  // pass or scatter), then escapes or finds its surface as in surfacePath.
  Rgb volumetricPath(const Ray& ray, const Hit* hit, Sampler& sampler, RayCounters& counters,
                     PathAovs& aovs) const;

  // One surface vertex of `path`, `depth` bounces from the camera: the surface `h` (of `hit`,
  // found by `*ray`) adds what it emits and the light sampled there, then picks the next
  // direction. Draws the vertex's kVertexDimensions from `sampler`. Returns false where the
  // path ends; else `*ray` is the next segment's ray, not yet traced. `shadowMedia(shadowRay)`
  // is the transmittance of the media along a shadow ray (noMedia without media).
  // Inlined into both paths, as the one loop it was part of.
  template <class ShadowMedia>
  [[gnu::always_inline]] inline bool surfaceVertex(Path& path, ShadedHit& h, const Hit& hit,
                                                   int depth, Sampler& sampler,
                                                   ShadowMedia&& shadowMedia, RayCounters& counters,
                                                   Ray* ray) const;
  // One medium vertex: `event` scattered `*ray` in a medium. Light sampled there, then a
  // phase-sampled direction; as surfaceVertex otherwise. `tracker`: the media's own numbers.
  [[gnu::always_inline]] inline bool mediumVertex(Path& path, const MediumEvent& event, int depth,
                                                  Sampler& sampler, Sampler& tracker,
                                                  RayCounters& counters, Ray* ray) const;
  // Adds what a ray that leaves the scene along `d` brings: the environment lights,
  // MIS-weighted after non-delta bounces, or the background.
  [[gnu::always_inline]] inline void addEscaped(Path& path, Vec3f d) const;
  // The density with which next-event estimation from `prev` would have found light `index`
  // along `wi` at `at`: the other strategy of the MIS weight on emission a BSDF sample found.
  // `prev` by value: the Path it comes from never has its address taken, so the compiler keeps
  // it in registers (callgrind: 0.3% of a Cornell box's instructions).
  float lightPdf(LightSampleContext prev, uint32_t index, const Light& light, Vec3f wi,
                 const LightHit& at) const {
    return scene_.lightSampler()->pmf(prev, index) * light.pdfLi(prev, wi, at);
  }

  // One light sampled for the lit point `si` (next-event estimation), MIS-weighted against
  // the BSDF; `uLight` picks the light, `uPoint` the point on it. `leftLights`: the vertex
  // leaves the lights that allow it to BSDF sampling (nothing drawn from them). Shadow rays
  // carry `shadowMedia(shadowRay)`.
  template <class ShadowMedia>
  Rgb sampleLight(const SurfaceInteraction& si, const Bsdf& bsdf, bool leftLights, float time,
                  float uLight, Vec2f uPoint, ShadowMedia&& shadowMedia,
                  RayCounters& counters) const;
  // One light sampled for the medium point of `ctx` seen along unit direction `d` (towards the
  // point), Henyey–Greenstein `g`, MIS-weighted against phase sampling; shadow rays carry the
  // transmittance (`tracker`'s numbers).
  Rgb sampleLightInMedium(const LightSampleContext& ctx, Vec3f d, float g, float uLight,
                          Vec2f uPoint, Sampler& tracker, RayCounters& counters) const;

  int maxDepth_, rrDepth_;
  bool wholeSegmentEmission_;  // IntegratorSettings::wholeSegmentEmission
  bool shadows_;               // some light casts shadows (Feature::Shadows)
  bool lights_;                // there is a light to sample (else no next-event estimation at all)
  const MediaScene* media_ = nullptr;  // null without media: surfacePath, not volumetricPath
  bool mediaScatter_ = true;           // media scatter (volume != "emission")
  // Can a BSDF-sampled ray find light at all (an emitting surface, an environment, a
  // non-black background, media)? If not, the last bounce is not traced.
  bool emissionFindable_ = true;
  // The environment lights with their indices in scene.lights() (the light sampler's pmf
  // needs the index).
  std::vector<std::pair<const Light*, uint32_t>> infinite_;
  // Per light in scene.lights(): can a BSDF sample find it (an environment, or an area light
  // some instance's emission maps to)? Next-event estimation weights only those by MIS; the
  // others are its only way in and keep weight 1.
  std::vector<bool> bsdfFindable_;
  // Per light in scene.lights(): left to BSDF sampling at the surfaces whose BSDF samples it
  // well (Light::leftToBsdfSampling, leavesLights in path.cpp): next-event estimation there
  // draws nothing from it, and a BSDF sample from there that finds it has weight 1. Media
  // points still sample it.
  std::vector<bool> bsdfOnlyAtSurfaces_;
  bool someLeftToBsdf_ = false;  // any of them (else no vertex asks its BSDF)
};

}  // namespace glint
