// glint — integrators: radiance along a camera ray.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "renderer/ray_counters.h"
#include "renderer/sampler.h"
#include "renderer/scene.h"
#include "renderer/settings.h"
#include "renderer/shading.h"

namespace glint {

// First-hit attributes: `hit` always (for alpha); the rest only when `wanted` (AOV output).
struct PathAovs {
  bool wanted = false;
  Rgb albedo;
  Vec3f normal;
  float depth = 0;
  bool hit = false;

  // Records the first hit: `hit` always, the attributes only when wanted.
  void record(ShadedHit& h) {
    hit = true;
    if (!wanted) return;
    albedo = h.albedo();
    normal = h.si.ns;
    depth = h.distance;
  }
};

class Integrator {
 public:
  explicit Integrator(const RenderScene& scene);
  virtual ~Integrator() = default;
  const RenderScene& scene() const { return scene_; }

  // Radiance arriving at the camera along `ray`, whose closest hit the caller already found
  // (`hit` is null when the ray escapes): the render loop traces a pixel's camera rays
  // together and hands each result here. Draws random numbers from `sampler` in a fixed order;
  // counts the further rays it traces (not the camera ray); fills `aovs` from the first hit.
  virtual Rgb LiFromHit(const Ray& ray, const Hit* hit, Sampler& sampler, RayCounters& counters,
                        PathAovs& aovs) const = 0;

  // The same for a camera ray not yet traced: traces it, counts it, then LiFromHit.
  Rgb Li(const Ray& ray, Sampler& sampler, RayCounters& counters, PathAovs& aovs) const;

  // What the integrator prepared before rendering, for the statistics, as (name, value)
  // pairs: instant radiosity's VPLs and clamp; nothing for the others.
  struct SetupStat {
    std::string name;
    double value;
  };
  virtual std::vector<SetupStat> setupStats() const { return {}; }

 protected:
  const RenderScene& scene_;
  // What each material's hits need, per material: hits are shaded as
  // ShadedHit h(scene_, shading_, ray, hit, cone).
  std::vector<MaterialShading> shading_;
};

// The integrators there are.
enum class IntegratorKind { Whitted, Path, InstantRadiosity };

// The integrator settings.type asks for, with "auto" resolved for `scene`: the path tracer when
// the scene has light with an extent (an environment, emitting surfaces that are lights, any
// non-delta light) or media asked to scatter multiply, else Whitted. Throws
// InputError for unknown names (the loaders accept only integratorNames()).
IntegratorKind resolveIntegrator(const RenderScene& scene, const IntegratorSettings& settings);
// "whitted", "path", "instant-radiosity": the name the settings use.
const char* integratorName(IntegratorKind kind);
// Builds the integrator settings.integrator.type names for `scene` ("auto" resolved as
// above). Throws InputError for unknown names.
std::unique_ptr<Integrator> makeIntegrator(const RenderScene& scene,
                                           const RenderSettings& settings);
// The names makeIntegrator accepts.
const std::vector<std::string>& integratorNames();

}  // namespace glint
