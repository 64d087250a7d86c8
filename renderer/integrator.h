// glint — integrators: radiance along a camera ray.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "renderer/sampler.h"
#include "renderer/scene.h"
#include "renderer/settings.h"

namespace glint {

// Rays traced, by kind; summed over threads for --stats.
struct RayCounters {
  uint64_t camera = 0, shadow = 0, secondary = 0;
  RayCounters& operator+=(const RayCounters& o) {
    camera += o.camera, shadow += o.shadow, secondary += o.secondary;
    return *this;
  }
  uint64_t total() const { return camera + shadow + secondary; }
};

// First-hit attributes: `hit` always (for alpha); the rest only when `wanted` (AOV output).
struct PathAovs {
  bool wanted = false;
  Rgb albedo;
  Vec3f normal;
  float depth = 0;
  bool hit = false;
};

class Integrator {
 public:
  explicit Integrator(const RenderScene& scene) : scene_(scene) {}
  virtual ~Integrator() = default;
  const RenderScene& scene() const { return scene_; }

  // Radiance arriving at the camera along `ray`, whose closest hit the caller already found
  // (`hit` is null when the ray escapes): the render loop traces a pixel's camera rays
  // together and hands each result here. Draws random numbers from `sampler` in a fixed order;
  // counts the further rays it traces (not the camera ray); fills `aovs` from the first hit.
  virtual Rgb LiFromHit(const Ray& ray, const Hit* hit, Sampler& sampler,
                        RayCounters& counters, PathAovs& aovs) const = 0;

  // The same for a camera ray not yet traced: traces it, counts it, then LiFromHit.
  Rgb Li(const Ray& ray, Sampler& sampler, RayCounters& counters, PathAovs& aovs) const;

 protected:
  const RenderScene& scene_;
};

// Builds the integrator called `name` ("whitted"). Throws std::invalid_argument otherwise.
std::unique_ptr<Integrator> makeIntegrator(const std::string& name, const RenderScene& scene,
                                           const RenderSettings& settings);

}  // namespace glint
