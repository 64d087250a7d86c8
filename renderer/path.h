// glint — unidirectional path tracing: the reference integrator the others are checked against.
//
// Estimates the radiance arriving at the camera, L = Le + ∫ f Li |cos|, by following one path
// per camera sample. At every vertex it adds light two ways and weights them against each
// other with multiple importance sampling (Veach's power heuristic, beta = 2):
//   next-event estimation — one light picked by scene.lightSampler, one point or direction on
//     it (Light::sampleLi) and a shadow ray; weighted by pmf x pdfLi against the BSDF's pdf
//     (delta lights: weight 1, no BSDF sample can find them);
//   BSDF sampling — the path's next direction (Material::sample); when it finds an emitting
//     surface that is a light (RenderScene::areaLight) or escapes into an environment light,
//     that emission is weighted by the BSDF's pdf against the previous vertex's
//     pmf x pdfLi. Camera rays and delta (mirror, glass) bounces take emission with weight 1,
//     as do emitting surfaces that are not lights and the plain background (NEE never
//     samples them).
// Paths end after `maxDepth` bounces (0: only what the camera sees emitting) or by Russian
// roulette from `rrDepth` bounces on: survival probability = the largest throughput component
// (undoing radiance's 1/eta^2 at refractions), clamped to [0.05, 1], so bright paths are
// never cut and dim ones not boosted more than 20x.
//
// Shared with Whitted: unlit (eyelight) materials return colour x |cos| and end the path;
// partly transparent surfaces (opacity < 1) let the path pass straight through with
// probability 1 - opacity (a pass counts as a bounce, as in Whitted); AOVs are the first
// hit's; shading goes through Integrator::shadingPoint.
//
// Every vertex draws the same kVertexDimensions sampler dimensions in the same order
// (pass-through, light choice, light point, BSDF direction, BSDF lobe, roulette), whichever
// branch it takes, so bounce k always reads the same dimensions: stratification carries over
// and results depend only on (pixel, sample, seed).
//
// Not yet: participating media (added by the volume change), path regularisation, and ray
// cones after diffuse bounces (texture footprints keep the camera cone's spread).
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
  // One light sampled for the lit point `si` (next-event estimation), MIS-weighted against
  // the BSDF; `uLight` picks the light, `uPoint` the point on it.
  Rgb sampleLight(const SurfaceInteraction& si, const Material& material, float time, float uLight,
                  Vec2f uPoint, RayCounters& counters) const;

  int maxDepth_, rrDepth_;
  bool shadows_;  // some light casts shadows (Feature::Shadows)
  bool lights_;   // there is a light to sample (else no next-event estimation at all)
  RayCone cameraCone_;
  // The environment lights with their indices in scene.lights (the light sampler's pmf
  // needs the index).
  std::vector<std::pair<const Light*, uint32_t>> infinite_;
};

// The power heuristic (beta = 2) weight of a sample drawn with density `f` against another
// strategy of density `g`: f^2 / (f^2 + g^2); 1 when f^2 overflows, 0 when both vanish.
float powerHeuristic(float f, float g);

}  // namespace glint
