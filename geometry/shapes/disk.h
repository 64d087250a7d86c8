// glint — the disk primitive: radius r in the plane y = 0, centred at the origin, normal +Y.
#pragma once

#include "geometry/shape.h"
#include "geometry/shapes/registry.h"

namespace glint {

class Disk final : public Shape {
 public:
  // radius > 0 and finite.
  explicit Disk(float radius);

  // Reads and checks this shape's parameters (keyword "disk", geometry/shapes/registry.h).
  static std::unique_ptr<Shape> create(ShapeParameters& params);
  std::unique_ptr<Shape> clone() const override { return std::make_unique<Disk>(*this); }

  const char* typeName() const override { return "disk"; }
  Bounds3f bounds() const override { return {{-radius_, 0, -radius_}, {radius_, 0, radius_}}; }
  bool intersect(const Ray& ray, ShapeHit* hit) const override;
  // n = +Y (both sides are hittable); uv = (x/2r + 1/2, z/2r + 1/2). Part 0.
  ShapeSurface surface(const Ray& ray, const ShapeHit& hit, SurfaceDetails details) const override;
  float area() const override { return kPi * radius_ * radius_; }
  // Uniform by the concentric map (stratified u stay stratified).
  std::optional<ShapeSample> sample(Vec2f u) const override;
  Vec3f flatNormal() const override { return {0, 1, 0}; }

  float radius() const { return radius_; }

 private:
  float radius_;
};

}  // namespace glint
