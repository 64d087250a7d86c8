// glint — area lights: quads, disks (ellipses), spheres and emissive triangle meshes.
//
// Quads, disks and meshes are sampled by area, the density then converted to solid angle
// (pdf = d^2 / (|cos| area)). Spheres seen from outside are sampled by the cone of directions
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
  // A uniform point on the surface for u in [0, 1)^2.
  virtual AreaPoint samplePoint(Vec2f u) const = 0;

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
