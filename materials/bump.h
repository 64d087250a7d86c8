// glint — shading-normal modifiers: bump mapping, normal maps and "snow" (normal jitter).
//
// All of them work on SurfaceInteraction::dpdu / dpdv, which every primitive provides
// (triangles from their UVs, analytic shapes from their own parameterisation, CSG leaves from
// the leaf that was hit), and leave ns in ng's hemisphere. The BSDF then multiplies by
// the shadow-terminator term (bsdf.h) so that strongly tilted normals do not show a hard
// terminator.
#pragma once

#include "materials/material.h"

namespace glint {

// Blinn (1978): the surface displaced by strength * h along its normal; the perturbed normal
// is cross(dp/du + dh/du n, dp/dv + dh/dv n) with h = strength * height. The height derivatives
// are exact when the texture knows its gradient (procedural patterns) and finite differences
// over half a pixel footprint otherwise (images). Colour height maps are read as luminance.
class BumpMap final : public NormalModifier {
 public:
  BumpMap(const Texture* height, float strength) : height_(height), strength_(strength) {}
  void apply(SurfaceInteraction& si) const override;
  std::vector<const Texture*> textures() const override { return {height_}; }
  // dh/du and dh/dv at si (h including the strength), by the texture's gradient or by finite
  // differences; `forceFiniteDifferences` is for tests.
  Vec2f heightDerivatives(const SurfaceInteraction& si, bool forceFiniteDifferences) const;

 private:
  const Texture* height_;
  float strength_;
};

// A tangent-space normal map (glTF normalTexture): rgb * 2 - 1 in the frame (t, w n x t, n),
// the x and y components scaled by `scale`. t is the mesh's TANGENT (w its handedness; the
// builder derives per-vertex ones for files without, mesh.h's vertexTangents) or, for surfaces
// without any, dp/du from the UVs with the layout's own handedness (uvHandedness).
// The tangent frame (t, b) of glTF's tangent space at si around `front` (the normal on the
// surface's front side): the mesh's TANGENT with its bitangent handedness when it has one, else
// dp/du of the texture coordinate set `uvSet` (0: TEXCOORD_0, 1: TEXCOORD_1, whose dp/du1
// follows from dp/du, dp/dv and the triangle's map from uv to uv1) with the handedness of the
// uv layout; projected onto the plane of `front`. False when that projection vanishes. Normal
// maps and anisotropy share it.
bool tangentFrame(const SurfaceInteraction& si, Vec3f front, Vec3f* t, Vec3f* b, int uvSet = 0);

class NormalMap final : public NormalModifier {
 public:
  NormalMap(const Texture* map, float scale) : map_(map), scale_(scale) {}
  void apply(SurfaceInteraction& si) const override;
  std::vector<const Texture*> textures() const override { return {map_}; }

 private:
  const Texture* map_;
  float scale_;
};

// Random normal jitter, as on snow: the object-space surface is cut into cubic grains of size
// `grain`, and each grain tilts the normal by `amount` times a random vector in the unit ball
// (a hash of the grain cell and `seed`). Keyed to object space, the pattern stays put on
// moving objects and is the same in every frame.
class SnowPerturbation final : public NormalModifier {
 public:
  SnowPerturbation(float amount, float grain, uint64_t seed)
      : amount_(amount), grain_(grain), seed_(seed) {}
  void apply(SurfaceInteraction& si) const override;
  TextureNeeds needs() const override { return {.objectSpace = true}; }

 private:
  float amount_, grain_;
  uint64_t seed_;
};

// Keeps a perturbed normal in the geometric normal's hemisphere (tilted just above the
// surface when it would point below it).
Vec3f clampToHemisphere(Vec3f ns, Vec3f ng);

// The shading normal nearest `ns`, towards `ng`, about which the mirror direction of `wo`
// stays above the geometric surface: reflect(wo, n) . ng >= min(0.9 wo . ng, 0.01) (ng on
// wo's side, ns in ng's hemisphere, all unit). A normal map, a bump or a coarse mesh's
// interpolated normal can tilt ns away from a grazing view until wo skims it or falls below
// it; a BSDF built around such a normal divides by wo . ns (a glossy lobe's 1 / (4 wo.n wi.n),
// a mirror's F / cos) and sends its mirror direction into the surface. Tilting ns back in the
// plane of ng and ns just far enough (as Cycles' ensure_valid_reflection does) keeps every
// lobe's value, density and direction consistent with one another, and bounds
// wo . n >= wo . ng / 2. Returns ns itself where nothing is needed, which is almost every
// hit: one test of two dot products.
Vec3f reflectionSafeNormal(Vec3f ns, Vec3f ng, Vec3f wo);

}  // namespace glint
