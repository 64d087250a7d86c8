// glint — the list of unbounded shapes.
#include "geometry/accel/unbounded.h"

#include <algorithm>

#include "geometry/accel/accelerator.h"

namespace glint {

void UnboundedShapes::build(const GeometryScene& scene) {
  shapes_.clear();
  motion_.clear();
  instances_.clear();
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    if (!inst.isShape()) continue;
    PlacedShape placed = scene.placedShape(i);
    if (!isUnbounded(placed.bounds())) continue;
    shapes_.push_back(placed);
    motion_.push_back(inst.moves() ? &inst.motion : nullptr);
    instances_.push_back(i);
  }
}

PlacedShape UnboundedShapes::at(size_t k, float time) const {
  if (!motion_[k]) return shapes_[k];
  return PlacedShape(&shapes_[k].shape(), motion_[k]->at(time));
}

bool UnboundedShapes::closestHit(const Ray& ray, Hit* hit) const {
  Ray r = ray;
  bool found = false;
  for (size_t k = 0; k < shapes_.size(); ++k) {
    ShapeHit sh;
    const bool hitK = motion_[k] ? at(k, ray.time).intersect(r, &sh) : shapes_[k].intersect(r, &sh);
    if (!hitK) continue;
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
  for (size_t k = 0; k < shapes_.size(); ++k)
    if (motion_[k] ? at(k, ray.time).occluded(ray) : shapes_[k].occluded(ray)) return true;
  return false;
}

bool UnboundedShapes::contains(uint32_t instance) const {
  return std::find(instances_.begin(), instances_.end(), instance) != instances_.end();
}

}  // namespace glint
