// glint — area lights: quads, disks (ellipses), spheres, emissive triangle meshes and the
// surfaces of analytic shapes under any affine placement.
//
// Quads, disks, meshes and shape surfaces are sampled by area, the density then converted to
// solid angle (pdf = d^2 / (|cos| area density)). Spheres seen from outside are sampled by the cone of directions
// they subtend (uniform in the cone, as pbrt does), which wastes no samples on the far side.
// Emission is one-sided by default (towards the surface normal) or two-sided; an emitting
// material's light is two-sided, because Material::emitted ignores the side a ray arrives from.
#pragma once

#include <vector>

#include "geometry/math.h"
#include "materials/material.h"
#include "renderer/light.h"
#include "renderer/light_sampler.h"

namespace glint {

// The radiance an area light emits: a constant, or the emitting material evaluated at the
// point (textured emission), on one side (the normal's) or both.
struct AreaEmission {
  Rgb radiance{1, 1, 1};              // used when `material` is null
  const Material* material = nullptr;  // emitting surfaces: Material::emitted at the point
  Transform objectFromWorld;          // the surface's object frame, for object-space textures
  uint32_t instance = 0;              // the instance, for textures keyed on it
  bool twoSided = false;

  // Radiance leaving point p (unit normal n, uv) towards unit direction wo.
  Rgb at(Vec3f p, Vec3f n, Vec3f ns, Vec2f uv, Vec3f wo) const;
};

// A point on a light's surface, drawn uniformly by area.
struct AreaPoint {
  Vec3f p, pError;
  Vec3f n;   // unit geometric normal (the emitting side)
  Vec3f ns;  // unit shading normal (meshes with normals), else n
  Vec2f uv;
};

// The shared part of quads, disks and meshes: uniform area sampling converted to solid angle.
class AreaLight : public Light {
 public:
  std::optional<LightSample> sampleLi(const LightSampleContext& ctx, Vec2f u) const override;
  float pdfLi(const LightSampleContext& ctx, Vec3f wi, const LightHit& hit) const override;
  std::optional<LightLeSample> sampleLe(Vec2f uPos, Vec2f uDir, float time) const override;
  Rgb phi() const override { return phi_; }
  const AreaEmission& emission() const { return emission_; }
  // Sidecar lights may opt out of shadows (emitting surfaces always cast them).
  void setCastsShadows(bool castsShadows) { castsShadows_ = castsShadows; }
  float area() const { return area_; }
  // A point on the surface for u in [0, 1)^2: uniform by area unless areaDensity says
  // otherwise.
  virtual AreaPoint samplePoint(Vec2f u) const = 0;
  // The density of samplePoint per unit world area at a point of unit geometric normal n
  // (either side): 1 / area for uniform sampling.
  virtual float areaDensity(Vec3f n) const {
    (void)n;
    return 1 / area_;
  }

 protected:
  explicit AreaLight(const AreaEmission& emission)
      : Light(LightKind::Area), emission_(emission) {}
  // Called by the constructors once the shape is known: the power, from the radiance averaged
  // over a stratified grid of points (exact for constant radiance).
  void finish();
  AreaEmission emission_;
  float area_ = 0;
  Rgb phi_;
};

// The parallelogram corner + a edgeU + b edgeV, a, b in [0, 1]; normal cross(edgeU, edgeV);
// uv = (a, b), like the quad shape.
class QuadLight final : public AreaLight {
 public:
  QuadLight(Vec3f corner, Vec3f edgeU, Vec3f edgeV, const AreaEmission& emission);
  AreaPoint samplePoint(Vec2f u) const override;
  std::optional<LightBounds> bounds() const override;

 private:
  Vec3f corner_, edgeU_, edgeV_, normal_;
};

// The ellipse center + x axisX + z axisZ, x^2 + z^2 <= 1 (a disk when the axes are orthogonal
// and of equal length: the radius); normal cross(axisZ, axisX); uv = (x/2 + 1/2, z/2 + 1/2),
// like the disk shape (whose axes are r X and r Z, normal +Y).
class DiskLight final : public AreaLight {
 public:
  DiskLight(Vec3f center, Vec3f axisX, Vec3f axisZ, const AreaEmission& emission);
  AreaPoint samplePoint(Vec2f u) const override;
  std::optional<LightBounds> bounds() const override;

 private:
  Vec3f center_, axisX_, axisZ_, normal_;
};

// A sphere emitting outwards (or both ways). Seen from outside: a uniform direction in the
// cone it subtends; from inside: uniform by area. `objectFromWorld` orients the uv (like the
// sphere shape: u around +Y from +X towards +Z, v from +Y) for textured emission.
class SphereLight final : public AreaLight {
 public:
  SphereLight(Vec3f center, float radius, const AreaEmission& emission);
  std::optional<LightSample> sampleLi(const LightSampleContext& ctx, Vec2f u) const override;
  float pdfLi(const LightSampleContext& ctx, Vec3f wi, const LightHit& hit) const override;
  AreaPoint samplePoint(Vec2f u) const override;
  std::optional<LightBounds> bounds() const override;

 private:
  AreaPoint pointAt(Vec3f n) const;  // the surface point of outward unit normal n
  Vec3f center_;
  float radius_;
};

// One piece of an analytic shape's surface in the shape's object space, as
// ShapeSurfaceLight samples it. Its uv follow the shape's own surface() (geometry/shapes/).
struct SurfacePart {
  enum class Kind {
    Parallelogram,  // origin + a edgeU + b edgeV, a, b in [0, 1]; uv = (a, b)
    Disk,           // centre origin, `radius`, in the plane y = origin.y; normal ±Y; uv (x, z)
    CylinderSide,   // x^2 + z^2 = radius^2 for 0 <= y <= height; uv (angle / 2pi, y / height)
    ConeSide,       // base `radius` at y = 0, apex at y = height; uv as the cylinder's
    Sphere,         // centre origin, `radius`; uv (phi / 2pi around +Y, theta / pi from +Y)
  };
  Kind kind = Kind::Parallelogram;
  Vec3f origin, edgeU, edgeV;
  Vec3f normal;  // outward unit normal: parallelogram (± cross(edgeU, edgeV)) and disk
  float radius = 0, height = 0;
  float area() const;
};

// The whole surface of an analytic shape (a box's faces, a cylinder's or cone's side and caps,
// a sphere) placed by any affine `worldFromObject`, also with non-uniform scale or shear.
// Points are drawn uniformly by *object* area (a part by its area, then a point on it) and
// mapped to the world; there a surface element of object normal n_o grows by
// J = |det M| |M^-T n_o| = |det M| / |M^T n| (M: the linear part, n: the world unit normal),
// so the density per unit world area is |M^T n| / (A_obj |det M|): exact, and uniform again
// under a similarity. Every point of the closed surface is drawn, also those on the far side
// that the shape itself hides from the receiver (their shadow rays find the shape): simple and
// unbiased, at the price of about half the samples of a convex shape seen from outside.
class ShapeSurfaceLight final : public AreaLight {
 public:
  ShapeSurfaceLight(std::vector<SurfacePart> parts, const Transform& worldFromObject,
                    const AreaEmission& emission);
  AreaPoint samplePoint(Vec2f u) const override;
  float areaDensity(Vec3f n) const override;
  std::optional<LightBounds> bounds() const override;

 private:
  std::vector<SurfacePart> parts_;
  Transform world_;
  DiscreteDistribution byArea_;  // parts by object area
  float objectArea_ = 0, det_ = 0;
  Bounds3f bounds_;
};

// An emissive triangle mesh in world space: a triangle picked by area, then a uniform point in
// it. Normals (per vertex, optional) give the shading normal the material sees; uvs
// (optional) its texture coordinates, barycentrics otherwise, as for camera hits.
class TriangleMeshLight final : public AreaLight {
 public:
  TriangleMeshLight(std::vector<Vec3f> positions, std::vector<uint32_t> indices,
                    std::vector<Vec3f> normals, std::vector<Vec2f> uvs,
                    const AreaEmission& emission);
  AreaPoint samplePoint(Vec2f u) const override;
  std::optional<LightBounds> bounds() const override;

 private:
  std::vector<Vec3f> positions_, normals_;
  std::vector<uint32_t> indices_;
  std::vector<Vec2f> uvs_;
  DiscreteDistribution triangles_;  // by area
};

}  // namespace glint
