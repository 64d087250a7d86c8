// glint — the glTF metallic-roughness microfacet BSDF.
#include "materials/pbr.h"

#include "geometry/sampling.h"
#include "materials/microfacet.h"
#include "materials/scattering.h"

namespace glint {

namespace {

// Schlick's Fresnel for conductors with reflectance f0 at normal incidence (glTF's metal).
Rgb schlick(Rgb f0, float cosTheta) {
  const float m = std::clamp(1 - cosTheta, 0.0f, 1.0f);
  const float m5 = (m * m) * (m * m) * m;
  return f0 + (Rgb{1, 1, 1} - f0) * m5;
}

float square(float v) { return v * v; }

// The least share (1 - Fresnel) the lobe selection gives rough transmission (see lobesAt).
constexpr float kMinRoughTransmissionWeight = 0.2f;

}  // namespace

// Everything about the material at one hit, in the local shading frame (ns = +Z, wo.z > 0).
struct PbrMaterial::Lobes {
  Frame frame;
  Vec3f wo;
  Rgb base;
  float metallic = 0, transmission = 0, alpha = 1;
  bool smooth = false;  // alpha below the delta threshold: specular lobes are deltas here
  float eta = 1.5f;     // relative index of refraction across the surface, seen from wo's side
  // Probabilities of sampling the specular reflection, diffuse and transmission lobes
  // (zero for lobes not allowed), summing to 1 unless every lobe is excluded.
  float pSpec = 0, pDiff = 0, pTrans = 0;
  bool valid() const { return wo.z > 0 && pSpec + pDiff + pTrans > 0; }
};

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
}

PbrMaterial::Lobes PbrMaterial::lobesAt(const SurfaceInteraction& si, uint32_t allowed) const {
  Lobes l;
  l.frame = Frame::fromZ(si.ns);
  l.wo = l.frame.toLocal(si.wo);
  l.base = p_.baseColor.evaluate(si);
  float metallic = p_.metallic.factor, roughness = p_.roughness.factor;
  if (p_.metallic.texture && p_.metallic.texture == p_.roughness.texture &&
      p_.metallic.channel >= 0 && p_.roughness.channel >= 0) {
    // glTF's metallicRoughnessTexture holds both: one lookup, two channels.
    const Vec4f mr = p_.metallic.texture->evaluate(TexturePoint(si));
    metallic *= mr[p_.metallic.channel];
    roughness *= mr[p_.roughness.channel];
  } else {
    metallic = p_.metallic.evaluate(si);
    roughness = p_.roughness.evaluate(si);
  }
  l.metallic = std::clamp(metallic, 0.0f, 1.0f);
  l.transmission = std::clamp(p_.transmission.evaluate(si), 0.0f, 1.0f);
  l.alpha = TrowbridgeReitzDistribution::roughnessToAlpha(std::clamp(roughness, 0.0f, 1.0f));
  l.smooth = TrowbridgeReitzDistribution(l.alpha).effectivelySmooth();
  // An opaque surface has no inside: both faces see air against the material's index.
  l.eta = l.transmission > 0 && !si.frontFace ? 1 / p_.ior : p_.ior;

  // Lobe weights from the Fresnel reflectance at wo (the microfacet normals scatter around ns).
  const float fd = fresnelDielectric(std::max(l.wo.z, 0.0f), l.eta);
  const float dielectric = 1 - l.metallic;
  float wSpec = l.metallic + dielectric * fd;
  float wDiff = dielectric * (1 - l.transmission) * (1 - fd) * std::max(luminance(l.base), 0.0f);
  // A rough surface transmits through tilted microfacets even where the macro-surface reflects
  // totally (fd = 1 seen from inside past the critical angle): the transmission lobe keeps a
  // minimum weight there, or sample() would never reach light that eval() says passes.
  const float fdTransmission = l.smooth ? fd : std::min(fd, 1 - kMinRoughTransmissionWeight);
  float wTrans = dielectric * l.transmission * (1 - fdTransmission);
  if (!(allowed & kBsdfReflection)) wSpec = wDiff = 0;
  if (!(allowed & kBsdfTransmission)) wTrans = 0;
  if (allowed & kBsdfSpecular) {  // only the delta lobes
    wDiff = 0;
    if (!l.smooth) wSpec = wTrans = 0;
  }
  const float sum = wSpec + wDiff + wTrans;
  if (sum > 0) l.pSpec = wSpec / sum, l.pDiff = wDiff / sum, l.pTrans = wTrans / sum;
  return l;
}

Rgb PbrMaterial::evalLocal(const Lobes& l, Vec3f wo, Vec3f wi) const {
  const float dielectric = 1 - l.metallic;
  if (l.smooth) {
    // Only the diffuse lobe is not a delta; it gets what the mirror lobe leaves at wo.
    if (wi.z <= 0) return {};
    const float fd = fresnelDielectric(wo.z, l.eta);
    return l.base * (dielectric * (1 - l.transmission) * (1 - fd) * kInvPi);
  }
  const TrowbridgeReitzDistribution distribution(l.alpha);
  if (wi.z > 0) {
    Vec3f h = wo + wi;
    if (lengthSquared(h) == 0) return {};
    h = normalize(h);
    const float cosH = std::max(dot(wo, h), 0.0f);
    const float spec = distribution.D(h) * distribution.G(wo, wi) / (4 * wo.z * wi.z);
    const float fd = fresnelDielectric(cosH, l.eta);
    const Rgb metal = schlick(l.base, cosH) * spec;
    // The diffuse layer gets what the interface does not reflect at wo, 1 - F(wo.n), as in
    // the smooth case and the lobe weights above, not glTF's 1 - F(wo.h): the half-vector
    // coupling is not energy conserving (glTF 2.0, B.3.6.3; a white surface reflected up to
    // 1.7 times the light at grazing angles), and from inside a transmitting surface past
    // the critical angle it was non-zero where the diffuse lobe is never sampled.
    const float fdView = fresnelDielectric(wo.z, l.eta);
    const Rgb plastic =
        Rgb{1, 1, 1} * (fd * spec) + l.base * ((1 - l.transmission) * (1 - fdView) * kInvPi);
    return metal * l.metallic + plastic * dielectric;
  }
  if (l.transmission <= 0 || dielectric <= 0) return {};
  // Refraction through a microfacet: the generalized half vector of Walter et al. (2007).
  Vec3f wm = wi * l.eta + wo;
  if (wi.z == 0 || lengthSquared(wm) == 0) return {};
  wm = normalize(wm);
  if (wm.z < 0) wm = -wm;
  const float wiM = dot(wi, wm), woM = dot(wo, wm);
  if (wiM * wi.z <= 0 || woM * wo.z <= 0) return {};  // back-facing microfacet
  const float fd = fresnelDielectric(woM, l.eta);
  const float denom = square(wiM + woM / l.eta) * wi.z * wo.z;
  const float ft = distribution.D(wm) * distribution.G(wo, wi) * (1 - fd) *
                   std::abs(wiM * woM / denom) / square(l.eta);
  return l.base * (dielectric * l.transmission * ft);
}

float PbrMaterial::pdfLocal(const Lobes& l, Vec3f wo, Vec3f wi) const {
  if (l.smooth) return wi.z > 0 ? l.pDiff * cosineHemispherePdf(wi.z) : 0;
  const TrowbridgeReitzDistribution distribution(l.alpha);
  if (wi.z > 0) {
    Vec3f h = wo + wi;
    float pdf = l.pDiff * cosineHemispherePdf(wi.z);
    if (l.pSpec > 0 && lengthSquared(h) > 0) {
      h = normalize(h);
      const float woH = dot(wo, h);
      if (woH > 0) pdf += l.pSpec * distribution.PDF(wo, h) / (4 * woH);
    }
    return pdf;
  }
  if (l.pTrans <= 0) return 0;
  Vec3f wm = wi * l.eta + wo;
  if (wi.z == 0 || lengthSquared(wm) == 0) return 0;
  wm = normalize(wm);
  if (wm.z < 0) wm = -wm;
  const float wiM = dot(wi, wm), woM = dot(wo, wm);
  if (wiM * wi.z <= 0 || woM * wo.z <= 0) return 0;
  const float dwmDwi = std::abs(wiM) / square(wiM + woM / l.eta);
  return l.pTrans * distribution.PDF(wo, wm) * dwmDwi;
}

namespace {
// Reflection and transmission must agree between the shading frame (local z) and the
// geometric normal (ng faces wo), or light would leak through the surface.
bool consistentSide(const SurfaceInteraction& si, Vec3f wiWorld, float localZ) {
  const float g = dot(wiWorld, si.ng);
  return localZ > 0 ? g > 0 : g < 0;
}
}  // namespace

Rgb PbrMaterial::evalBsdf(const SurfaceInteraction& si, Vec3f wi) const {
  const Lobes l = lobesAt(si, kBsdfAllLobes);
  if (l.wo.z <= 0) return {};
  const Vec3f wiLocal = l.frame.toLocal(wi);
  if (!consistentSide(si, wi, wiLocal.z)) return {};
  return evalLocal(l, l.wo, wiLocal);
}

float PbrMaterial::pdfBsdf(const SurfaceInteraction& si, Vec3f wi) const {
  const Lobes l = lobesAt(si, kBsdfAllLobes);
  if (!l.valid()) return 0;
  const Vec3f wiLocal = l.frame.toLocal(wi);
  if (!consistentSide(si, wi, wiLocal.z)) return 0;
  return pdfLocal(l, l.wo, wiLocal);
}

std::optional<BsdfSample> PbrMaterial::sampleBsdf(const SurfaceInteraction& si, Vec2f u,
                                                  float uLobe, uint32_t lobes) const {
  const Lobes l = lobesAt(si, lobes);
  if (!l.valid()) return std::nullopt;
  const Vec3f wo = l.wo;
  const float dielectric = 1 - l.metallic;
  enum {
    kSpec,
    kDiff,
    kTrans
  } lobe = uLobe < l.pSpec             ? kSpec
           : uLobe < l.pSpec + l.pDiff ? kDiff
                                       : kTrans;
  if (lobe == kTrans && l.pTrans <= 0) lobe = l.pDiff > 0 ? kDiff : kSpec;  // rounding at 1

  Vec3f wi;
  BsdfSample s;
  if (l.smooth && lobe != kDiff) {
    // Delta lobes: the mirror direction, or the refracted one.
    if (lobe == kSpec) {
      wi = {-wo.x, -wo.y, wo.z};
      const Rgb F = schlick(l.base, wo.z) * l.metallic +
                    Rgb{1, 1, 1} * (dielectric * fresnelDielectric(wo.z, l.eta));
      s = {F / wi.z, {}, l.pSpec, kBsdfSpecular | kBsdfReflection};
    } else {
      float etaCrossed = 1;
      if (!refract(wo, {0, 0, 1}, l.eta, &etaCrossed, &wi)) return std::nullopt;
      const float T = 1 - fresnelDielectric(wo.z, l.eta);
      s = {l.base * (dielectric * l.transmission * T / (std::abs(wi.z) * square(etaCrossed))),
           {},
           l.pTrans,
           kBsdfSpecular | kBsdfTransmission,
           etaCrossed};
    }
  } else {
    const TrowbridgeReitzDistribution distribution(l.alpha);
    if (lobe == kDiff) {
      wi = sampleCosineHemisphere(u);
      s.flags = kBsdfDiffuse | kBsdfReflection;
    } else if (lobe == kSpec) {
      const Vec3f wm = distribution.Sample_wm(wo, u);
      wi = reflect(wo, wm);
      if (wi.z <= 0) return std::nullopt;
      s.flags = kBsdfGlossy | kBsdfReflection;
    } else {
      const Vec3f wm = distribution.Sample_wm(wo, u);
      float etaCrossed = 1;
      if (!refract(wo, wm, l.eta, &etaCrossed, &wi) || wi.z >= 0) return std::nullopt;
      s.flags = kBsdfGlossy | kBsdfTransmission;
      s.eta = etaCrossed;
    }
    s.f = evalLocal(l, wo, wi);
    s.pdf = pdfLocal(l, wo, wi);
    if (!(s.pdf > 0)) return std::nullopt;
  }
  s.wi = l.frame.fromLocal(wi);
  if ((s.flags & kBsdfSpecular) && (s.flags & kBsdfReflection) && dot(s.wi, si.ng) <= 0) {
    // A mirror direction about a strongly tilted shading normal (normal maps, coarse smooth
    // meshes) can point into the surface; fold it back above the geometric plane rather than
    // lose it (a lost ray shows as a black fringe on mirrors).
    s.wi = normalize(s.wi - si.ng * (2 * dot(s.wi, si.ng)));
    return s;
  }
  if (!consistentSide(si, s.wi, wi.z)) return std::nullopt;
  return s;
}

}  // namespace glint
