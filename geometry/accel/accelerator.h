// glint — the accelerator interface: closest-hit and any-hit queries over a GeometryScene.
//
// Backends are interchangeable and chosen by name (makeAccelerator); they are tested against
// each other. A hit records only what traversal knows (t, instance, primitive, barycentrics);
// surface details are computed once, for the final hit (computeSurfaceInteraction).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/ray.h"

namespace glint {

struct Hit {
  static constexpr uint32_t kInvalid = ~0u;
  float t = kInfinity;
  uint32_t instance = kInvalid;  // index into GeometryScene::instances
  uint32_t prim = kInvalid;      // triangle index within the instance's mesh
  float u = 0, v = 0;            // barycentrics: p = (1-u-v) p0 + u p1 + v p2
};

class Accelerator {
 public:
  virtual ~Accelerator() = default;
  virtual std::string name() const = 0;
  // Finds the closest hit with t in [ray.tMin, ray.tMax]; false when there is none.
  virtual bool closestHit(const Ray& ray, Hit* hit) const = 0;
  // True when anything is hit with t in [ray.tMin, ray.tMax] (shadow rays).
  virtual bool anyHit(const Ray& ray) const = 0;
};

// Builds the backend called `name` over `scene`, which must outlive the accelerator.
// Throws std::invalid_argument for an unknown name and std::runtime_error if the build fails.
std::unique_ptr<Accelerator> makeAccelerator(const std::string& name, const GeometryScene& scene);

// The names makeAccelerator accepts.
std::vector<std::string> acceleratorNames();

}  // namespace glint
