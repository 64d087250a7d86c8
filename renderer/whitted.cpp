// glint — the Whitted integrator.
#include "renderer/whitted.h"

#include <optional>

namespace glint {

WhittedIntegrator::WhittedIntegrator(const RenderScene& scene, int maxDepth)
    : Integrator(scene), maxDepth_(maxDepth) {
  shadows_ = scene.features.has(Feature::Shadows);
  media_ = scene.features.has(Feature::Volumes) ? scene.media.get() : nullptr;
  cameraCone_ = scene.camera.pixelCone();
}

Rgb WhittedIntegrator::LiFromHit(const Ray& ray, const Hit* hit, Sampler& sampler,
                                 RayCounters& counters, PathAovs& aovs) const {
  if (media_) return throughMedia(ray, hit, cameraCone_, 0, sampler, counters, &aovs);
  return shade(ray, hit, cameraCone_, 0, sampler, counters, &aovs);
}

Rgb WhittedIntegrator::trace(const Ray& ray, const RayCone& cone, int depth, Sampler& sampler,
                             RayCounters& counters) const {
  ++counters.secondary;
  Hit hit;
  bool found = scene_.accel->closestHit(ray, &hit);
  if (media_)
    return throughMedia(ray, found ? &hit : nullptr, cone, depth, sampler, counters, nullptr);
  return shade(ray, found ? &hit : nullptr, cone, depth, sampler, counters, nullptr);
}

Rgb WhittedIntegrator::shade(const Ray& ray, const Hit* found, const RayCone& cone, int depth,
                             Sampler& sampler, RayCounters& counters, PathAovs* aovs) const {
  if (!found) return scene_.escaped(normalize(ray.d));
  const Hit& hit = *found;
  const uint32_t materialIndex = scene_.materialIndex(hit);
  const Material& material = *scene_.materials[materialIndex];
  const MaterialShading& shading = shading_[materialIndex];
  std::optional<Transform> movingFrame;  // a moving object's frame: lives as long as `si`
  SurfaceInteraction si = shadingPoint(ray, hit, cone, materialIndex, &movingFrame);
  if (aovs) aovs->record(material, si, hit.t * length(ray.d));
  // The cone at the hit, carried on by every secondary ray from here (only they need it).
  auto next = [&] { return RayCone{cone.widthAt(hit.t * length(ray.d)), cone.spread}; };

  // Partly transparent surfaces: the rest of the light comes straight through.
  const float opacity = shading.transparent ? material.opacity(si) : 1.0f;
  Rgb behind;
  if (opacity < 1) {
    if (depth < maxDepth_)
      behind = trace(si.spawnRay(ray.d, ray.time), next(), depth + 1, sampler, counters);
    if (opacity <= 0) return behind;
  }

  Rgb L;
  if (shading.unlit) {
    L = material.albedo(si) * std::abs(dot(si.ns, si.wo));
  } else {
    if (shading.emits) L = material.emitted(si);
    L += directLight(si, material, ray.time, sampler, counters);
    if (indirect_ && (shading.flags & (kBsdfDiffuse | kBsdfGlossy)))
      L += indirectLight(si, material, ray.time, sampler, counters);
  }
  // Mirror and glass: follow the reflected and the refracted ray, each with its own weight.
  if ((shading.flags & kBsdfSpecular) && depth < maxDepth_)
    L += specularBounces(material, si, shading.flags, ray.time, sampler, [&](const Ray& r) {
      return trace(r, next(), depth + 1, sampler, counters);
    });
  return opacity < 1 ? L * opacity + behind * (1 - opacity) : L;
}

Rgb WhittedIntegrator::throughMedia(const Ray& ray, const Hit* hit, const RayCone& cone,
                                    int depth, Sampler& sampler, RayCounters& counters,
                                    PathAovs* aovs) const {
  const VolumeSegment seg =
      media_->integrate(scene_, ray, hit ? hit->t : kInfinity, sampler, counters);
  // Behind an opaque medium the surface cannot be seen: no need to shade it (AOVs aside).
  if (maxComponent(seg.T) <= 0 && !aovs) return seg.L;
  return seg.T * shade(ray, hit, cone, depth, sampler, counters, aovs) + seg.L;
}

Rgb WhittedIntegrator::directLight(const SurfaceInteraction& si, const Material& material,
                                   float time, Sampler& sampler, RayCounters& counters) const {
  Rgb L;
  const LightSampleContext ctx(si, time);
  for (const auto& light : scene_.lights) {
    Vec2f u = light->isDelta() ? Vec2f{0.5f, 0.5f} : sampler.get2D();
    std::optional<LightSample> ls = light->sampleLi(ctx, u);
    if (!ls || ls->pdf <= 0) continue;
    float cosTheta = dot(si.ns, ls->wi);
    if (cosTheta <= 0 || dot(si.ng, ls->wi) <= 0) continue;
    Rgb f = material.eval(si, ls->wi);
    if (maxComponent(f) <= 0) continue;
    if (shadows_ && light->castsShadows()) {
      Ray shadow = shadowRay(ctx, *ls);
      ++counters.shadow;
      if (scene_.accel->anyHit(shadow)) continue;
      if (media_) {
        const Rgb Tr = media_->transmittance(shadow, shadow.tMax, sampler);
        if (maxComponent(Tr) <= 0) continue;
        f *= Tr;
      }
    }
    L += f * ls->L * (cosTheta / ls->pdf);
  }
  return L;
}

}  // namespace glint
