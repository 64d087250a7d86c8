// glint — the infinite plane; as a solid, the half-space behind its normal.
#pragma once

#include "geometry/shape.h"
#include "geometry/shapes/registry.h"

namespace glint {

class Plane final : public Shape {
 public:
  // `normal` non-zero (normalized here), `point` finite, `uvScale` > 0.
  Plane(Vec3f point, Vec3f normal, float uvScale);

  // Reads and checks this shape's parameters (keyword "plane", geometry/shapes/registry.h).
  static std::unique_ptr<Shape> create(ShapeParameters& params);
  std::unique_ptr<Shape> clone() const override { return std::make_unique<Plane>(*this); }

  const char* typeName() const override { return "plane"; }
  // All-infinite: the plane is unbounded.
  Bounds3f bounds() const override;
  bool intersect(const Ray& ray, ShapeHit* hit) const override;
  // n = the unit normal; uv = coordinates in the fixed tangent frame Frame::fromZ(n) around
  // `point`, divided by uvScale (world-space tiling). Part 0.
  ShapeSurface surface(const Ray& ray, const ShapeHit& hit, SurfaceDetails details) const override;
  bool isSolid() const override { return true; }
  // (-inf, t] or [t, +inf) for a crossing line; a parallel line is all inside or missing.
  bool span(const Ray& ray, const SurfaceTolerance& tolerance, Span* out) const override;

  Vec3f point() const { return point_; }
  Vec3f normal() const { return normal_; }
  float uvScale() const { return uvScale_; }

 private:
  // The float values both span() and intersect() start from (plane.cpp).
  struct FloatSolve {
    float s, dn;    // (o - point) . n and d . n
    float es, edn;  // bounds on their rounding errors
  };
  FloatSolve floatSolve(const Ray& ray) const;
  bool spanFrom(const FloatSolve& f, const Ray& ray, const SurfaceTolerance& tolerance,
                Span* out) const;

  Vec3f point_, normal_;
  Frame frame_;
  float uvScale_;
};

}  // namespace glint
