// glint — perfect mirror and dielectric glass (their lobes: MirrorBxdf, GlassBxdf in bxdfs.h).
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
  explicit MirrorMaterial(ColorParam reflectance) : reflectance_(reflectance) {
    uses(reflectance_);
  }
  Rgb albedo(const SurfaceInteraction& si, TextureLookups& lookups) const override {
    return reflectance_.evaluate(si, lookups);
  }
  uint32_t flags() const override { return kBsdfSpecular | kBsdfReflection; }

 protected:
  void setLobes(const SurfaceInteraction& si, TextureLookups& lookups, Bsdf* bsdf) const override {
    bsdf->emplace<MirrorBxdf>(reflectance_.evaluate(si, lookups));
  }

 private:
  ColorParam reflectance_;
};

// A smooth dielectric interface with index of refraction `ior` inside (the outside is
// vacuum/air, 1; interior and exterior media come with volumes). `transmittance` tints the
// refracted light (not the reflection, which stays white as on real glass).
class GlassMaterial final : public Material {
 public:
  GlassMaterial(float ior, ColorParam transmittance) : ior_(ior), transmittance_(transmittance) {
    uses(transmittance_);
    traits_.refraction = true;
  }
  Rgb albedo(const SurfaceInteraction& si, TextureLookups& lookups) const override {
    return transmittance_.evaluate(si, lookups);
  }
  uint32_t flags() const override { return kBsdfSpecular | kBsdfReflection | kBsdfTransmission; }
  float ior() const { return ior_; }

 protected:
  void setLobes(const SurfaceInteraction& si, TextureLookups& lookups, Bsdf* bsdf) const override {
    // eta across the interface for light leaving wo's side.
    bsdf->emplace<GlassBxdf>(si.frontFace ? ior_ : 1 / ior_, transmittance_.evaluate(si, lookups));
  }

 private:
  float ior_;
  ColorParam transmittance_;
};

}  // namespace glint
