// glint — glTF's metallic-roughness material: the recipe whose lobes, PbrBxdf (bxdfs.h), are a
// microfacet BSDF (Trowbridge–Reitz / GGX with height-correlated Smith masking and
// visible-normal sampling, microfacet.h).
//
// The model is the glTF 2.0 specification's (Appendix B) with its material extensions:
//   material   = coat_layer(sheen_layer(base))
//   base       = metallic       * [ F_metal(wo.h) * spec + F_ms * ms ]
//              + (1 - metallic) * [ F(wo.h) * spec + diffuse part + btdf part ]
//   diffuse part = (1 - transmission) * S(wo, wi)
//                  * [(1 - dt) * baseColor / pi + dt * dtColor / pi (other side)]
//   S(wo, wi)    = (1 - E_spec(wo)) (1 - E_spec(wi)) / (1 - E_spec,avg)   (albedo scaling)
//   btdf part    = transmission * (1 - F(wo.m)) * baseColor * btdf
//   sheen_layer(b) = sheenColor * D_charlie V / (4 cos cos) + (1 - max(sheenColor) E_sheen(wo)) * b
//   coat_layer(b)  = clearcoat * F_coat(wo.h) * spec_coat  + (1 - clearcoat * F_coat(wo.n_coat)) *
//   b
// where spec is the GGX reflection lobe (anisotropic with KHR_materials_anisotropy: roughness
// along the direction mix(alpha, 1, strength^2)), btdf the GGX refraction lobe (Walter et al.
// 2007, weighted by 1 - F(wo.m) per microfacet), dt the diffuse transmission
// (KHR_materials_diffuse_transmission, a thin Lambertian sheet) and
//   F = specular * mix(F0 * specularColor -> 1 by the exact dielectric Fresnel's rise, film)
// the dielectric's reflectance: the exact Fresnel for `ior` (the specification allows Schlick;
// the exact form costs little and matches the glass shader), tinted at normal incidence by
// KHR_materials_specular's colour and scaled by its strength, mixed by the iridescence factor
// with a thin film's reflectance (KHR_materials_iridescence, materials/layers.h). F_metal is
// Schlick's from the base colour (or a film on it), F_coat the exact Fresnel for index 1.5,
// E_sheen the sheen's directional albedo (tabulated). The coat has its own normal (its normal
// map, or the surface's normal before the base's normal map). E_spec is the directional albedo
// of the dielectric's Fresnel-weighted spec lobe (F(wo.n) when smooth), E_spec,avg its cosine-
// weighted average, and ms Kulla and Conty's multiple-scattering lobe
//   ms = (1 - E(wo)) (1 - E(wi)) / (pi (1 - E_avg)),  F_ms = F_avg^2 E_avg / (1 - F_avg (1 -
//   E_avg))
// with E the GGX albedo for F = 1 and F_avg = F0 + (1 - F0) / 21 (Schlick's, from the base
// colour); the albedos are tabulated (microfacet_albedo.h).
//
// Deliberate changes, each for energy conservation or a ray tracer's needs:
//   - The diffuse part gets what the specular reflection leaves, by the albedo scaling S, not
//     the specification's 1 - F(wo.h) (fresnel_mix), which the specification itself notes is
//     not energy conserving (it reached an albedo of 1.68 at grazing angles in the white
//     furnace test) and which loses the light the single-scattering GGX lobe drops. With S a
//     white dielectric reflects everything at every roughness and view, S is reciprocal, and a
//     smooth surface (E_spec = F) keeps the classic (1 - F(wo)) (1 - F(wi)) / (1 - F_avg) of a
//     diffuse body under a clear interface. The specification's Appendix B allows this: its
//     BRDF is "a simplification", and the Khronos sample viewer's image-based lighting
//     weights its diffuse by the same idea, one minus the specular lobe's directional albedo
//     (Fdez-Aguera's multiple-scattering split sum).
//   - A rough metal gets Kulla and Conty's multiple-scattering lobe: a white rough metal then
//     reflects everything too (single scattering kept 0.31 at roughness 1 and normal incidence).
//     Rough refraction (transmission) has no such compensation yet and still loses light.
//   - Anisotropic and iridescent materials read the tables approximately (the geometric-mean
//     roughness; a film's reflectance times E), within the furnace tests' tolerances.
//   - The layers' albedo scalings (sheen, coat) use wo alone, so that every weight is a
//     property of the BSDF's construction, and the furnace test can check them.
// Transmission refracts when the material has a volume (KHR_materials_volume with a thickness
// above 0: then the inside absorbs, see absorption()); without one the surface is a thin sheet
// (thinWalled), as the extension says: light passes without bending. Dispersion
// (KHR_materials_dispersion) splits a refraction into the three colour channels, each with
// its own index, one channel per sampled path (PbrBxdf's channel choice).
//
// Roughness below ~0.03 (alpha < 1e-3) cannot be sampled or integrated in float; where a hit's
// roughness (constant or from the texture) is that low, the specular reflection and refraction
// are delta lobes, so that mirrors and clear glass from glTF render as such in the Whitted
// integrator too. The same holds for the coat.
#pragma once

#include <memory>

#include "materials/bump.h"
#include "materials/material.h"

namespace glint {

struct PbrParams {
  ColorParam baseColor;
  FloatParam metallic{1}, roughness{1};  // glTF: metallicRoughnessTexture B and G channels
  ColorParam emission{{0, 0, 0}};
  float ior = 1.5f;
  FloatParam transmission{0};
  bool thinWalled = false;  // transmission through a thin sheet (no volume, no refraction)
  // KHR_materials_volume: the inside's absorption coefficient per unit length (world units),
  // -ln(attenuationColor) / attenuationDistance; zero when clear.
  Rgb absorption{0, 0, 0};
  FloatParam specular{1};  // KHR_materials_specular (texture A) and colour (sRGB texture)
  ColorParam specularColor;
  FloatParam clearcoat{0}, clearcoatRoughness{0};  // KHR_materials_clearcoat (R, G channels)
  const Texture* clearcoatNormal = nullptr;        // tangent-space normal map of the coat
  float clearcoatNormalScale = 1;
  ColorParam sheenColor{{0, 0, 0}};   // KHR_materials_sheen (sRGB texture)
  FloatParam sheenRoughness{0};       //   (texture A)
  FloatParam diffuseTransmission{0};  // KHR_materials_diffuse_transmission (texture A)
  ColorParam diffuseTransmissionColor;
  FloatParam iridescence{0};  // KHR_materials_iridescence (texture R)
  float iridescenceIor = 1.3f;
  float iridescenceThicknessMin = 100, iridescenceThicknessMax = 400;  // nm
  const Texture* iridescenceThickness = nullptr;  // G: from min (0) to max (1); none: max
  float anisotropy = 0, anisotropyRotation = 0;   // KHR_materials_anisotropy (radians)
  const Texture* anisotropyTexture = nullptr;     // RG: direction in tangent space, B: strength
  float dispersion = 0;                           // KHR_materials_dispersion
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
  Rgb absorption() const override { return p_.absorption; }

 protected:
  void setLobes(const SurfaceInteraction& si, TextureLookups& lookups, Bsdf* bsdf) const override;

 private:
  PbrParams p_;
  uint32_t flags_;
  std::unique_ptr<NormalMap> coatNormalMap_;
};

}  // namespace glint
