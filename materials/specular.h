// glint — perfect mirror and dielectric glass.
//
// Glass follows Snell's law with the exact dielectric Fresnel reflectance (scattering.h) and
// total internal reflection. Which side is outside comes from the hit (SurfaceInteraction::
// frontFace): a ray arriving on the front face enters the material. Radiance crossing the
// interface is scaled by 1/eta^2 (it is compressed into a narrower cone); a path that enters
// and leaves again gets both factors, which cancel.
#pragma once

#include "materials/material.h"

namespace glint {

// Reflects everything into the mirror direction, tinted by `reflectance`.
class MirrorMaterial final : public Material {
 public:
  explicit MirrorMaterial(ColorParam reflectance);
  Rgb albedo(const SurfaceInteraction& si) const override { return reflectance_.evaluate(si); }
  uint32_t flags() const override { return kBsdfSpecular | kBsdfReflection; }

 protected:
  Rgb evalBsdf(const SurfaceInteraction&, Vec3f) const override { return {}; }
  std::optional<BsdfSample> sampleBsdf(const SurfaceInteraction& si, Vec2f u, float uLobe,
                                       uint32_t lobes) const override;
  float pdfBsdf(const SurfaceInteraction&, Vec3f) const override { return 0; }

 private:
  ColorParam reflectance_;
};

// A smooth dielectric interface with index of refraction `ior` inside (the outside is
// vacuum/air, 1; interior and exterior media come with volumes). `transmittance` tints the
// refracted light (not the reflection, which stays white as on real glass).
class GlassMaterial final : public Material {
 public:
  GlassMaterial(float ior, ColorParam transmittance);
  Rgb albedo(const SurfaceInteraction& si) const override { return transmittance_.evaluate(si); }
  uint32_t flags() const override { return kBsdfSpecular | kBsdfReflection | kBsdfTransmission; }
  float ior() const { return ior_; }

 protected:
  Rgb evalBsdf(const SurfaceInteraction&, Vec3f) const override { return {}; }
  std::optional<BsdfSample> sampleBsdf(const SurfaceInteraction& si, Vec2f u, float uLobe,
                                       uint32_t lobes) const override;
  float pdfBsdf(const SurfaceInteraction&, Vec3f) const override { return 0; }

 private:
  float ior_;
  ColorParam transmittance_;
};

}  // namespace glint
