// glint — the BxDFs too large to inline (Phong and Blinn-Phong, glTF's metallic-roughness
// microfacet model; diffuse, mirror and glass are in the header) and the parts of Bsdf that are
// not in its inner loop (the dispatch of evaluate and sample is inline, in bsdf.h).
#include "materials/bxdfs.h"

#include <algorithm>
#include <cmath>

#include "geometry/sampling.h"
#include "materials/bsdf.h"
#include "materials/layers.h"
#include "materials/microfacet.h"
#include "materials/microfacet_albedo.h"
#include "materials/scattering.h"

namespace glint {

namespace {

float square(float v) { return v * v; }

// The mirror direction of w about the local normal +Z.
Vec3f mirrorLocal(Vec3f w) { return {-w.x, -w.y, w.z}; }

// Schlick's Fresnel for conductors with reflectance f0 at normal incidence (glTF's metal).
Rgb schlick(Rgb f0, float cosTheta) {
  const float m = std::clamp(1 - cosTheta, 0.0f, 1.0f);
  const float m5 = (m * m) * (m * m) * m;
  return f0 + (Rgb{1, 1, 1} - f0) * m5;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Phong and Blinn-Phong
// ---------------------------------------------------------------------------------------------

PhongBxdf::PhongBxdf(Rgb kd_, Rgb ks_, float shininess_, bool blinn_) noexcept
    : kd(kd_), ks(ks_), shininess(shininess_), blinn(blinn_) {
  // Lobes chosen by their largest channel, not their luminance: a sample's weight in any channel
  // is then at most d + s (a red diffuse under a grey highlight chosen by luminance weighed
  // 1.6 in red).
  const float d = maxComponent(kd), s = maxComponent(ks);
  pSpecular = d + s > 0 ? s / (d + s) : 0;
}

Rgb PhongBxdf::evaluate(Vec3f wo, Vec3f wi, float* pdf) const {
  *pdf = 0;
  if (wi.z <= 0) return {};
  const float n = shininess;
  // The specular lobe's value (without ks) and its sampling density share cos^n.
  float lobe = 0, lobePdf = 0;
  if (!blinn) {
    const float cosAlpha = dot(mirrorLocal(wo), wi);
    if (cosAlpha > 0) {
      const float c = std::pow(cosAlpha, n);
      lobe = (n + 2) / (2 * kPi) * c;
      lobePdf = (n + 1) / (2 * kPi) * c;
    }
  } else {
    Vec3f h = wo + wi;
    if (lengthSquared(h) > 0) {
      h = normalize(h);
      const float cosH = h.z, hDotWi = dot(h, wi), hDotWo = dot(h, wo);
      if (cosH > 0) {
        const float c = std::pow(cosH, n);
        const float denominator = hDotWi * std::max(wi.z, wo.z);
        if (denominator > 0) lobe = (n + 1) / (8 * kPi) * c / denominator;
        // Half vectors are drawn with density (n+1)/(2 pi) cos^n(theta_h); the Jacobian of
        // reflection about h is 1 / (4 h.wo).
        if (hDotWo > 0) lobePdf = (n + 1) / (2 * kPi) * c / (4 * hDotWo);
      }
    }
  }
  *pdf = (1 - pSpecular) * cosineHemispherePdf(wi.z) + pSpecular * lobePdf;
  return kd * kInvPi + ks * lobe;
}

bool PhongBxdf::sample(Vec3f wo, Vec2f u, float uLobe, uint32_t lobes, BsdfSample* s) const {
  if (!(lobes & kBsdfReflection) || (lobes & kBsdfSpecular)) return false;
  Vec3f wi;
  if (uLobe < pSpecular) {
    // A cos^n lobe around the mirror direction (Phong) or the normal (Blinn's half vector):
    // cos = u^(1/(n+1)).
    const float cosA = std::pow(u.x, 1 / (shininess + 1));
    const float sinA = std::sqrt(std::max(0.0f, 1 - cosA * cosA));
    const float phi = 2 * kPi * u.y;
    const Vec3f local{sinA * std::cos(phi), sinA * std::sin(phi), cosA};
    wi = blinn ? reflect(wo, local) : Frame::fromZ(mirrorLocal(wo)).fromLocal(local);
  } else {
    wi = sampleCosineHemisphere(u);
  }
  if (wi.z <= 0) return false;
  float p;
  const Rgb f = evaluate(wo, wi, &p);
  if (!(p > 0)) return false;
  *s = {f, wi, p, kBsdfGlossy | kBsdfReflection};
  return true;
}

// ---------------------------------------------------------------------------------------------
// glTF metallic-roughness
// ---------------------------------------------------------------------------------------------

namespace {
float mean(Rgb c) { return (c.x + c.y + c.z) / 3; }
Rgb clamp01(Rgb c) {
  return {std::clamp(c.x, 0.0f, 1.0f), std::clamp(c.y, 0.0f, 1.0f), std::clamp(c.z, 0.0f, 1.0f)};
}
const Rgb kOne{1, 1, 1};
// The normal-incidence reflectance of an interface of relative index eta.
float f0FromEta(float eta) { return square((eta - 1) / (eta + 1)); }
// KHR_materials_specular changes the dielectric's reflectance (a colour or strength not 1).
bool tintedSpecular(const PbrHit& hit) { return hit.specularColor != kOne || hit.specular != 1; }
}  // namespace

PbrBxdf::PbrBxdf(Vec3f wo, Rgb base_, float metallic_, float roughness, float transmission_,
                 float eta_) noexcept
    : PbrBxdf(wo, [&] {
        PbrHit h;
        h.base = base_;
        h.metallic = metallic_;
        h.roughness = roughness;
        h.transmission = transmission_;
        h.eta = eta_;
        return h;
      }()) {}

PbrBxdf::PbrBxdf(Vec3f wo, const PbrHit& h) noexcept : hit(h) {
  hit.metallic = std::clamp(hit.metallic, 0.0f, 1.0f);
  hit.transmission = std::clamp(hit.transmission, 0.0f, 1.0f);
  hit.specular = std::clamp(hit.specular, 0.0f, 1.0f);
  hit.clearcoat = std::clamp(hit.clearcoat, 0.0f, 1.0f);
  hit.diffuseTransmission = std::clamp(hit.diffuseTransmission, 0.0f, 1.0f);
  hit.iridescence = std::clamp(hit.iridescence, 0.0f, 1.0f);
  hit.anisotropy = std::clamp(hit.anisotropy, 0.0f, 1.0f);
  hit.sheenColor = max(hit.sheenColor, Rgb{0, 0, 0});
  const float alpha =
      TrowbridgeReitzDistribution::roughnessToAlpha(std::clamp(hit.roughness, 0.0f, 1.0f));
  alphaX = alphaY = alpha;
  const Vec2f d = hit.anisotropyDirection;
  const float dLength = std::sqrt(d.x * d.x + d.y * d.y);
  if (hit.anisotropy > 0 && dLength > 0 && std::isfinite(dLength)) {
    // KHR_materials_anisotropy: the roughness along the direction grows towards 1 with the
    // square of the strength; across it stays the base roughness. The local frame is turned so
    // that x is the direction.
    anisotropic = true;
    hit.anisotropyDirection = d * (1 / dLength);
    alphaX = alpha + (1 - alpha) * hit.anisotropy * hit.anisotropy;
  }
  smooth = TrowbridgeReitzDistribution(alphaX, alphaY).effectivelySmooth();
  tableRoughness_ = std::sqrt(std::sqrt(alphaX * alphaY));
  coatAlpha =
      TrowbridgeReitzDistribution::roughnessToAlpha(std::clamp(hit.clearcoatRoughness, 0.0f, 1.0f));
  coatSmooth = TrowbridgeReitzDistribution(coatAlpha).effectivelySmooth();
  // The coat's frame (its normal may differ from the base's shading normal).
  Vec3f cn = anisotropic ? toAniso(hit.coatNormal) : hit.coatNormal;
  if (!(lengthSquared(cn) > 0) || !isFinite(cn) || cn.z <= 0) cn = {0, 0, 1};
  cn = normalize(cn);
  if (cn.z > 0.999999f) {
    toCoat_[0] = {1, 0, 0}, toCoat_[1] = {0, 1, 0}, toCoat_[2] = {0, 0, 1};
  } else {
    const Frame f = Frame::fromZ(cn);
    toCoat_[0] = f.s, toCoat_[1] = f.t, toCoat_[2] = f.n;
  }

  if (anisotropic) wo = toAniso(wo);
  if (!(wo.z > 0)) return;  // seen from below its shading normal: black, never sampled
  // Lobe weights at wo: the layers' reflectances there (the microfacet normals scatter around
  // the macro normal).
  fresnelWo_ = dielectricFresnel(wo.z);
  const Vec3f woCoat = toCoat(wo);
  coatFresnelWo_ = hit.clearcoat > 0 && woCoat.z > 0 ? coatFresnel(woCoat.z) : 0;
  const float sheenMax = maxComponent(hit.sheenColor);
  const float sheenE = sheenMax > 0 ? sheenAlbedo(wo.z, hit.sheenRoughness) : 0;
  baseScaleWo_ = (1 - coatFresnelWo_) * (1 - sheenMax * sheenE);
  const float baseScale = baseScaleWo_;
  const float dielectric = 1 - hit.metallic;
  const float F = mean(fresnelWo_);
  const float opaque = 1 - hit.transmission;
  // The diffuse layer's albedo scaling and the metal's multiple scattering (pbr.h): their
  // parts that depend on wo alone. Their albedos at wo, (1 - E_spec(wo)) and
  // F_ms (1 - E(wo)), weight the two lobes that sample them (kDiff, kMulti).
  Rgb diffuseAlbedo, multipleAlbedo;
  if (dielectric * opaque > 0) {
    const Rgb eWo = dielectricAlbedo(wo.z), eAvg = dielectricAverageAlbedo();
    for (int c = 0; c < 3; ++c)
      diffuseScaleWo_[c] = eAvg[c] < 1 ? (1 - eWo[c]) / (1 - eAvg[c]) : 0.0f;
    diffuseAlbedo = kOne - eWo;
  }
  if (hit.metallic > 0 && !smooth) {
    // Kulla and Conty's F_ms = F_avg^2 E_avg / (1 - F_avg (1 - E_avg)) with Schlick's average
    // reflectance F_avg = F0 + (1 - F0) / 21 (F0 the base colour).
    const float eWo = ggxAlbedo(wo.z, tableRoughness_), eAvg = ggxAverageAlbedo(tableRoughness_);
    if (eAvg < 1) {
      const Rgb base = clamp01(hit.base);
      const Rgb fAvg = base + (kOne - base) * (1.0f / 21);
      Rgb fMs;
      for (int c = 0; c < 3; ++c) fMs[c] = square(fAvg[c]) * eAvg / (1 - fAvg[c] * (1 - eAvg));
      metalMultipleWo_ = fMs * ((1 - eWo) / (kPi * (1 - eAvg)));
      multipleAlbedo = fMs * (1 - eWo);
    }
  }
  w_[kCoat] = coatFresnelWo_;
  w_[kSheen] = (1 - coatFresnelWo_) * sheenMax * sheenE;
  // Each lobe weighs by its largest channel, so that a sample's weight f cos / pdf in any
  // channel stays below the sum of the weights, about the surface's albedo (by luminance, or
  // with the metal's reflectance taken as 1, a red metal's diffuse samples weighed 3 in red).
  w_[kSpec] = baseScale * (hit.metallic * maxComponent(metalFresnel(wo.z)) +
                           dielectric * maxComponent(fresnelWo_));
  w_[kDiff] = baseScale * std::max(dielectric * opaque * (1 - hit.diffuseTransmission) *
                                       maxComponent(hit.base * diffuseAlbedo),
                                   0.0f);
  w_[kMulti] = baseScale * std::max(hit.metallic * maxComponent(multipleAlbedo), 0.0f);
  w_[kDiffTrans] = baseScale * dielectric * opaque * hit.diffuseTransmission *
                   std::max(maxComponent(hit.diffuseTransmissionColor * diffuseAlbedo), 0.0f);
  // A rough interface chooses between reflection and refraction per microfacet (reflectShare),
  // so it transmits through tilted microfacets even where the macro-surface reflects totally
  // (F = 1 seen from inside past the critical angle): w[kSpec] + w[kTrans] is its weight.
  w_[kTrans] = baseScale * dielectric * hit.transmission * (1 - F);
  p_ = lobeProbabilities(kBsdfAllLobes);
}

Vec3f PbrBxdf::toAniso(Vec3f v) const {
  const Vec2f d = hit.anisotropyDirection;
  return {d.x * v.x + d.y * v.y, -d.y * v.x + d.x * v.y, v.z};
}

Vec3f PbrBxdf::fromAniso(Vec3f v) const {
  const Vec2f d = hit.anisotropyDirection;
  return {d.x * v.x - d.y * v.y, d.y * v.x + d.x * v.y, v.z};
}

Vec3f PbrBxdf::toCoat(Vec3f v) const {
  return {dot(toCoat_[0], v), dot(toCoat_[1], v), dot(toCoat_[2], v)};
}

Vec3f PbrBxdf::fromCoat(Vec3f v) const {
  return toCoat_[0] * v.x + toCoat_[1] * v.y + toCoat_[2] * v.z;
}

Rgb PbrBxdf::dielectricFresnel(float c) const { return dielectricFresnel(c, hit.eta); }

Rgb PbrBxdf::dielectricFresnel(float c, float eta) const {
  const float F = fresnelDielectric(c, eta);
  Rgb r{F, F, F};
  if (tintedSpecular(hit)) {
    // KHR_materials_specular: F0 tinted by the specular colour (at most 1), the exact
    // Fresnel's rise from F0 to 1 kept as the blend weight, all scaled by the strength.
    const float f0 = f0FromEta(eta);
    const float w = f0 < 1 ? std::clamp((F - f0) / (1 - f0), 0.0f, 1.0f) : 1.0f;
    const Rgb f0Tinted = min(hit.specularColor * f0, kOne);
    r = f0Tinted + (kOne - f0Tinted) * w;
  }
  if (hit.iridescence > 0)
    r = lerp(hit.iridescence, r,
             thinFilmFresnel(c, hit.iridescenceIor, Rgb{eta, eta, eta}, hit.iridescenceThickness));
  return clamp01(r * hit.specular);
}

Rgb PbrBxdf::metalFresnel(float c) const {
  const Rgb r = schlick(hit.base, c);
  if (!(hit.iridescence > 0)) return r;
  return lerp(hit.iridescence, r,
              thinFilmFresnel(c, hit.iridescenceIor,
                              {iorFromF0(hit.base.x), iorFromF0(hit.base.y), iorFromF0(hit.base.z)},
                              hit.iridescenceThickness));
}

float PbrBxdf::coatFresnel(float c) const { return hit.clearcoat * fresnelDielectric(c, 1.5f); }

namespace {
// E_spec from the bare interface's albedos: eF with the exact Fresnel for the index, e1 with
// F = 1 (both 1 when smooth and the eF the Fresnel reflectance), as dielectricFresnel() tints
// and scales F: KHR_materials_specular's F = F0' + (1 - F0') w with w = (F - F0) / (1 - F0)
// is linear in F, so its albedo is F0' e1 + (1 - F0') (eF - F0 e1) / (1 - F0). e1 is read
// only when tintedSpecular(hit).
Rgb specularAlbedo(const PbrHit& hit, float eF, float e1) {
  Rgb r{eF, eF, eF};
  if (tintedSpecular(hit)) {
    const float f0 = f0FromEta(hit.eta);
    const float ew = f0 < 1 ? std::clamp((eF - f0 * e1) / (1 - f0), 0.0f, e1) : e1;
    const Rgb f0Tinted = min(hit.specularColor * f0, kOne);
    r = f0Tinted * e1 + (kOne - f0Tinted) * ew;
  }
  return r;
}
}  // namespace

Rgb PbrBxdf::dielectricAlbedo(float mu) const {
  if (smooth) return dielectricFresnel(mu);
  Rgb r = specularAlbedo(hit, ggxDielectricAlbedo(mu, tableRoughness_, hit.eta),
                         tintedSpecular(hit) ? ggxAlbedo(mu, tableRoughness_) : 0.0f);
  if (hit.iridescence > 0)  // approximately: the film's reflectance at mu times E with F = 1
    r = lerp(hit.iridescence, r,
             thinFilmFresnel(mu, hit.iridescenceIor, Rgb{hit.eta, hit.eta, hit.eta},
                             hit.iridescenceThickness) *
                 ggxAlbedo(mu, tableRoughness_));
  return clamp01(r * hit.specular);
}

Rgb PbrBxdf::dielectricAverageAlbedo() const {
  if (hit.iridescence > 0) {
    // No table for a film: 2 int E(mu) mu dmu by 8-point Gauss-Legendre on [0, 1].
    static constexpr float kNodes[8] = {0.0198551f, 0.1016667f, 0.2372338f, 0.4082826f,
                                        0.5917174f, 0.7627662f, 0.8983333f, 0.9801449f};
    static constexpr float kWeights[8] = {0.0506143f, 0.1111905f, 0.1568533f, 0.1813419f,
                                          0.1813419f, 0.1568533f, 0.1111905f, 0.0506143f};
    Rgb sum;
    for (int i = 0; i < 8; ++i) sum += dielectricAlbedo(kNodes[i]) * (2 * kWeights[i] * kNodes[i]);
    return clamp01(sum);
  }
  const Rgb r =
      smooth ? specularAlbedo(hit, dielectricFresnelAverage(hit.eta), 1)
             : specularAlbedo(hit, ggxDielectricAverageAlbedo(tableRoughness_, hit.eta),
                              tintedSpecular(hit) ? ggxAverageAlbedo(tableRoughness_) : 0.0f);
  return clamp01(r * hit.specular);
}

PbrBxdf::LobeProbabilities PbrBxdf::lobeProbabilities(uint32_t lobes) const {
  LobeProbabilities r;
  float w[kLobeCount];
  std::copy(std::begin(w_), std::end(w_), w);
  if (!(lobes & kBsdfReflection)) w[kCoat] = w[kSheen] = w[kSpec] = w[kDiff] = w[kMulti] = 0;
  if (!(lobes & kBsdfTransmission)) w[kDiffTrans] = w[kTrans] = 0;
  if (lobes & kBsdfSpecular) {  // only the delta lobes
    w[kSheen] = w[kDiff] = w[kMulti] = w[kDiffTrans] = 0;
    if (!smooth) w[kSpec] = w[kTrans] = 0;
    if (!coatSmooth) w[kCoat] = 0;
  }
  float sum = 0;
  for (float v : w) sum += v;
  if (sum > 0)
    for (int i = 0; i < kLobeCount; ++i) r.p[i] = w[i] / sum;
  // A rough refracting interface (not a thin sheet's, whose 'refraction' is a mirrored
  // reflection through the sheet: same microfacet, same split).
  if (!smooth && hit.transmission > 0 && hit.metallic < 1 && !(lobes & kBsdfSpecular)) {
    r.reflects = (lobes & kBsdfReflection) != 0;
    r.refracts = (lobes & kBsdfTransmission) != 0;
    r.interface = r.p[kSpec] + r.p[kTrans];
    r.grouped = r.interface > 0;
  }
  return r;
}

float PbrBxdf::reflectShare(Vec3f wo, Vec3f wm, float eta, const LobeProbabilities& pr) const {
  if (!pr.refracts) return 1;
  if (!pr.reflects) return 0;
  // The two sides' weights at this microfacet, each by its largest channel (as the lobes'
  // weights at wo): a sample's weight is then about their sum over the share's own side.
  const float c = dot(wo, wm);
  const float dielectric = 1 - hit.metallic;
  const Rgb F = dielectricFresnel(c, eta);
  const float reflect = hit.metallic * maxComponent(metalFresnel(c)) + dielectric * maxComponent(F);
  const float refract =
      dielectric * hit.transmission * std::max(maxComponent(hit.base * (kOne - F)), 0.0f);
  if (!(reflect + refract > 0)) return 1;
  return reflect / (reflect + refract);
}

uint32_t PbrBxdf::flags() const {
  uint32_t f = kBsdfReflection;
  const float* p = p_.p;
  if (p[kDiff] > 0 || p[kMulti] > 0 || p[kDiffTrans] > 0) f |= kBsdfDiffuse;
  if (p[kSheen] > 0) f |= kBsdfGlossy;
  if (p[kSpec] > 0 || p[kTrans] > 0) f |= smooth ? kBsdfSpecular : kBsdfGlossy;
  if (p[kCoat] > 0) f |= coatSmooth ? kBsdfSpecular : kBsdfGlossy;
  if (p[kTrans] > 0 || p[kDiffTrans] > 0) f |= kBsdfTransmission;
  return f;
}

float PbrBxdf::narrowestAlpha() const {
  const float* p = p_.p;
  float a = 1;
  if (p[kSpec] > 0 || p[kTrans] > 0) a = smooth ? 0.0f : std::min({a, alphaX, alphaY});
  if (p[kCoat] > 0) a = std::min(a, coatSmooth ? 0.0f : coatAlpha);
  return a;
}

// The non-delta lobes at (wo, wi), both in the anisotropy-turned local frame, and the density
// of sample() for the lobe probabilities `pr` (sample() may restrict them). See pbr.h for the
// model.
PbrBxdf::Eval PbrBxdf::evaluateLocal(Vec3f wo, Vec3f wi, const LobeProbabilities& pr) const {
  Eval r;
  if (!(wo.z > 0)) return r;
  const float* p = pr.p;
  const float dielectric = 1 - hit.metallic;
  const float baseScale = baseScaleWo_;
  const float opaque = 1 - hit.transmission;
  const TrowbridgeReitzDistribution distribution(alphaX, alphaY);
  // The diffuse layers' albedo scaling at wi (pbr.h): 1 - E_spec(|wi.z|).
  auto diffuseScale = [&](float cosI) {
    return dielectric * opaque > 0 ? diffuseScaleWo_ * (kOne - dielectricAlbedo(cosI)) : Rgb{};
  };
  if (wi.z > 0) {
    // The diffuse layer gets what the interface does not reflect, in the reciprocal albedo
    // scaling form (1 - E_spec(wo)) (1 - E_spec(wi)) / (1 - E_spec,avg), not glTF's
    // 1 - F(wo.h): the half-vector coupling is not energy conserving (glTF 2.0, B.3.6.3; a
    // white surface reflected up to 1.7 times the light at grazing angles).
    Rgb f;
    if (dielectric * opaque * (1 - hit.diffuseTransmission) > 0)
      f = hit.base * diffuseScale(wi.z) *
          (dielectric * opaque * (1 - hit.diffuseTransmission) * kInvPi);
    if (metalMultipleWo_ != Rgb{})
      f += metalMultipleWo_ * (hit.metallic * (1 - ggxAlbedo(wi.z, tableRoughness_)));
    r.pdf = p[kDiff] * cosineHemispherePdf(wi.z) + p[kSheen] * uniformHemispherePdf(wi.z);
    if (p[kMulti] > 0) r.pdf += p[kMulti] * multipleScatteringPdf(wi.z, tableRoughness_);
    Vec3f h = wo + wi;
    if (lengthSquared(h) == 0) {
      r.f = f * baseScale;
      return r;
    }
    h = normalize(h);
    const float woH = dot(wo, h);
    if (!smooth) {
      const float cosH = std::max(woH, 0.0f);
      const float spec = distribution.D(h) * distribution.G(wo, wi) / (4 * wo.z * wi.z);
      f += metalFresnel(cosH) * (hit.metallic * spec) +
           dielectricFresnel(cosH) * (dielectric * spec);
      if (woH > 0) {
        const float pSpec = pr.grouped ? pr.interface * reflectShare(wo, h, hit.eta, pr) : p[kSpec];
        if (pSpec > 0) r.pdf += pSpec * distribution.PDF(wo, h) / (4 * woH);
      }
    }
    r.f = f * baseScale;
    if (hit.sheenColor != Rgb{0, 0, 0}) {
      const float sheenAlpha = std::max(square(hit.sheenRoughness), kMinSheenAlpha);
      r.f += hit.sheenColor * (sheenBrdf(wo.z, wi.z, h.z, sheenAlpha) * (1 - coatFresnelWo_));
    }
    if (hit.clearcoat > 0 && !coatSmooth) {
      const Vec3f woC = toCoat(wo), wiC = toCoat(wi), hC = toCoat(h);
      const float woHC = dot(woC, hC);
      if (woC.z > 0 && wiC.z > 0 && hC.z > 0) {
        const TrowbridgeReitzDistribution coat(coatAlpha);
        r.f += kOne * (coatFresnel(std::max(woHC, 0.0f)) * coat.D(hC) * coat.G(woC, wiC) /
                       (4 * woC.z * wiC.z));
        if (p[kCoat] > 0 && woHC > 0) r.pdf += p[kCoat] * coat.PDF(woC, hC) / (4 * woHC);
      }
    }
    return r;
  }
  if (wi.z == 0) return r;
  // Diffuse transmission: a thin Lambertian sheet of its own colour.
  if (hit.diffuseTransmission > 0) {
    r.f += hit.diffuseTransmissionColor * diffuseScale(-wi.z) *
           (baseScale * dielectric * opaque * hit.diffuseTransmission * kInvPi);
    r.pdf += p[kDiffTrans] * cosineHemispherePdf(-wi.z);
  }
  const bool transmits = hit.transmission > 0 && dielectric > 0;
  if (smooth || (!transmits && !(p[kTrans] > 0))) return r;
  const float weight = baseScale * dielectric * hit.transmission;
  if (hit.thinWalled) {
    // A thin sheet: the rough reflection's lobe, mirrored through the sheet (no refraction).
    const Vec3f wr{wi.x, wi.y, -wi.z};
    const Vec3f h = normalize(wo + wr);
    const float woH = dot(wo, h);
    if (!(woH > 0)) return r;
    if (transmits) {
      const float spec = distribution.D(h) * distribution.G(wo, wr) / (4 * wo.z * wr.z);
      r.f += hit.base * (kOne - dielectricFresnel(woH)) * (weight * spec);
    }
    const float pTrans =
        pr.grouped ? pr.interface * (1 - reflectShare(wo, h, hit.eta, pr)) : p[kTrans];
    if (pTrans > 0) r.pdf += pTrans * distribution.PDF(wo, h) / (4 * woH);
    return r;
  }
  // Refraction through a microfacet: the generalized half vector of Walter et al. (2007); with
  // dispersion, one per channel's index (sample() picks a channel with probability 1/3).
  const int channels = hit.dispersion > 0 ? 3 : 1;
  float pdfSum = 0;
  for (int c = 0; c < channels; ++c) {
    const float eta = channels == 1 ? hit.eta : channelEta(c);
    Vec3f wm = wi * eta + wo;
    if (lengthSquared(wm) == 0) continue;
    wm = normalize(wm);
    if (wm.z < 0) wm = -wm;
    const float wiM = dot(wi, wm), woM = dot(wo, wm);
    if (wiM * wi.z <= 0 || woM * wo.z <= 0) continue;  // back-facing microfacet
    const float denom = square(wiM + woM / eta);
    if (transmits) {
      const float ft = distribution.D(wm) * distribution.G(wo, wi) *
                       std::abs(wiM * woM / (denom * wi.z * wo.z)) / square(eta);
      const Rgb t = hit.base * (kOne - dielectricFresnel(woM, eta)) * (weight * ft);
      if (channels == 1)
        r.f += t;
      else
        r.f[c] += t[c];
    }
    // sample() splits by the index of the whole (hit.eta) before it picks a channel.
    const float share = pr.grouped ? 1 - reflectShare(wo, wm, hit.eta, pr) : 1.0f;
    pdfSum += share * distribution.PDF(wo, wm) * std::abs(wiM) / denom;
  }
  const float pTrans = pr.grouped ? pr.interface : p[kTrans];
  if (pTrans > 0) r.pdf += pTrans * pdfSum / float(channels);
  return r;
}

float PbrBxdf::channelEta(int c) const {
  // hit.eta is the index seen from wo's side: n outside-in, 1/n from inside.
  const bool inside = hit.eta < 1;
  const float n = inside ? 1 / hit.eta : hit.eta;
  const float nc = dispersedIor(n, hit.dispersion, kChannelWavelengthNm[c]);
  return inside ? 1 / nc : nc;
}

Rgb PbrBxdf::evaluate(Vec3f wo, Vec3f wi, float* pdf) const {
  if (anisotropic) wo = toAniso(wo), wi = toAniso(wi);
  const Eval e = evaluateLocal(wo, wi, p_);
  *pdf = e.pdf;
  return e.f;
}

bool PbrBxdf::sample(Vec3f wo, Vec2f u, float uLobe, uint32_t lobes, BsdfSample* out) const {
  if (anisotropic) wo = toAniso(wo);
  if (!(wo.z > 0)) return false;
  const LobeProbabilities pr = lobeProbabilities(lobes);
  const float* p = pr.p;
  int lobe = -1;
  float before = 0;
  for (int i = 0; i < kLobeCount; ++i) {
    if (!(p[i] > 0)) continue;
    lobe = i;  // the last lobe with a chance catches rounding at 1
    if (uLobe < before + p[i]) break;
    before += p[i];
  }
  if (lobe < 0) return false;
  // What is left of uLobe once the lobe is chosen: a uniform number for the dispersion channel.
  const float uRest = std::clamp((uLobe - before) / p[lobe], 0.0f, 0.99999994f);
  const float dielectric = 1 - hit.metallic;
  const float baseScale = baseScaleWo_;
  auto finish = [&](const BsdfSample& s) {
    *out = s;
    if (anisotropic) out->wi = fromAniso(out->wi);
    return true;
  };

  // Delta lobes. The base's mirror and a smooth coat on the same normal share one direction:
  // one sample carries both, with both probabilities.
  const bool coatSharesMirror = coatSmooth && toCoat_[2].z > 0.999999f;
  if ((lobe == kSpec && smooth) || (lobe == kCoat && coatSmooth)) {
    const bool base = smooth && (lobe == kSpec || coatSharesMirror);
    const bool coat = coatSmooth && (lobe == kCoat || coatSharesMirror);
    Vec3f wi;
    if (lobe == kSpec || coatSharesMirror) {
      wi = mirrorLocal(wo);
    } else {
      const Vec3f n = toCoat_[2];
      wi = n * (2 * dot(wo, n)) - wo;
      if (wi.z <= 0) return false;
    }
    Rgb F;
    float pdf = 0;
    if (base) {
      F += (metalFresnel(wo.z) * hit.metallic + fresnelWo_ * dielectric) * baseScale;
      pdf += p[kSpec];
    }
    if (coat) {
      F += kOne * coatFresnelWo_;
      pdf += p[kCoat];
    }
    return finish(BsdfSample{F / wi.z, wi, pdf, kBsdfSpecular | kBsdfReflection});
  }
  if (lobe == kTrans && smooth) {
    if (hit.thinWalled) {
      const Vec3f wi = -wo;
      return finish(BsdfSample{hit.base * (kOne - fresnelWo_) *
                                   (baseScale * dielectric * hit.transmission / std::abs(wi.z)),
                               wi, p[kTrans], kBsdfSpecular | kBsdfTransmission, 1});
    }
    const int channel = hit.dispersion > 0 ? std::min(int(uRest * 3), 2) : -1;
    const float eta = channel < 0 ? hit.eta : channelEta(channel);
    Vec3f wi;
    float etaCrossed = 1;
    if (!refract(wo, {0, 0, 1}, eta, &etaCrossed, &wi)) return false;
    const Rgb T = kOne - (channel < 0 ? fresnelWo_ : dielectricFresnel(wo.z, eta));
    Rgb f = hit.base * T *
            (baseScale * dielectric * hit.transmission / (std::abs(wi.z) * square(etaCrossed)));
    float pdf = p[kTrans];
    if (channel >= 0) {  // one channel's path, chosen with probability 1/3
      Rgb only;
      only[channel] = f[channel];
      f = only;
      pdf /= 3;
    }
    return finish(BsdfSample{f, wi, pdf, kBsdfSpecular | kBsdfTransmission, etaCrossed});
  }

  BsdfSample& s = *out;
  s.eta = 1;
  Vec3f wi;
  switch (lobe) {
    case kDiff:
      wi = sampleCosineHemisphere(u);
      s.flags = kBsdfDiffuse | kBsdfReflection;
      break;
    case kMulti: {
      float unused;
      const float mu = sampleMultipleScatteringCos(tableRoughness_, u.x, &unused);
      const float sinTheta = std::sqrt(std::max(0.0f, 1 - mu * mu));
      const float phi = 2 * kPi * u.y;
      wi = {sinTheta * std::cos(phi), sinTheta * std::sin(phi), mu};
      s.flags = kBsdfDiffuse | kBsdfReflection;
      break;
    }
    case kSheen:
      // Uniformly: the sheen peaks towards the horizon, where a cosine density vanishes (it
      // gave samples of 2.33 under a sky of 1).
      wi = sampleUniformHemisphere(u);
      s.flags = kBsdfGlossy | kBsdfReflection;
      break;
    case kDiffTrans:
      wi = sampleCosineHemisphere(u);
      wi.z = -wi.z;
      s.flags = kBsdfDiffuse | kBsdfTransmission;
      break;
    case kCoat: {
      const TrowbridgeReitzDistribution coat(coatAlpha);
      const Vec3f woC = toCoat(wo);
      if (!(woC.z > 0)) return false;
      wi = fromCoat(reflect(woC, coat.Sample_wm(woC, u)));
      if (wi.z <= 0) return false;
      s.flags = kBsdfGlossy | kBsdfReflection;
      break;
    }
    case kSpec:
    case kTrans: {  // rough
      const TrowbridgeReitzDistribution distribution(alphaX, alphaY);
      const Vec3f wm = distribution.Sample_wm(wo, u);
      // The side: the lobe chosen, or for a grouped interface the Fresnel factor at this
      // microfacet (what is left of uLobe, uRest, decides, and then what is left of it
      // chooses the dispersion channel).
      float uChannel = uRest;
      bool reflects = lobe == kSpec;
      if (pr.grouped) {
        const float share = reflectShare(wo, wm, hit.eta, pr);
        reflects = uRest < share;
        uChannel = reflects ? uRest / share : (uRest - share) / (1 - share);
        uChannel = std::clamp(uChannel, 0.0f, 0.99999994f);
      }
      if (reflects) {
        wi = reflect(wo, wm);
        if (wi.z <= 0) return false;
        s.flags = kBsdfGlossy | kBsdfReflection;
        break;
      }
      s.flags = kBsdfGlossy | kBsdfTransmission;
      if (hit.thinWalled) {
        const Vec3f wr = reflect(wo, wm);
        if (wr.z <= 0) return false;
        wi = {wr.x, wr.y, -wr.z};
        break;
      }
      const float eta = hit.dispersion > 0 ? channelEta(std::min(int(uChannel * 3), 2)) : hit.eta;
      float etaCrossed = 1;
      if (!refract(wo, wm, eta, &etaCrossed, &wi) || wi.z >= 0) return false;
      s.eta = etaCrossed;
      break;
    }
    default:
      return false;
  }
  const Eval e = evaluateLocal(wo, wi, pr);
  if (!(e.pdf > 0)) return false;
  s.f = e.f;
  s.pdf = e.pdf;
  s.wi = anisotropic ? fromAniso(wi) : wi;
  return true;
}

// ---------------------------------------------------------------------------------------------
// The BSDF: what is not inline
// ---------------------------------------------------------------------------------------------

bool Bsdf::foldReflection(float cosI, BsdfSample* s) const {
  // A mirror direction about a strongly tilted shading normal (normal maps, coarse smooth
  // meshes) can point into the surface; fold it back above the geometric plane rather than
  // lose it. (Integrators tilt such normals back first, reflectionSafeNormal; this catches what
  // rounding leaves.) f was F / cos at the unfolded direction: rescaled to the folded one's
  // cosine, so the sample's weight f |cos| / pdf stays F / pdf.
  const Vec3f ng = frame_.ng;
  const Vec3f folded = normalize(s->wi - ng * (2 * dot(s->wi, ng)));
  const float cosFolded = std::abs(dot(folded, frame_.ns));
  if (!(cosFolded > 0)) return false;
  s->f *= std::abs(cosI) / cosFolded;
  s->wi = folded;
  return true;
}

float PhongBxdf::narrowestAlpha() const {
  return pSpecular > 0 ? std::min(1.0f, std::sqrt(2 / (shininess + 2))) : 1.0f;
}

float Bsdf::narrowestAlpha() const {
  return dispatch([](const auto& b) -> float {
    using B = std::decay_t<decltype(b)>;
    if constexpr (std::is_same_v<B, MirrorBxdf> || std::is_same_v<B, GlassBxdf>)
      return 0;
    else if constexpr (std::is_same_v<B, PhongBxdf> || std::is_same_v<B, PbrBxdf>)
      return b.narrowestAlpha();
    else
      return 1;
  });
}

float Bsdf::diffuseProbability() const {
  return dispatch([](const auto& b) -> float {
    using B = std::decay_t<decltype(b)>;
    if constexpr (std::is_same_v<B, DiffuseBxdf>)
      return 1;
    else if constexpr (std::is_same_v<B, PhongBxdf> || std::is_same_v<B, PbrBxdf>)
      return b.diffuseProbability();
    else
      return 0;
  });
}

uint32_t Bsdf::flags() const {
  return dispatch([](const auto& b) -> uint32_t {
    if constexpr (std::is_same_v<std::decay_t<decltype(b)>, std::monostate>)
      return kBsdfNone;
    else
      return b.flags();
  });
}

Bsdf::StraightCrossing Bsdf::straightCrossing(Vec3f w, bool frontFace) const {
  const float cosTheta = std::abs(dot(w, frame_.ns));
  // The material's index from its bxdf's relative one (inverted on back faces).
  auto outsideReflectance = [&](float eta) {
    return fresnelDielectric(cosTheta, frontFace ? eta : 1 / eta);
  };
  if (const auto* glass = std::get_if<GlassBxdf>(&lobes_))
    return {glass->T, outsideReflectance(glass->eta)};
  if (const auto* pbr = std::get_if<PbrBxdf>(&lobes_)) {
    const PbrHit& h = pbr->hit;
    const float share = (1 - h.metallic) * h.transmission;
    if (!(share > 0)) return {};
    // A thin sheet has no refracting volume: its two faces are one crossing here.
    return {h.base * share, h.thinWalled ? 0.0f : outsideReflectance(h.eta)};
  }
  return {};
}

}  // namespace glint
