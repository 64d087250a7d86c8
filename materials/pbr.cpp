// glint — the glTF metallic-roughness material: its parameters, read once per hit.
#include "materials/pbr.h"

#include "materials/microfacet.h"

namespace glint {

PbrMaterial::PbrMaterial(const PbrParams& params) : p_(params) {
  uses(p_.baseColor);
  uses(p_.metallic);
  uses(p_.roughness);
  uses(p_.emission);
  uses(p_.transmission);
  traits_.emits = !p_.emission.isBlack();
  const bool transmits = p_.transmission.texture || p_.transmission.factor > 0;
  traits_.refraction = transmits;
  // Smoothness is decided per hit (a roughness texture may hold both); the flags say which
  // kinds of lobes the material can have anywhere.
  const bool smoothFactor = TrowbridgeReitzDistribution(
                                TrowbridgeReitzDistribution::roughnessToAlpha(p_.roughness.factor))
                                .effectivelySmooth();
  flags_ = kBsdfReflection | kBsdfDiffuse;
  if (p_.roughness.texture || smoothFactor) flags_ |= kBsdfSpecular;
  if (p_.roughness.texture || !smoothFactor) flags_ |= kBsdfGlossy;
  if (transmits) flags_ |= kBsdfTransmission;
  traits_.glossyMetal =
      (flags_ & kBsdfGlossy) && (p_.metallic.texture || p_.metallic.factor > 0);
}

Bsdf PbrMaterial::makeBsdf(const SurfaceInteraction& si, const BsdfFrame& frame,
                           TextureLookups& lookups) const {
  const float transmission = p_.transmission.evaluate(lookups);
  // An opaque surface has no inside: both faces see air against the material's index.
  const float eta = transmission > 0 && !si.frontFace ? 1 / p_.ior : p_.ior;
  // glTF's metallicRoughnessTexture holds both in one image: TextureLookups reads it once.
  return Bsdf(frame,
              PbrBxdf(frame.wo, p_.baseColor.evaluate(si, lookups), p_.metallic.evaluate(lookups),
                      p_.roughness.evaluate(lookups), transmission, eta));
}

}  // namespace glint
