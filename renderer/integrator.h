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
  virtual ~Integrator() = default;
  // Radiance arriving at the camera along `ray`. Draws random numbers from `sampler` in a fixed
  // order; counts the rays it traces; fills `aovs` from the first hit.
  virtual Rgb Li(const Ray& ray, Sampler& sampler, RayCounters& counters,
                 PathAovs& aovs) const = 0;
};

// Builds the integrator called `name` ("whitted"). Throws std::invalid_argument otherwise.
std::unique_ptr<Integrator> makeIntegrator(const std::string& name, const RenderScene& scene,
                                           const RenderSettings& settings);

}  // namespace glint
