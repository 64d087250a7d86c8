// glint — what every integrator shares, and the integrator factory.
#include "renderer/integrator.h"

#include <stdexcept>

#include "renderer/whitted.h"

namespace glint {

Rgb Integrator::Li(const Ray& ray, Sampler& sampler, RayCounters& counters,
                   PathAovs& aovs) const {
  ++counters.camera;
  Hit hit;
  bool found = scene_.accel->closestHit(ray, &hit);
  return LiFromHit(ray, found ? &hit : nullptr, sampler, counters, aovs);
}

std::unique_ptr<Integrator> makeIntegrator(const std::string& name, const RenderScene& scene,
                                           const RenderSettings& settings) {
  if (name == "whitted") return std::make_unique<WhittedIntegrator>(scene, settings.maxDepth);
  throw std::invalid_argument("unknown integrator '" + name + "' (whitted)");
}

}  // namespace glint
