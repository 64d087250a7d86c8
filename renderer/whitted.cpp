// glint — the Whitted integrator.
#include "renderer/whitted.h"

#include <stdexcept>

namespace glint {

WhittedIntegrator::WhittedIntegrator(const RenderScene& scene, int maxDepth)
    : Integrator(scene), maxDepth_(maxDepth) {
  needs_.uvs = scene.features.has(Feature::Textures);
  needs_.colors = scene.features.has(Feature::VertexColors);
  shadows_ = scene.features.has(Feature::Shadows);
  unlit_.resize(scene.materials.size());
  for (size_t m = 0; m < unlit_.size(); ++m)
    unlit_[m] = (scene.materials[m]->flags() & kBsdfUnlit) != 0;
}

Rgb WhittedIntegrator::LiFromHit(const Ray& ray, const Hit* found, Sampler& sampler,
                                 RayCounters& counters, PathAovs& aovs) const {
  if (!found) return scene_.background;
  const Hit& hit = *found;
  const uint32_t materialIndex = scene_.materialIndex(hit);
  const Material& material = *scene_.materials[materialIndex];
  const bool unlit = unlit_[materialIndex];
  SurfaceNeeds needs = needs_;
  needs.position = !unlit;
  SurfaceInteraction si = computeSurfaceInteraction(scene_.geometry, ray, hit, needs);
  aovs.hit = true;
  if (aovs.wanted) {
    aovs.albedo = material.albedo(si);
    aovs.normal = si.ns;
    aovs.depth = hit.t * length(ray.d);
  }
  if (unlit) return material.albedo(si) * std::abs(dot(si.ns, si.wo));

  Rgb L = material.emitted(si);
  L += directLight(si, material, ray.time, sampler, counters);
  // Specular recursion (mirror, glass) up to maxDepth_ lands with those materials (issue 5).
  (void)maxDepth_;
  return L;
}

Rgb WhittedIntegrator::directLight(const SurfaceInteraction& si, const Material& material,
                                   float time, Sampler& sampler, RayCounters& counters) const {
  Rgb L;
  for (const auto& light : scene_.lights) {
    Vec2f u = light->isDelta() ? Vec2f{0.5f, 0.5f} : sampler.get2D();
    std::optional<LightSample> ls = light->sampleLi(si.p, u);
    if (!ls || ls->pdf <= 0) continue;
    float cosTheta = dot(si.ns, ls->wi);
    if (cosTheta <= 0 || dot(si.ng, ls->wi) <= 0) continue;
    Rgb f = material.eval(si, ls->wi);
    if (maxComponent(f) <= 0) continue;
    if (shadows_ && light->castsShadows()) {
      Ray shadow = ls->infinite ? si.spawnRay(ls->wi, time) : si.spawnRayTo(ls->pLight, time);
      ++counters.shadow;
      if (scene_.accel->anyHit(shadow)) continue;
    }
    L += f * ls->Li * (cosTheta / ls->pdf);
  }
  return L;
}

}  // namespace glint
