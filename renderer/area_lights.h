// glint — the area light: an emitting surface and its emission. The surface is an analytic
// shape under an affine placement (geometry/shapes/: each shape samples itself) or a triangle
// mesh; there is no per-shape light class, so a new shape is a light with no change here.
//
// Next-event estimation asks the surface for a point as seen from the receiver: by area over
// the part of it the receiver may see (a sphere's subtended cone, a box's front faces, ...), so
// closed emitters spend no samples on their far side. That area density becomes solid angle
// once, in world space (pdf = d^2 / |cos| x area density), and pdfLi evaluates the same density
// at the point a BSDF sample found, so MIS weighs with exactly the density sampleLi used.
// Emission is one-sided (towards the normal) or two-sided; an emitting material's light is
// two-sided, because Material::emitted ignores the side a ray arrives from.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "geometry/math.h"
#include "geometry/shape.h"
#include "materials/material.h"
#include "renderer/light.h"
#include "renderer/light_sampler.h"

namespace glint {

// The radiance an area light emits: a constant, or the emitting material evaluated at the
// point (textured emission), on one side (the normal's) or both.
struct AreaEmission {
  Rgb radiance{1, 1, 1};               // used when `material` is null
  const Material* material = nullptr;  // emitting surfaces: Material::emitted at the point
  Transform objectFromWorld;           // the surface's object frame, for object-space textures
  uint32_t instance = 0;               // the instance, for textures keyed on it
  bool twoSided = false;

  // Radiance leaving point p (unit normal n, shading normal ns, texture coordinates uv and
  // uv1: glTF's TEXCOORD_0 and _1) towards unit direction wo; textures filtered over the uv
  // footprint duvdx, duvdy (zero: a point sample).
  Rgb at(Vec3f p, Vec3f n, Vec3f ns, Vec2f uv, Vec2f uv1, Vec3f wo, Vec2f duvdx = {},
         Vec2f duvdy = {}) const;
};

// An emitting triangle mesh in world space. Normals (per vertex, optional) give the shading
// normal the material sees; uvs (optional) its texture coordinates, barycentrics otherwise, as
// for camera hits; uvs1 (optional) the second set, uvs otherwise.
struct EmissiveMesh {
  std::vector<Vec3f> positions;
  std::vector<uint32_t> indices;  // three per triangle
  std::vector<Vec3f> normals;
  std::vector<Vec2f> uvs;
  std::vector<Vec2f> uvs1;
};

class AreaLight final : public Light {
 public:
  // An emitting shape placed in the world; `owned` keeps alive the shape `shape` refers to
  // when the light made it (sidecar lights); emitting instances refer to the scene's shapes.
  AreaLight(const PlacedShape& shape, const AreaEmission& emission,
            std::unique_ptr<Shape> owned = nullptr);
  // An emitting triangle mesh: a triangle picked by the power it emits (its area times its
  // mean radiance, estimated once from the emission's textures), then a uniform point in it.
  // A mesh whose emissive texture is black almost everywhere (glTF's lamps and screens) thus
  // spends its light samples where it glows.
  AreaLight(EmissiveMesh mesh, const AreaEmission& emission);

  std::optional<LightSample> sampleLi(const LightSampleContext& ctx, Vec2f u) const override;
  float pdfLi(const LightSampleContext& ctx, Vec3f wi, const LightHit& hit) const override;
  std::optional<LightLeSample> sampleLe(Vec2f uPos, Vec2f uDir, float time) const override;
  Rgb phi() const override { return phi_; }
  std::optional<LightBounds> bounds() const override;

  const AreaEmission& emission() const { return emission_; }
  // Sidecar lights may opt out of shadows (emitting surfaces always cast them).
  void setCastsShadows(bool castsShadows) { castsShadows_ = castsShadows; }
  // World-space area of the whole surface.
  float area() const { return area_; }
  // The placed shape, or null for a mesh.
  const PlacedShape* shape() const { return shape_ ? &*shape_ : nullptr; }

 private:
  // A point of the surface with its world area density: for the receiver at *ref (visible
  // part only), or uniform when ref is null. `ns` receives the shading normal, `uv1` the
  // second texture coordinate set (the sample's uv where there is none).
  std::optional<ShapeSample> samplePoint(const Vec3f* ref, Vec2f u, Vec3f* ns, Vec2f* uv1) const;
  // The density of samplePoint(&ref, ·) per unit world area at surface point p, normal n, on
  // triangle `prim` of a mesh.
  float pdfPoint(Vec3f ref, Vec3f p, Vec3f n, uint32_t prim) const;
  // A mesh triangle's mean radiance (luminance), from lookups spread over it.
  Rgb meanRadiance(uint32_t t) const;
  // Where the shape judges what a receiver sees from: the receiving point moved off its
  // surface towards the light past its rounding error, so that a point on the light itself
  // (a glowing enclosure lit by the rest of it) counts as inside whichever way it rounded.
  Vec3f referencePoint(const LightSampleContext& ctx) const;
  // Power and bounds, once the surface is known.
  void finish();

  std::unique_ptr<Shape> owned_;
  std::optional<PlacedShape> shape_;
  EmissiveMesh mesh_;
  DiscreteDistribution triangles_;  // by emitted power (area times mean radiance)
  std::vector<float> triangleAreas_;
  AreaEmission emission_;
  Bounds3f bounds_;
  float area_ = 0;
  Rgb phi_;
};

// An area light over a shape of its own, placed by `worldFromObject`.
std::unique_ptr<AreaLight> makeShapeLight(std::unique_ptr<Shape> shape,
                                          const Transform& worldFromObject,
                                          const AreaEmission& emission);

}  // namespace glint
