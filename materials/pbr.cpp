// glint — the glTF metallic-roughness material and its extensions: parameters read once per hit.
#include "materials/pbr.h"

#include "materials/microfacet.h"

namespace glint {

namespace {
bool isSmooth(float roughness) {
  return TrowbridgeReitzDistribution(TrowbridgeReitzDistribution::roughnessToAlpha(roughness))
      .effectivelySmooth();
}
}  // namespace

PbrMaterial::PbrMaterial(const PbrParams& params) : p_(params) {
  for (const ColorParam* c : {&p_.baseColor, &p_.emission, &p_.specularColor, &p_.sheenColor,
                              &p_.diffuseTransmissionColor})
    uses(*c);
  for (const FloatParam* f :
       {&p_.metallic, &p_.roughness, &p_.transmission, &p_.specular, &p_.clearcoat,
        &p_.clearcoatRoughness, &p_.sheenRoughness, &p_.diffuseTransmission, &p_.iridescence})
    uses(*f);
  uses(p_.clearcoatNormal);
  uses(p_.iridescenceThickness);
  uses(p_.anisotropyTexture);
  if (p_.clearcoatNormal) {
    coatNormalMap_ = std::make_unique<NormalMap>(p_.clearcoatNormal, p_.clearcoatNormalScale);
    traits_.needs.tangents = true;
  }
  if (p_.anisotropy > 0) traits_.needs.tangents = true;
  traits_.emits = !p_.emission.isBlack();
  const bool transmits = p_.transmission.texture || p_.transmission.factor > 0;
  const bool diffuseTransmits = p_.diffuseTransmission.texture || p_.diffuseTransmission.factor > 0;
  traits_.refraction = transmits;
  // Smoothness is decided per hit (a roughness texture may hold both); the flags say which
  // kinds of lobes the material can have anywhere.
  const bool smoothFactor = isSmooth(p_.roughness.factor) && p_.anisotropy <= 0;
  flags_ = kBsdfReflection | kBsdfDiffuse;
  if (p_.roughness.texture || smoothFactor) flags_ |= kBsdfSpecular;
  if (p_.roughness.texture || !smoothFactor) flags_ |= kBsdfGlossy;
  if (transmits || diffuseTransmits) flags_ |= kBsdfTransmission;
  const bool coated = p_.clearcoat.texture || p_.clearcoat.factor > 0;
  if (coated) {
    const bool coatSmooth = isSmooth(p_.clearcoatRoughness.factor);
    if (p_.clearcoatRoughness.texture || coatSmooth) flags_ |= kBsdfSpecular;
    if (p_.clearcoatRoughness.texture || !coatSmooth) flags_ |= kBsdfGlossy;
  }
  if (!p_.sheenColor.isBlack()) flags_ |= kBsdfGlossy;
  traits_.glossyMetal =
      ((flags_ & kBsdfGlossy) && (p_.metallic.texture || p_.metallic.factor > 0)) || coated ||
      !p_.sheenColor.isBlack();
}

void PbrMaterial::setLobes(const SurfaceInteraction& si, TextureLookups& lookups,
                           Bsdf* bsdf) const {
  const BsdfFrame& frame = bsdf->buildLocalFrame(si);
  PbrHit h;
  h.base = p_.baseColor.evaluate(si, lookups);
  // glTF's metallicRoughnessTexture holds both in one image: TextureLookups reads it once.
  h.metallic = p_.metallic.evaluate(lookups);
  h.roughness = p_.roughness.evaluate(lookups);
  h.transmission = p_.transmission.evaluate(lookups);
  h.thinWalled = p_.thinWalled;
  // An opaque surface, or a thin sheet, has no inside: both faces see air against the index.
  const bool inside = h.transmission > 0 && !p_.thinWalled && !si.frontFace;
  h.eta = inside ? 1 / p_.ior : p_.ior;
  h.specular = p_.specular.evaluate(lookups);
  h.specularColor = p_.specularColor.evaluate(si, lookups);
  h.diffuseTransmission = p_.diffuseTransmission.evaluate(lookups);
  if (h.diffuseTransmission > 0)
    h.diffuseTransmissionColor = p_.diffuseTransmissionColor.evaluate(si, lookups);
  if (!p_.thinWalled) h.dispersion = p_.dispersion;
  if (p_.anisotropy > 0) {
    // The direction in tangent space (the texture's, turned by the rotation), then in the
    // BSDF's local frame.
    float strength = p_.anisotropy;
    Vec2f dir{1, 0};
    if (p_.anisotropyTexture) {
      const Vec4f c = lookups(p_.anisotropyTexture);
      dir = {2 * c.x - 1, 2 * c.y - 1};
      strength *= c.z;
    }
    const float cr = std::cos(p_.anisotropyRotation), sr = std::sin(p_.anisotropyRotation);
    dir = {cr * dir.x - sr * dir.y, sr * dir.x + cr * dir.y};
    const Vec3f n = si.ns;
    Vec3f t, b;
    if (tangentFrame(si, si.frontFace ? n : -n, &t, &b)) {
      const Vec3f local = frame.local.toLocal(t * dir.x + b * dir.y);
      h.anisotropy = strength;
      h.anisotropyDirection = {local.x, local.y};
    }
  }
  // The layers on top face the outside: a ray inside a transmitting object does not see them.
  if (!inside) {
    h.clearcoat = p_.clearcoat.evaluate(lookups);
    if (h.clearcoat > 0) {
      h.clearcoatRoughness = p_.clearcoatRoughness.evaluate(lookups);
      // The coat's normal: its own normal map on the surface's normal, or that normal before
      // the base's normal map.
      SurfaceInteraction coat = si;
      if (perturbsNormal()) coat.ns = si.nsUnperturbed;
      if (coatNormalMap_) coatNormalMap_->apply(coat);
      h.coatNormal = frame.local.toLocal(coat.ns);
    }
    h.sheenColor = p_.sheenColor.evaluate(si, lookups);
    if (h.sheenColor != Rgb{0, 0, 0}) h.sheenRoughness = p_.sheenRoughness.evaluate(lookups);
    h.iridescence = p_.iridescence.evaluate(lookups);
    if (h.iridescence > 0) {
      h.iridescenceIor = p_.iridescenceIor;
      float t = 1;
      if (p_.iridescenceThickness) t = lookups(p_.iridescenceThickness).y;
      h.iridescenceThickness = p_.iridescenceThicknessMin +
                               (p_.iridescenceThicknessMax - p_.iridescenceThicknessMin) * t;
    }
  }
  bsdf->emplace<PbrBxdf>(frame.woLocal, h);
}

}  // namespace glint
