// glint — what every integrator shares, and the integrator factory.
#include "renderer/integrator.h"

#include "geometry/error.h"
#include "renderer/instant_radiosity.h"
#include "renderer/path.h"
#include "renderer/whitted.h"

namespace glint {

Integrator::Integrator(const RenderScene& scene)
    : scene_(scene), shading_(materialShadings(scene)) {}

Rgb Integrator::Li(const Ray& ray, Sampler& sampler, RayCounters& counters, PathAovs& aovs) const {
  ++counters.camera;
  Hit hit;
  bool found = scene_.accel().closestHit(ray, &hit);
  return LiFromHit(ray, found ? &hit : nullptr, sampler, counters, aovs);
}

const std::vector<std::string>& integratorNames() {
  static const std::vector<std::string> names = {"whitted", "path", "instant-radiosity", "auto"};
  return names;
}

IntegratorKind resolveIntegrator(const RenderScene& scene, const IntegratorSettings& settings) {
  if (settings.type == "whitted") return IntegratorKind::Whitted;
  if (settings.type == "path") return IntegratorKind::Path;
  if (settings.type == "instant-radiosity") return IntegratorKind::InstantRadiosity;
  if (settings.type != "auto")
    throw InputError("unknown integrator '" + settings.type +
                     "' (whitted, path, instant-radiosity, auto)");
  // Media asking for multiple scattering need the path tracer (Whitted scatters once); other
  // media go by the light rule below (Whitted's marched single scattering is the low-noise
  // answer for point lights).
  if (scene.media() && settings.volume == "multiple") return IntegratorKind::Path;
  // Light with an extent (area, emitting surfaces, the environment) is what Whitted's hard
  // shadows cannot render; point, spot and directional lights it renders exactly.
  bool extended = !scene.infiniteLights().empty();
  for (int32_t l : scene.instanceLight()) extended = extended || l >= 0;
  for (const auto& light : scene.lights()) extended = extended || !light->isDelta();
  // A rough metal reflects the rest of the scene through a glossy lobe, which Whitted renders
  // only as highlights of point lights: it looks black elsewhere.
  for (const auto& material : scene.materials())
    extended = extended || material->traits().glossyMetal;
  return extended ? IntegratorKind::Path : IntegratorKind::Whitted;
}

const char* integratorName(IntegratorKind kind) {
  switch (kind) {
    case IntegratorKind::Whitted:
      return "whitted";
    case IntegratorKind::Path:
      return "path";
    case IntegratorKind::InstantRadiosity:
      return "instant-radiosity";
  }
  return "?";
}

std::unique_ptr<Integrator> makeIntegrator(const RenderScene& scene,
                                           const RenderSettings& settings) {
  const IntegratorSettings& s = settings.integrator;
  switch (resolveIntegrator(scene, s)) {
    case IntegratorKind::Whitted:
      return std::make_unique<WhittedIntegrator>(scene, s.maxDepth, s.glassShadows, s.minWeight);
    case IntegratorKind::Path:
      return std::make_unique<PathIntegrator>(scene, s);
    case IntegratorKind::InstantRadiosity:
      return std::make_unique<InstantRadiosityIntegrator>(scene, s, settings.seed);
  }
  return nullptr;
}

}  // namespace glint
