// glint — the axis-aligned box primitive (a solid; place it with PlacedShape to rotate it).
#pragma once

#include "geometry/shape.h"
#include "geometry/shapes/registry.h"

namespace glint {

class Box final : public Shape {
 public:
  // lower < upper in every axis, all finite.
  Box(Vec3f lower, Vec3f upper);

  // Reads and checks this shape's parameters (keyword "box", geometry/shapes/registry.h).
  static std::unique_ptr<Shape> create(ShapeParameters& params);
  std::unique_ptr<Shape> clone() const override { return std::make_unique<Box>(*this); }

  const char* typeName() const override { return "box"; }
  Bounds3f bounds() const override { return {lower_, upper_}; }
  Vec3f lower() const { return lower_; }
  Vec3f upper() const { return upper_; }
  bool intersect(const Ray& ray, ShapeHit* hit) const override;
  // Parts 0..5 = -X, +X, -Y, +Y, -Z, +Z. uv in [0,1]^2 per face: X faces (z, y), Y faces
  // (x, z), Z faces (x, y), each measured from `lower`.
  ShapeSurface surface(const Ray& ray, const ShapeHit& hit, SurfaceDetails details) const override;
  bool isSolid() const override { return true; }
  bool span(const Ray& ray, const SurfaceTolerance& tolerance, Span* out) const override;
  float area() const override;
  std::optional<ShapeSample> sample(Vec2f u) const override;
  // From outside: uniform by area over the faces turned towards `ref` (the others are hidden
  // behind them); from inside: all faces.
  std::optional<ShapeSample> sample(Vec3f ref, Vec2f u) const override;
  float pdf(Vec3f ref, Vec3f p) const override;

 private:
  // Bit f set for the faces f (parts) whose outside holds ref; all six when none does.
  unsigned facesSeenFrom(Vec3f ref) const;
  // A point uniform by area over the faces in `faces`.
  std::optional<ShapeSample> sampleFaces(unsigned faces, Vec2f u) const;
  double faceArea(int face) const;

  Vec3f lower_, upper_;
};

}  // namespace glint
