// glint — Whitted-style ray tracing: direct light from every light with hard shadows, the
// eyelight shortcut, emission, and recursion along the delta lobes of mirrors and glass (both
// the reflected and the refracted ray, each weighted by its Fresnel share) and through
// transparent surfaces, up to `maxDepth` bounces. Branches too faint for the camera to see
// (weight below `minWeight`, 1/255 by default as POV-Ray's adc_bailout) go on by Russian
// roulette instead of to the depth limit: unbiased, and glass no longer spawns a full binary
// tree of rays (specularBounces in whitted.cpp).
//
// Shadow rays stop at the first opaque surface. Through glass and glTF transmission they go on
// straight, unrefracted, keeping each surface's Fresnel transmittance and tint, two crossings
// of one object combined as a pane's multiple internal reflections are, (1 - R1)(1 - R2) /
// (1 - R1 R2): POV-Ray's filtered shadows, an approximation (no caustic, no refraction of the
// shadow's shape) that beats the black shadow of an opaque stand-in; `glassShadows` false
// (sidecar integrator.glass_shadows) restores that. Light reaches a point behind glass
// correctly only along paths the path tracer samples.
//
// Participating media (when the scene has them, Feature::Volumes): every camera and secondary
// ray's segment up to its hit (or to where it leaves the media) adds what the media emit and,
// in the "single" volume mode, scatter from the lights (renderer/volume.h), and attenuates
// what lies behind; shadow rays are attenuated by the media they cross. The "multiple" mode
// is single scattering here.
//
// Light beyond that (instant radiosity's VPLs) comes in through an IndirectLight: the
// recursion asks it at every diffuse or glossy point. Plain Whitted has none.
//
// The shape, for a ray and its hit: radiance() takes the media in front (if any), then the
// background or the surface, which shade() shades by its material's kind of hit (HitKind,
// decided once per material): each kind is its own instantiation, so that a hit pays only for
// what its material does (benchmarks/features_bench, pipeline_bench).
#pragma once

#include <cstdint>
#include <vector>

#include "renderer/integrator.h"

namespace glint {

// Light beyond the lights' own that Whitted's recursion adds at every diffuse or glossy point:
// instant radiosity's VPLs (renderer/instant_radiosity.h).
class IndirectLight {
 public:
  // The light arriving at the lit point `si`, reflected by `bsdf` towards si.wo. Draws a fixed
  // number of sampler dimensions; counts its shadow rays.
  virtual Rgb gather(const SurfaceInteraction& si, const Bsdf& bsdf, float time, Sampler& sampler,
                     RayCounters& counters) const = 0;

 protected:
  ~IndirectLight() = default;
};

class WhittedIntegrator final : public Integrator {
 public:
  // `minWeight`: see IntegratorSettings::minWeight (0 here: every branch followed).
  // `indirect`: the light added at diffuse and glossy points (null: none); it must outlive the
  // integrator.
  WhittedIntegrator(const RenderScene& scene, int maxDepth, bool glassShadows = true,
                    float minWeight = 0, const IndirectLight* indirect = nullptr);
  Rgb LiFromHit(const Ray& ray, const Hit* hit, Sampler& sampler, RayCounters& counters,
                PathAovs& aovs) const override;

 private:
  // What a material's hits do, decided once per material (kinds_).
  enum class HitKind : uint8_t {
    // Lit, opaque, neither emitting nor absorbing inside, no specular lobe, and no indirect
    // light: direct light and nothing else.
    Plain,
    // Unlit (eyelight), opaque, absorbing nothing: its colour and nothing else.
    Unlit,
    // Anything else: pass-through, emission, indirect light, mirror and glass recursion.
    General,
  };

  // Radiance along `ray` to its hit `hit` (null: escaped), `depth` bounces from the camera,
  // which sees it with weight `weight` (1 for camera rays; see specularBounces): what the media
  // in between add and let through, then the background or the surface. `aovs` is the camera
  // ray's (null for deeper rays). Inlined into its two callers, LiFromHit and trace.
  [[gnu::always_inline]] inline Rgb radiance(const Ray& ray, const Hit* hit, const RayCone& cone,
                                             int depth, float weight, Sampler& sampler,
                                             RayCounters& counters, PathAovs* aovs) const;
  // radiance() in a scene with media: the media in front, then surface(). Out of line, so that
  // a scene without media pays for them no more than a test.
  Rgb throughMedia(const Ray& ray, const Hit* hit, const RayCone& cone, int depth, float weight,
                   Sampler& sampler, RayCounters& counters, PathAovs* aovs) const;
  // radiance() behind the media: the background, or the surface shaded as its material's
  // kind of hit asks (kinds_).
  [[gnu::always_inline]] inline Rgb surface(const Ray& ray, const Hit* hit, const RayCone& cone,
                                            int depth, float weight, Sampler& sampler,
                                            RayCounters& counters, PathAovs* aovs) const;
  // Traces a secondary ray and returns its radiance().
  Rgb trace(const Ray& ray, const RayCone& cone, int depth, float weight, Sampler& sampler,
            RayCounters& counters) const;
  // The radiance the surface at `hit` (material `materialIndex`, of kind kKind) sends back
  // along `ray`; the branches kKind rules out are compiled out.
  template <HitKind kKind>
  Rgb shade(const Ray& ray, const Hit& hit, uint32_t materialIndex, const RayCone& cone, int depth,
            float weight, Sampler& sampler, RayCounters& counters, PathAovs* aovs) const;
  // Direct light at a lit surface point: sum over all lights, shadow rays when enabled.
  // kPlainShadows: shadow rays neither cross glass nor media (`plainShadows_`). Inlined into
  // shade: a call per hit was a visible share of a plain scene's time.
  template <bool kPlainShadows>
  [[gnu::always_inline]] inline Rgb directLight(const SurfaceInteraction& si, const Bsdf& bsdf,
                                                float time, Sampler& sampler,
                                                RayCounters& counters) const;
  // Mirror and glass at `si`: for each specular lobe (reflection, transmission) in `flags`
  // (the material's, so that every hit on it draws the same dimensions), one sample of the
  // BSDF's delta part, its weight times the radiance traced along the spawned ray (`cone`,
  // `depth`: the spawned rays'). Glossy and diffuse light is directLight's. Draws four sampler
  // dimensions per lobe. `pathWeight`: what the camera sees of this point (see the file
  // comment's faint branches). Inlined into shade, as directLight.
  [[gnu::always_inline]] inline Rgb specularBounces(const Bsdf& bsdf, const SurfaceInteraction& si,
                                                    uint32_t flags, float time, const RayCone& cone,
                                                    int depth, float pathWeight, Sampler& sampler,
                                                    RayCounters& counters) const;
  // What reaches the end of `shadow` through the glass on its way (zero behind anything
  // opaque): the shadow ray followed from surface to surface (see the file comment).
  Rgb throughGlass(const Ray& shadow, RayCounters& counters) const;

  int maxDepth_;
  bool shadows_;                   // some light casts shadows (Feature::Shadows)
  const MediaScene* media_;        // null without media: rays take the media-free path
  bool glassShadows_;              // shadow rays cross glass (the scene has some, and it is asked)
  float minWeight_;                // faint specular branches go by Russian roulette below this
  const IndirectLight* indirect_;  // null: none
  // Per material: the kind of its hits (HitKind). What a material does not call for its hits
  // do not pay for, not even a test (benchmarks/features_bench).
  std::vector<HitKind> kinds_;
  bool plainShadows_;  // shadow rays cross no glass (glassShadows_) and no media
};

}  // namespace glint
