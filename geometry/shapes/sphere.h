// glint — the sphere primitive: a solid ball, Y as the pole axis (glTF is Y-up).
#pragma once

#include "geometry/shape.h"
#include "geometry/shapes/registry.h"

namespace glint {

class Sphere final : public Shape {
 public:
  // `radius` > 0 and finite.
  Sphere(Vec3f center, float radius);

  // Reads and checks this shape's parameters (keyword "sphere", geometry/shapes/registry.h).
  static std::unique_ptr<Shape> create(ShapeParameters& params);
  std::unique_ptr<Shape> clone() const override { return std::make_unique<Sphere>(*this); }

  const char* typeName() const override { return "sphere"; }
  Bounds3f bounds() const override;
  bool intersect(const Ray& ray, ShapeHit* hit) const override;
  // uv: u = phi / 2pi around +Y (phi from +X towards +Z), v = theta / pi from +Y. Part 0.
  ShapeSurface surface(const Ray& ray, const ShapeHit& hit, SurfaceDetails details) const override;
  bool isSolid() const override { return true; }
  bool span(const Ray& ray, const SurfaceTolerance& tolerance, Span* out) const override;
  float area() const override { return 4 * kPi * radius_ * radius_; }
  std::optional<ShapeSample> sample(Vec2f u) const override;
  // From outside: a uniform direction in the cone the sphere subtends (pbrt's method), so only
  // the cap facing `ref` is drawn; from inside: uniform by area.
  std::optional<ShapeSample> sample(Vec3f ref, Vec2f u) const override;
  float pdf(Vec3f ref, Vec3f p) const override;

  Vec3f center() const { return center_; }
  float radius() const { return radius_; }

 private:
  Vec3f center_;
  float radius_;
};

}  // namespace glint
