// glint — Whitted-style ray tracing: direct light from every light with hard shadows, the
// eyelight shortcut, emission; mirror and glass recursion arrive with those shaders.
#pragma once

#include <cstdint>
#include <vector>

#include "renderer/integrator.h"

namespace glint {

class WhittedIntegrator final : public Integrator {
 public:
  WhittedIntegrator(const RenderScene& scene, int maxDepth);
  Rgb LiFromHit(const Ray& ray, const Hit* hit, Sampler& sampler, RayCounters& counters,
                PathAovs& aovs) const override;

 private:
  // Direct light at a lit surface point: sum over all lights, shadow rays when enabled.
  Rgb directLight(const SurfaceInteraction& si, const Material& material, float time,
                  Sampler& sampler, RayCounters& counters) const;

  int maxDepth_;
  SurfaceNeeds needs_;  // from the scene's features
  bool shadows_;
  std::vector<uint8_t> unlit_;  // per material: unlit (decided once, not per hit)
};

}  // namespace glint
