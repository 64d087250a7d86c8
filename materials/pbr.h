// glint — glTF's metallic-roughness material: the recipe whose lobes, PbrBxdf (bxdfs.h), are a
// microfacet BSDF (Trowbridge–Reitz / GGX with height-correlated Smith masking and
// visible-normal sampling, microfacet.h).
//
// The model is the glTF 2.0 specification's (Appendix B) with KHR_materials_transmission and
// KHR_materials_ior:
//   f = metallic         * F_schlick(baseColor, wo.h) * spec
//     + (1 - metallic)   * [ F(wo.h) * spec + (1 - F(wo.n)) * diffuse + btdf part ]
//   diffuse = (1 - transmission) * baseColor / pi, btdf part = transmission * baseColor * btdf
// where spec is the GGX reflection lobe, btdf the GGX refraction lobe (Walter et al. 2007,
// weighted by 1 - F(wo.m) per microfacet) and F the exact dielectric Fresnel reflectance for
// `ior` (the specification allows Schlick; the exact form costs little and matches the glass
// shader). One deliberate change: the diffuse part is weighted by 1 - F(wo.n), not the
// specification's 1 - F(wo.h), which the specification itself notes is not energy conserving
// (it reached an albedo of 1.68 at grazing angles in the white furnace test); the price is a
// darker rough dielectric at grazing angles (missing multiple scattering, which Kulla-Conty
// tables would restore).
// Transmission refracts (as with KHR_materials_volume); a thin-walled variant is not modelled.
//
// Roughness below ~0.03 (alpha < 1e-3) cannot be sampled or integrated in float; where a hit's
// roughness (constant or from the texture) is that low, the specular reflection and refraction
// are delta lobes, so that mirrors and clear glass from glTF render as such in the Whitted
// integrator too.
#pragma once

#include "materials/material.h"

namespace glint {

struct PbrParams {
  ColorParam baseColor;
  FloatParam metallic{1}, roughness{1};  // glTF: metallicRoughnessTexture B and G channels
  ColorParam emission{{0, 0, 0}};
  float ior = 1.5f;
  FloatParam transmission{0};
};

class PbrMaterial final : public Material {
 public:
  explicit PbrMaterial(const PbrParams& params);
  Rgb emitted(const SurfaceInteraction& si, TextureLookups& lookups) const override {
    return p_.emission.evaluate(si, lookups);
  }
  using Material::emitted;
  Rgb albedo(const SurfaceInteraction& si, TextureLookups& lookups) const override {
    return p_.baseColor.evaluate(si, lookups);
  }
  uint32_t flags() const override { return flags_; }

 protected:
  Bsdf makeBsdf(const SurfaceInteraction& si, const BsdfFrame& frame,
                TextureLookups& lookups) const override;

 private:
  PbrParams p_;
  uint32_t flags_;
};

}  // namespace glint
