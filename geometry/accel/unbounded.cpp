// glint — the list of unbounded shapes.
#include "geometry/accel/unbounded.h"

#include <algorithm>

#include "geometry/accel/accelerator.h"

namespace glint {

void UnboundedShapes::build(const GeometryScene& scene) {
  shapes_.clear();
  instances_.clear();
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    if (!scene.instances[i].isShape()) continue;
    PlacedShape placed = scene.placedShape(i);
    if (!isUnbounded(placed.bounds())) continue;
    shapes_.push_back(placed);
    instances_.push_back(i);
  }
}

bool UnboundedShapes::closestHit(const Ray& ray, Hit* hit) const {
  Ray r = ray;
  bool found = false;
  for (size_t k = 0; k < shapes_.size(); ++k) {
    ShapeHit sh;
    if (!shapes_[k].intersect(r, &sh)) continue;
    r.tMax = sh.t;
    hit->t = sh.t;
    hit->instance = instances_[k];
    hit->prim = sh.part;
    hit->u = hit->v = 0;
    found = true;
  }
  return found;
}

bool UnboundedShapes::anyHit(const Ray& ray) const {
  for (const PlacedShape& s : shapes_)
    if (s.occluded(ray)) return true;
  return false;
}

bool UnboundedShapes::contains(uint32_t instance) const {
  return std::find(instances_.begin(), instances_.end(), instance) != instances_.end();
}

}  // namespace glint
