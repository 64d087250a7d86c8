// glint — unbounded shapes (infinite planes, and CSG trees whose bounds are infinite), kept
// out of acceleration hierarchies.
//
// An infinite plane has no finite bounding box. Giving it huge finite bounds (1e30) inside a
// BVH or kd-tree wrecks the SAH (every node overlaps it) and the bounds' own arithmetic; so
// every backend keeps such shapes in this short list instead and tests them directly: a
// closest-hit query first intersects them and then asks the hierarchy only for hits nearer
// than the nearest plane (shorter rays also traverse faster). Scenes have a handful of
// planes at most, so a linear list is the right structure. A moving one is placed at each
// ray's time (Instance::worldFromObjectAt), exactly as the bounded shapes are.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/accel/accelerator.h"
#include "geometry/mesh.h"

namespace glint {

class UnboundedShapes {
 public:
  // Collects the unbounded shape instances of `scene`.
  void build(const GeometryScene& scene);
  bool empty() const { return shapes_.empty(); }
  // The nearest hit with t in (tMin, tMax]: fills `hit` (instance, part as prim, t) and
  // returns true.
  bool closestHit(const Ray& ray, Hit* hit) const;
  bool anyHit(const Ray& ray) const;
  // Whether instance `i` is in the list.
  bool contains(uint32_t instance) const;

 private:
  // The shape at ray time `time`: as placed, or where its motion puts it then.
  PlacedShape at(size_t k, float time) const;

  std::vector<PlacedShape> shapes_;               // placed at shutter open
  std::vector<const AnimatedTransform*> motion_;  // null for static shapes
  std::vector<uint32_t> instances_;
};

}  // namespace glint
