// glint — the cone primitive: base disk of `radius` at y = 0, apex at (0, height, 0), the one
// nappe between; optionally closed by the base cap (then a solid).
#pragma once

#include "geometry/shape.h"

namespace glint {

class Cone final : public Shape {
 public:
  // radius, height > 0 and finite.
  Cone(float radius, float height, bool capped);

  const char* typeName() const override { return "cone"; }
  Bounds3f bounds() const override;
  bool intersect(const Ray& ray, ShapeHit* hit) const override;
  // Parts: 0 side (n outward, away from the axis and up; u = angle / 2pi from +X towards +Z,
  // v = y / height), 1 base cap at y = 0 (n = -Y, uv = (x/2r + 1/2, z/2r + 1/2)).
  ShapeSurface surface(const Ray& ray, const ShapeHit& hit) const override;
  bool isSolid() const override { return capped_; }
  float radius() const { return radius_; }
  float height() const { return height_; }
  bool capped() const { return capped_; }
  bool span(const Ray& ray, Span* out) const override;

 private:
  // The part of the line inside the infinite solid cone below the apex (y <= height), as
  // crossings; `tRoot` receives the double t of each finite crossing (NaN for +-inf).
  bool nappeSpan(const Ray& ray, Span* out, double tRoot[2]) const;

  float radius_, height_;
  bool capped_;
};

}  // namespace glint
