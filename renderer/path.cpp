// glint — the path tracer.
#include "renderer/path.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace glint {

float powerHeuristic(float f, float g) {
  const float f2 = f * f, g2 = g * g;
  if (std::isinf(f2)) return 1;
  if (!(f2 + g2 > 0) || !std::isfinite(g2)) return 0;
  return f2 / (f2 + g2);
}

PathIntegrator::PathIntegrator(const RenderScene& scene, const IntegratorSettings& settings)
    : Integrator(scene), maxDepth_(settings.maxDepth), rrDepth_(settings.rrDepth) {
  shadows_ = scene.features.has(Feature::Shadows);
  lights_ = !scene.lights.empty() && scene.lightSampler;
  cameraCone_ = scene.camera.pixelCone();
  for (const Light* l : scene.infiniteLights)
    for (size_t i = 0; i < scene.lights.size(); ++i)
      if (scene.lights[i].get() == l) infinite_.push_back({l, uint32_t(i)});
}

// ---------------------------------------------------------------------------------------------
// The path
// ---------------------------------------------------------------------------------------------

Rgb PathIntegrator::LiFromHit(const Ray& cameraRay, const Hit* cameraHit, Sampler& sampler,
                              RayCounters& counters, PathAovs& aovs) const {
  Rgb L, beta{1, 1, 1};
  float etaScale = 1;  // the 1/eta^2 refractions put into beta, undone for roulette
  // The previous scattering vertex, for MIS on emission the BSDF sample finds: whether it was
  // a delta bounce (or the camera), its BSDF pdf, and its light-sampling context.
  bool specularBounce = true;
  float bsdfPdf = 0;
  LightSampleContext prev;

  Ray ray = cameraRay;
  Hit hitStorage;
  const Hit* hit = cameraHit;
  RayCone cone = cameraCone_;
  for (int depth = 0;; ++depth) {
    // --- Escaped: the environment (MIS-weighted after non-delta bounces) or the background.
    if (!hit) {
      const Vec3f d = normalize(ray.d);
      if (specularBounce || infinite_.empty()) {
        L += beta * scene_.escaped(d);
      } else {
        for (const auto& [light, index] : infinite_) {
          const Rgb Le = light->Le(d);
          if (maxComponent(Le) <= 0) continue;
          const float lightPdf =
              scene_.lightSampler->pmf(prev, index) * light->pdfLi(prev, d, LightHit{});
          L += beta * Le * powerHeuristic(bsdfPdf, lightPdf);
        }
      }
      break;
    }

    const uint32_t materialIndex = scene_.materialIndex(*hit);
    const Material& material = *scene_.materials[materialIndex];
    const MaterialShading& shading = shading_[materialIndex];
    std::optional<Transform> movingFrame;  // a moving object's frame: lives as long as `si`
    SurfaceInteraction si = shadingPoint(ray, *hit, cone, materialIndex, &movingFrame);
    const float distance = hit->t * length(ray.d);
    if (depth == 0) {
      aovs.hit = true;
      if (aovs.wanted) {
        aovs.albedo = material.albedo(si);
        aovs.normal = si.ns;
        aovs.depth = distance;
      }
    }
    cone = RayCone{cone.widthAt(distance), cone.spread};

    // The vertex's sampler dimensions, all drawn whatever happens below (kVertexDimensions).
    const float uPass = sampler.get1D();
    const float uLight = sampler.get1D();
    const Vec2f uLightPoint = sampler.get2D();
    const Vec2f uBsdf = sampler.get2D();
    const float uLobe = sampler.get1D();
    const float uRoulette = sampler.get1D();

    // --- Partly transparent: pass straight through with probability 1 - opacity (beta
    // unchanged: the probability and the weight cancel). The previous vertex stays the MIS
    // reference, since the direction does not change.
    if (shading.transparent && uPass >= material.opacity(si)) {
      if (depth >= maxDepth_) break;
      ray = si.spawnRay(ray.d, ray.time);
      ++counters.secondary;
      hit = scene_.accel->closestHit(ray, &hitStorage) ? &hitStorage : nullptr;
      continue;
    }

    if (shading.unlit) {
      L += beta * material.albedo(si) * std::abs(dot(si.ns, si.wo));
      break;
    }

    // --- Emission found by the camera or a BSDF sample.
    if (material.traits().emits) {
      const Rgb Le = material.emitted(si);
      if (maxComponent(Le) > 0) {
        uint32_t index = 0;
        const Light* area = scene_.areaLight(*hit, &index);
        if (specularBounce || !area) {
          L += beta * Le;
        } else {
          const float lightPdf = scene_.lightSampler->pmf(prev, index) *
                                 area->pdfLi(prev, -si.wo, LightHit{si.p, si.ng});
          L += beta * Le * powerHeuristic(bsdfPdf, lightPdf);
        }
      }
    }
    if (depth >= maxDepth_) break;

    // --- Next-event estimation, at surfaces with a non-delta lobe.
    if (lights_ && (shading.flags & (kBsdfDiffuse | kBsdfGlossy)))
      L += beta * sampleLight(si, material, ray.time, uLight, uLightPoint, counters);

    // --- The next direction.
    std::optional<BsdfSample> s = material.sample(si, uBsdf, uLobe);
    if (!s || !(s->pdf > 0) || !std::isfinite(s->pdf)) break;
    const Rgb weight = s->weight(si.ns);
    if (!(maxComponent(weight) > 0) || !isFinite(weight)) break;
    beta *= weight;
    specularBounce = (s->flags & kBsdfSpecular) != 0;
    bsdfPdf = s->pdf;
    prev = LightSampleContext(si, ray.time);
    if (s->flags & kBsdfTransmission) etaScale *= s->eta * s->eta;

    // --- Russian roulette: survive with the throughput's largest component, clamped.
    if (depth + 1 >= rrDepth_) {
      const float survive = std::clamp(maxComponent(beta * etaScale), 0.05f, 1.0f);
      if (survive < 1) {
        if (uRoulette >= survive) break;
        beta *= 1 / survive;
      }
    }

    ray = si.spawnRay(s->wi, ray.time);
    ++counters.secondary;
    hit = scene_.accel->closestHit(ray, &hitStorage) ? &hitStorage : nullptr;
  }
  return L;
}

// ---------------------------------------------------------------------------------------------
// Next-event estimation
// ---------------------------------------------------------------------------------------------

Rgb PathIntegrator::sampleLight(const SurfaceInteraction& si, const Material& material, float time,
                                float uLight, Vec2f uPoint, RayCounters& counters) const {
  const LightSampleContext ctx(si, time);
  const std::optional<SampledLight> picked = scene_.lightSampler->sample(ctx, uLight);
  if (!picked || !(picked->p > 0)) return {};
  const Light& light = *scene_.lights[picked->index];
  const std::optional<LightSample> ls = light.sampleLi(ctx, uPoint);
  if (!ls || !(ls->pdf > 0) || !std::isfinite(ls->pdf) || !(maxComponent(ls->L) > 0)) return {};
  // Light must arrive on the side of the geometric surface the BSDF says it can; eval checks
  // the hemispheres (reflection and transmission alike).
  const Rgb f = material.eval(si, ls->wi);
  if (!(maxComponent(f) > 0)) return {};
  if (shadows_ && light.castsShadows()) {
    ++counters.shadow;
    if (scene_.accel->anyHit(shadowRay(ctx, *ls))) return {};
  }
  const float lightPdf = picked->p * ls->pdf;
  const float w = ls->delta ? 1.0f : powerHeuristic(lightPdf, material.pdf(si, ls->wi));
  return f * ls->L * (std::abs(dot(si.ns, ls->wi)) * w / lightPdf);
}

}  // namespace glint
