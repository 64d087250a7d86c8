// glint — the cylinder primitive: axis +Y, x^2 + z^2 = r^2 for 0 <= y <= height, optionally
// closed by caps (then a solid).
#pragma once

#include "geometry/shape.h"

namespace glint {

class Cylinder final : public Shape {
 public:
  // radius, height > 0 and finite.
  Cylinder(float radius, float height, bool capped);

  const char* typeName() const override { return "cylinder"; }
  Bounds3f bounds() const override;
  bool intersect(const Ray& ray, ShapeHit* hit) const override;
  // Parts: 0 side (n away from the axis; u = angle / 2pi from +X towards +Z, v = y / height),
  // 1 cap at y = 0 (n = -Y), 2 cap at y = height (n = +Y); caps: uv = (x/2r + 1/2, z/2r + 1/2).
  ShapeSurface surface(const Ray& ray, const ShapeHit& hit) const override;
  bool isSolid() const override { return capped_; }
  float radius() const { return radius_; }
  float height() const { return height_; }
  bool capped() const { return capped_; }
  bool span(const Ray& ray, Span* out) const override;

 private:
  // The infinite cylinder's span of the line (the whole line for a ray along the axis inside).
  bool sideSpan(const Ray& ray, Span* out, double* t0, double* t1) const;

  float radius_, height_;
  bool capped_;
};

}  // namespace glint
