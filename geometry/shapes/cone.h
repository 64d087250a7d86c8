// glint — the cone primitive: base disk of `radius` at y = 0, apex at (0, height, 0), the one
// nappe between; optionally closed by the base cap (then a solid).
#pragma once

#include "geometry/shape.h"
#include "geometry/shapes/registry.h"

namespace glint {

namespace prim {
struct RevolvedView;
}

class Cone final : public Shape {
 public:
  // radius, height > 0 and finite.
  Cone(float radius, float height, bool capped);

  // Reads and checks this shape's parameters (keyword "cone", geometry/shapes/registry.h).
  static std::unique_ptr<Shape> create(ShapeParameters& params);
  std::unique_ptr<Shape> clone() const override { return std::make_unique<Cone>(*this); }

  const char* typeName() const override { return "cone"; }
  Bounds3f bounds() const override;
  bool intersect(const Ray& ray, ShapeHit* hit) const override;
  // Parts: 0 side (n outward, away from the axis and up; u = angle / 2pi from +X towards +Z,
  // v = y / height), 1 base cap at y = 0 (n = -Y, uv = (x/2r + 1/2, z/2r + 1/2)).
  ShapeSurface surface(const Ray& ray, const ShapeHit& hit, SurfaceDetails details) const override;
  bool isSolid() const override { return capped_; }
  float radius() const { return radius_; }
  float height() const { return height_; }
  bool capped() const { return capped_; }
  bool span(const Ray& ray, const SurfaceTolerance& tolerance, Span* out) const override;
  float area() const override;
  std::optional<ShapeSample> sample(Vec2f u) const override;
  // Capped, from outside: uniform by area over what faces `ref`, the side's generators within
  // an angle of ref's own and the cap ref is beyond; otherwise the whole surface.
  std::optional<ShapeSample> sample(Vec3f ref, Vec2f u) const override;
  float pdf(Vec3f ref, Vec3f p) const override;

 private:
  // What a receiver at `ref` may see (primitive_math.h: the side's generators and caps).
  prim::RevolvedView visibleFrom(Vec3f ref) const;
  // Areas of the visible side and caps, indexed by part; returns the total.
  double visibleAreas(const prim::RevolvedView& v, double areas[2]) const;
  std::optional<ShapeSample> sampleVisible(const prim::RevolvedView& v, Vec2f u) const;

  // The part of the line inside the infinite solid cone below the apex (y <= height), as
  // crossings; `tRoot` receives the double t of each finite crossing (NaN for +-inf).
  bool nappeSpan(const Ray& ray, Span* out, double tRoot[2]) const;

  float radius_, height_;
  bool capped_;
};

}  // namespace glint
