// glint — Whitted-style ray tracing: direct light from every light with hard shadows, the
// eyelight shortcut, emission, and recursion along the delta lobes of mirrors and glass (both
// the reflected and the refracted ray, each weighted by its Fresnel share) and through
// transparent surfaces, up to `maxDepth` bounces. Branches too faint for the camera to see
// (weight below `minWeight`, 1/255 by default as POV-Ray's adc_bailout) go on by Russian
// roulette instead of to the depth limit: unbiased, and glass no longer spawns a full binary
// tree of rays (Integrator::specularBounces).
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
#pragma once

#include <cstdint>
#include <vector>

#include "renderer/integrator.h"

namespace glint {

class WhittedIntegrator : public Integrator {
 public:
  // `minWeight`: see IntegratorSettings::minWeight (0 here: every branch followed).
  // `indirect`: indirectLight() adds light (a subclass's; plain Whitted has none).
  WhittedIntegrator(const RenderScene& scene, int maxDepth, bool glassShadows = true,
                    float minWeight = 0, bool indirect = false);
  Rgb LiFromHit(const Ray& ray, const Hit* hit, Sampler& sampler, RayCounters& counters,
                PathAovs& aovs) const override;

 protected:
  // Light beyond the direct at a diffuse or glossy point (instant radiosity's VPLs), asked
  // only when `indirect_` is set (the constructor's `indirect`). Plain Whitted has none.
  virtual Rgb indirectLight(const SurfaceInteraction& si, const Bsdf& bsdf, float time,
                            Sampler& sampler, RayCounters& counters) const {
    (void)si, (void)bsdf, (void)time, (void)sampler, (void)counters;
    return {};
  }
  // The scene's media when it has them (Feature::Volumes), else null.
  const MediaScene* media() const { return media_; }
  const bool indirect_;
  int maxDepth_;
  bool shadows_;

 private:
  // Radiance along `ray`, which hit `hit` (null: escaped), `depth` bounces from the camera,
  // which sees it with weight `weight` (1 for camera rays; see specularBounces). `aovs` is the
  // camera ray's (null for deeper rays).
  Rgb shade(const Ray& ray, const Hit* hit, const RayCone& cone, int depth, float weight,
            Sampler& sampler, RayCounters& counters, PathAovs* aovs) const;
  // shade() for a hit on material `materialIndex`. kPlain: the material is `plain_` (see
  // there), and the branches for what it does not do are compiled out.
  template <bool kPlain>
  Rgb shadeAt(const Ray& ray, const Hit& hit, uint32_t materialIndex, const RayCone& cone,
              int depth, float weight, Sampler& sampler, RayCounters& counters,
              PathAovs* aovs) const;
  // What shade() returns for a camera ray's hit on an opaque unlit (eyelight) surface that
  // absorbs nothing: its colour, and the AOVs. Kept apart so that the cheapest scene there is
  // (pipeline_bench) pays none of shade()'s set-up for the other cases.
  Rgb shadeUnlit(const Ray& ray, const Hit& hit, uint32_t materialIndex, const RayCone& cone,
                 PathAovs& aovs) const;
  // Traces a secondary ray and shades what it finds.
  Rgb trace(const Ray& ray, const RayCone& cone, int depth, float weight, Sampler& sampler,
            RayCounters& counters) const;
  // The radiance `surface` (found at `hit`, null: escaped) seen through the media along `ray`.
  Rgb throughMedia(const Ray& ray, const Hit* hit, const RayCone& cone, int depth, float weight,
                   Sampler& sampler, RayCounters& counters, PathAovs* aovs) const;
  // Direct light at a lit surface point: sum over all lights, shadow rays when enabled.
  // kPlainShadows: shadow rays neither cross glass nor media (`plainShadows_`). Inlined into
  // shadeAt: a call per hit was a visible share of a plain scene's time.
  template <bool kPlainShadows>
  [[gnu::always_inline]] inline Rgb directLight(const SurfaceInteraction& si, const Bsdf& bsdf,
                                                float time, Sampler& sampler,
                                                RayCounters& counters) const;
  // What reaches the end of `shadow` through the glass on its way (zero behind anything
  // opaque): the shadow ray followed from surface to surface (see the file comment).
  Rgb throughGlass(const Ray& shadow, RayCounters& counters) const;

  const MediaScene* media_;  // null without media: rays take the media-free path
  bool glassShadows_;        // shadow rays cross glass (the scene has some, and it is asked)
  float minWeight_;          // faint specular branches go by Russian roulette below this
  // Per material: its hits take shadeAt<true>, the plain Whitted of an opaque, lit surface
  // that neither emits, absorbs inside nor bounces specularly, when there is no indirect
  // light: direct light and nothing else. What a material does not call for its hits do not
  // pay for, not even a test (benchmarks/features_bench).
  std::vector<uint8_t> plain_;
  bool plainShadows_;  // shadow rays cross no glass (glassShadows_) and no media
};

}  // namespace glint
