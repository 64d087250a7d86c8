// glint — direct lighting: the one routine every integrator uses to take light from a light.
//
// Whitted (every light at every lit point), the path tracer (one light picked per vertex, at
// surfaces and in media), single scattering in media and instant radiosity (through Whitted)
// all do the same five steps; only what scatters the light and how the shadow ray's media are
// estimated differ, and those come in as two small functions:
//   1. a point or direction on the light (Light::sampleLi),
//   2. what the receiver makes of it: `scatter(wi, pdf)` returns f |cos| at a surface or the
//      phase function in a medium, and, when `pdf` is not null, the density with which the
//      receiver's own sampling would find wi (for multiple importance sampling),
//   3. a shadow ray to the light (when the light casts shadows and the caller wants shadows;
//      through glass, the caller's transmittance traces it),
//   4. the transmittance of the media along it (`transmittance(shadowRay)`),
//   5. the estimate L f / (pmf pdf), weighted by the power heuristic when `mis` is set and
//      the light is not a delta light.
// Templates rather than std::function: the routine sits in every integrator's inner loop.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>

#include "renderer/light.h"
#include "renderer/ray_counters.h"
#include "renderer/scene.h"

namespace glint {

// The power heuristic (beta = 2) weight of a sample drawn with density `f` against another
// strategy of density `g`: f^2 / (f^2 + g^2); 1 when f^2 overflows, 0 when both vanish.
inline float powerHeuristic(float f, float g) {
  const float f2 = f * f, g2 = g * g;
  if (std::isinf(f2)) return 1;
  if (!(f2 + g2 > 0) || !std::isfinite(g2)) return 0;
  return f2 / (f2 + g2);
}

// What the caller asks of one light sample besides the point: `pmf` is the probability with
// which the light was chosen (1 when every light is taken); `shadows` whether to trace shadow
// rays at all (Feature::Shadows: a scene where no light casts them traces none); `mis` whether
// the receiver's own sampling can find this light (then the estimate is MIS-weighted).
struct DirectLightOptions {
  float pmf = 1;
  bool shadows = true;
  bool mis = false;
  // `transmittance(shadowRay)` traces the shadow ray itself (Whitted's shadows through glass):
  // no any-hit query first, and it counts its own rays.
  bool transmittanceTraces = false;
};

// The light `light` sends to the receiver at `ctx` through `u`, scattered by `scatter` and
// attenuated by `transmittance` (see the file comment). Counts its shadow ray.
template <class ScatterFn, class TransmittanceFn>
Rgb sampleDirectLight(const RenderScene& scene, const LightSampleContext& ctx, const Light& light,
                      Vec2f u, const DirectLightOptions& options, ScatterFn&& scatter,
                      TransmittanceFn&& transmittance, RayCounters& counters) {
  const std::optional<LightSample> ls = light.sampleLi(ctx, u);
  if (!ls || !(ls->pdf > 0) || !std::isfinite(ls->pdf) || !(maxComponent(ls->L) > 0)) return {};
  const bool weighted = options.mis && !ls->delta;
  float scatterPdf = 0;
  Rgb f = scatter(ls->wi, weighted ? &scatterPdf : nullptr);
  if (!(maxComponent(f) > 0)) return {};
  if (options.shadows && light.castsShadows()) {
    const Ray shadow = shadowRay(ctx, *ls);
    if (!options.transmittanceTraces) {
      ++counters.shadow;
      if (scene.accel().anyHit(shadow)) return {};
    }
    f *= transmittance(shadow);
    if (!(maxComponent(f) > 0)) return {};
  }
  const float lightPdf = options.pmf * ls->pdf;
  const float w = weighted ? powerHeuristic(lightPdf, scatterPdf) : 1.0f;
  return f * ls->L * (w / lightPdf);
}

// No media along the shadow ray.
inline Rgb noMedia(const Ray&) { return {1, 1, 1}; }

}  // namespace glint
