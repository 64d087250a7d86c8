// glint — the quad primitive: the parallelogram corner + a edgeU + b edgeV, a, b in [0, 1].
#pragma once

#include "geometry/shape.h"
#include "geometry/shapes/registry.h"

namespace glint {

class Quad final : public Shape {
 public:
  // Finite, with non-parallel edges.
  Quad(Vec3f corner, Vec3f edgeU, Vec3f edgeV);

  // Reads and checks this shape's parameters (keyword "quad", geometry/shapes/registry.h).
  static std::unique_ptr<Shape> create(ShapeParameters& params);
  std::unique_ptr<Shape> clone() const override { return std::make_unique<Quad>(*this); }

  const char* typeName() const override { return "quad"; }
  Bounds3f bounds() const override;
  bool intersect(const Ray& ray, ShapeHit* hit) const override;
  // n = normalize(cross(edgeU, edgeV)) (both sides hittable); uv = (a, b); dpdu = edgeU,
  // dpdv = edgeV. Part 0.
  ShapeSurface surface(const Ray& ray, const ShapeHit& hit, SurfaceDetails details) const override;
  float area() const override;
  // Uniform: (a, b) = u, so uv = u.
  std::optional<ShapeSample> sample(Vec2f u) const override;
  Vec3f flatNormal() const override { return normal_; }

  Vec3f corner() const { return corner_; }
  Vec3f edgeU() const { return edgeU_; }
  Vec3f edgeV() const { return edgeV_; }

 private:
  // (a, b) of the point `p` of the quad's plane.
  void coordinates(const double p[3], double* a, double* b) const;

  Vec3f corner_, edgeU_, edgeV_, normal_;
};

}  // namespace glint
