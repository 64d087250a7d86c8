// glint — the infinite plane; as a solid, the half-space behind its normal.
#pragma once

#include "geometry/shape.h"

namespace glint {

class Plane final : public Shape {
 public:
  // `normal` non-zero (normalized here), `point` finite, `uvScale` > 0.
  Plane(Vec3f point, Vec3f normal, float uvScale);

  const char* typeName() const override { return "plane"; }
  // All-infinite: the plane is unbounded.
  Bounds3f bounds() const override;
  bool intersect(const Ray& ray, ShapeHit* hit) const override;
  // n = the unit normal; uv = coordinates in the fixed tangent frame Frame::fromZ(n) around
  // `point`, divided by uvScale (world-space tiling). Part 0.
  ShapeSurface surface(const Ray& ray, const ShapeHit& hit) const override;
  bool isSolid() const override { return true; }
  // (-inf, t] or [t, +inf) for a crossing line; a parallel line is all inside or missing.
  bool span(const Ray& ray, Span* out) const override;

 private:
  Vec3f point_, normal_;
  Frame frame_;
  float uvScale_;
};

}  // namespace glint
