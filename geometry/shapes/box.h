// glint — the axis-aligned box primitive (a solid; place it with PlacedShape to rotate it).
#pragma once

#include "geometry/shape.h"

namespace glint {

class Box final : public Shape {
 public:
  // lower < upper in every axis, all finite.
  Box(Vec3f lower, Vec3f upper);

  const char* typeName() const override { return "box"; }
  Bounds3f bounds() const override { return {lower_, upper_}; }
  Vec3f lower() const { return lower_; }
  Vec3f upper() const { return upper_; }
  bool intersect(const Ray& ray, ShapeHit* hit) const override;
  // Parts 0..5 = -X, +X, -Y, +Y, -Z, +Z. uv in [0,1]^2 per face: X faces (z, y), Y faces
  // (x, z), Z faces (x, y), each measured from `lower`.
  ShapeSurface surface(const Ray& ray, const ShapeHit& hit) const override;
  bool isSolid() const override { return true; }
  bool span(const Ray& ray, Span* out) const override;

 private:
  Vec3f lower_, upper_;
};

}  // namespace glint
