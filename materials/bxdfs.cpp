// glint — the BxDFs (diffuse, Phong and Blinn-Phong, mirror, glass and glTF's metallic-roughness
// microfacet model) and the Bsdf that dispatches to them. One file, so that the dispatch inlines
// each BxDF's f, pdf and sample (they sit in every integrator's inner loop).
#include "materials/bxdfs.h"

#include <algorithm>
#include <cmath>

#include "geometry/sampling.h"
#include "materials/bsdf.h"
#include "materials/microfacet.h"
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
// Diffuse
// ---------------------------------------------------------------------------------------------

Rgb DiffuseBxdf::evaluate(Vec3f, Vec3f wi, float* pdf) const {
  *pdf = cosineHemispherePdf(wi.z);
  return wi.z > 0 ? R * kInvPi : Rgb{};
}

std::optional<BsdfSample> DiffuseBxdf::sample(Vec3f, Vec2f u, float, uint32_t lobes) const {
  if (!(lobes & kBsdfReflection) || (lobes & kBsdfSpecular)) return std::nullopt;
  const Vec3f wi = sampleCosineHemisphere(u);
  if (wi.z <= 0) return std::nullopt;
  return BsdfSample{R * kInvPi, wi, cosineHemispherePdf(wi.z), kBsdfDiffuse | kBsdfReflection};
}

// ---------------------------------------------------------------------------------------------
// Phong and Blinn-Phong
// ---------------------------------------------------------------------------------------------

PhongBxdf::PhongBxdf(Rgb kd_, Rgb ks_, float shininess_, bool blinn_)
    : kd(kd_), ks(ks_), shininess(shininess_), blinn(blinn_) {
  const float d = luminance(kd), s = luminance(ks);
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

std::optional<BsdfSample> PhongBxdf::sample(Vec3f wo, Vec2f u, float uLobe, uint32_t lobes) const {
  if (!(lobes & kBsdfReflection) || (lobes & kBsdfSpecular)) return std::nullopt;
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
  if (wi.z <= 0) return std::nullopt;
  float p;
  const Rgb f = evaluate(wo, wi, &p);
  if (!(p > 0)) return std::nullopt;
  return BsdfSample{f, wi, p, kBsdfGlossy | kBsdfReflection};
}

// ---------------------------------------------------------------------------------------------
// Mirror and glass
// ---------------------------------------------------------------------------------------------

std::optional<BsdfSample> MirrorBxdf::sample(Vec3f wo, Vec2f, float, uint32_t lobes) const {
  if (!(lobes & kBsdfReflection)) return std::nullopt;
  const Vec3f wi = mirrorLocal(wo);
  const float cosI = std::abs(wi.z);
  if (cosI == 0) return std::nullopt;
  return BsdfSample{R / cosI, wi, 1, kBsdfSpecular | kBsdfReflection};
}

std::optional<BsdfSample> GlassBxdf::sample(Vec3f wo, Vec2f, float uLobe, uint32_t lobes) const {
  const float R = fresnelDielectric(wo.z, eta), Tr = 1 - R;
  const float pr = (lobes & kBsdfReflection) ? R : 0;
  const float pt = (lobes & kBsdfTransmission) ? Tr : 0;
  if (pr + pt <= 0) return std::nullopt;
  if (uLobe < pr / (pr + pt)) {
    const Vec3f wi = mirrorLocal(wo);
    const float cosI = std::abs(wi.z);
    if (cosI == 0) return std::nullopt;
    return BsdfSample{Rgb{R, R, R} / cosI, wi, pr / (pr + pt), kBsdfSpecular | kBsdfReflection};
  }
  Vec3f wi;
  float etaCrossed = 1;
  if (!refract(wo, {0, 0, 1}, eta, &etaCrossed, &wi)) return std::nullopt;
  const float cosI = std::abs(wi.z);
  if (cosI == 0) return std::nullopt;
  return BsdfSample{T * (Tr / (cosI * etaCrossed * etaCrossed)), wi, pt / (pr + pt),
                    kBsdfSpecular | kBsdfTransmission, etaCrossed};
}

// ---------------------------------------------------------------------------------------------
// glTF metallic-roughness
// ---------------------------------------------------------------------------------------------

namespace {
// The least share (1 - Fresnel) the lobe selection gives rough transmission (see PbrBxdf's
// constructor).
constexpr float kMinRoughTransmissionWeight = 0.2f;
}  // namespace

PbrBxdf::PbrBxdf(Vec3f wo, Rgb base_, float metallic_, float roughness, float transmission_,
                 float eta_)
    : base(base_),
      metallic(std::clamp(metallic_, 0.0f, 1.0f)),
      transmission(std::clamp(transmission_, 0.0f, 1.0f)),
      alpha(TrowbridgeReitzDistribution::roughnessToAlpha(std::clamp(roughness, 0.0f, 1.0f))),
      eta(eta_) {
  smooth = TrowbridgeReitzDistribution(alpha).effectivelySmooth();
  if (!(wo.z > 0)) return;  // seen from below its shading normal: black, never sampled
  // Lobe weights from the Fresnel reflectance at wo (the microfacet normals scatter around ns).
  fresnelWo_ = fresnelDielectric(wo.z, eta);
  const float dielectric = 1 - metallic;
  wSpec_ = metallic + dielectric * fresnelWo_;
  wDiff_ = dielectric * (1 - transmission) * (1 - fresnelWo_) * std::max(luminance(base), 0.0f);
  // A rough surface transmits through tilted microfacets even where the macro-surface reflects
  // totally (F = 1 seen from inside past the critical angle): the transmission lobe keeps a
  // minimum weight there, or sample() would never reach light that f() says passes.
  const float fTransmission =
      smooth ? fresnelWo_ : std::min(fresnelWo_, 1 - kMinRoughTransmissionWeight);
  wTrans_ = dielectric * transmission * (1 - fTransmission);
  lobeProbabilities(kBsdfAllLobes, &pSpec_, &pDiff_, &pTrans_);
}

void PbrBxdf::lobeProbabilities(uint32_t lobes, float* pSpec, float* pDiff, float* pTrans) const {
  float wSpec = wSpec_, wDiff = wDiff_, wTrans = wTrans_;
  if (!(lobes & kBsdfReflection)) wSpec = wDiff = 0;
  if (!(lobes & kBsdfTransmission)) wTrans = 0;
  if (lobes & kBsdfSpecular) {  // only the delta lobes
    wDiff = 0;
    if (!smooth) wSpec = wTrans = 0;
  }
  const float sum = wSpec + wDiff + wTrans;
  *pSpec = *pDiff = *pTrans = 0;
  if (sum > 0) *pSpec = wSpec / sum, *pDiff = wDiff / sum, *pTrans = wTrans / sum;
}

uint32_t PbrBxdf::flags() const {
  uint32_t f = kBsdfReflection;
  if (pDiff_ > 0) f |= kBsdfDiffuse;
  if (pSpec_ > 0 || pTrans_ > 0) f |= smooth ? kBsdfSpecular : kBsdfGlossy;
  if (pTrans_ > 0) f |= kBsdfTransmission;
  return f;
}

namespace {
// f and pdf of the metallic-roughness model in the local frame, the pdf for the lobe
// probabilities given (sample() may restrict them).
struct PbrEval {
  Rgb f;
  float pdf = 0;
};
}  // namespace

// The shared evaluation: see pbr.h for the model.
static PbrEval evaluatePbr(const PbrBxdf& b, float fresnelWo, Vec3f wo, Vec3f wi, float pSpec,
                           float pDiff, float pTrans) {
  PbrEval r;
  if (!(wo.z > 0)) return r;
  const float dielectric = 1 - b.metallic;
  if (b.smooth) {
    // Only the diffuse lobe is not a delta; it gets what the mirror lobe leaves at wo.
    if (wi.z <= 0) return r;
    r.f = b.base * (dielectric * (1 - b.transmission) * (1 - fresnelWo) * kInvPi);
    r.pdf = pDiff * cosineHemispherePdf(wi.z);
    return r;
  }
  const TrowbridgeReitzDistribution distribution(b.alpha);
  if (wi.z > 0) {
    r.pdf = pDiff * cosineHemispherePdf(wi.z);
    const Rgb diffuse = b.base * ((1 - b.transmission) * (1 - fresnelWo) * kInvPi);
    Vec3f h = wo + wi;
    if (lengthSquared(h) == 0) {
      r.f = diffuse * dielectric;
      return r;
    }
    h = normalize(h);
    const float woH = dot(wo, h);
    const float cosH = std::max(woH, 0.0f);
    const float D = distribution.D(h);
    const float spec = D * distribution.G(wo, wi) / (4 * wo.z * wi.z);
    const float fd = fresnelDielectric(cosH, b.eta);
    const Rgb metal = schlick(b.base, cosH) * spec;
    // The diffuse layer gets what the interface does not reflect at wo, 1 - F(wo.n), not
    // glTF's 1 - F(wo.h): the half-vector coupling is not energy conserving (glTF 2.0,
    // B.3.6.3; a white surface reflected up to 1.7 times the light at grazing angles), and
    // from inside a transmitting surface past the critical angle it was non-zero where the
    // diffuse lobe is never sampled.
    const Rgb plastic = Rgb{1, 1, 1} * (fd * spec) + diffuse;
    r.f = metal * b.metallic + plastic * dielectric;
    if (pSpec > 0 && woH > 0) r.pdf += pSpec * distribution.PDF(wo, h) / (4 * woH);
    return r;
  }
  const bool transmits = b.transmission > 0 && dielectric > 0;
  if (!transmits && !(pTrans > 0)) return r;
  // Refraction through a microfacet: the generalized half vector of Walter et al. (2007).
  Vec3f wm = wi * b.eta + wo;
  if (wi.z == 0 || lengthSquared(wm) == 0) return r;
  wm = normalize(wm);
  if (wm.z < 0) wm = -wm;
  const float wiM = dot(wi, wm), woM = dot(wo, wm);
  if (wiM * wi.z <= 0 || woM * wo.z <= 0) return r;  // back-facing microfacet
  const float denom = square(wiM + woM / b.eta);
  if (transmits) {
    const float fd = fresnelDielectric(woM, b.eta);
    const float ft = distribution.D(wm) * distribution.G(wo, wi) * (1 - fd) *
                     std::abs(wiM * woM / (denom * wi.z * wo.z)) / square(b.eta);
    r.f = b.base * (dielectric * b.transmission * ft);
  }
  if (pTrans > 0) r.pdf = pTrans * distribution.PDF(wo, wm) * std::abs(wiM) / denom;
  return r;
}

Rgb PbrBxdf::evaluate(Vec3f wo, Vec3f wi, float* pdf) const {
  const PbrEval e = evaluatePbr(*this, fresnelWo_, wo, wi, pSpec_, pDiff_, pTrans_);
  *pdf = e.pdf;
  return e.f;
}

std::optional<BsdfSample> PbrBxdf::sample(Vec3f wo, Vec2f u, float uLobe, uint32_t lobes) const {
  float pSpec, pDiff, pTrans;
  lobeProbabilities(lobes, &pSpec, &pDiff, &pTrans);
  if (!(wo.z > 0) || !(pSpec + pDiff + pTrans > 0)) return std::nullopt;
  const float dielectric = 1 - metallic;
  enum {
    kSpec,
    kDiff,
    kTrans
  } lobe = uLobe < pSpec           ? kSpec
           : uLobe < pSpec + pDiff ? kDiff
                                   : kTrans;
  if (lobe == kTrans && pTrans <= 0) lobe = pDiff > 0 ? kDiff : kSpec;  // rounding at 1

  if (smooth && lobe != kDiff) {
    // Delta lobes: the mirror direction, or the refracted one.
    if (lobe == kSpec) {
      const Vec3f wi = mirrorLocal(wo);
      const Rgb F = schlick(base, wo.z) * metallic + Rgb{1, 1, 1} * (dielectric * fresnelWo_);
      return BsdfSample{F / wi.z, wi, pSpec, kBsdfSpecular | kBsdfReflection};
    }
    Vec3f wi;
    float etaCrossed = 1;
    if (!refract(wo, {0, 0, 1}, eta, &etaCrossed, &wi)) return std::nullopt;
    const float T = 1 - fresnelWo_;
    return BsdfSample{
        base * (dielectric * transmission * T / (std::abs(wi.z) * square(etaCrossed))), wi, pTrans,
        kBsdfSpecular | kBsdfTransmission, etaCrossed};
  }
  BsdfSample s;
  Vec3f wi;
  if (lobe == kDiff) {
    wi = sampleCosineHemisphere(u);
    s.flags = kBsdfDiffuse | kBsdfReflection;
  } else {
    const TrowbridgeReitzDistribution distribution(alpha);
    const Vec3f wm = distribution.Sample_wm(wo, u);
    if (lobe == kSpec) {
      wi = reflect(wo, wm);
      if (wi.z <= 0) return std::nullopt;
      s.flags = kBsdfGlossy | kBsdfReflection;
    } else {
      float etaCrossed = 1;
      if (!refract(wo, wm, eta, &etaCrossed, &wi) || wi.z >= 0) return std::nullopt;
      s.flags = kBsdfGlossy | kBsdfTransmission;
      s.eta = etaCrossed;
    }
  }
  const PbrEval e = evaluatePbr(*this, fresnelWo_, wo, wi, pSpec, pDiff, pTrans);
  if (!(e.pdf > 0)) return std::nullopt;
  s.f = e.f;
  s.pdf = e.pdf;
  s.wi = wi;
  return s;
}

// ---------------------------------------------------------------------------------------------
// The BSDF: dispatch and the geometric-side rules
// ---------------------------------------------------------------------------------------------
float terminatorShadowing(Vec3f ng, Vec3f ns, Vec3f wi) {
  const float cosNs = dot(ns, wi), cosNg = dot(ng, wi), cosNsNg = dot(ns, ng);
  if (cosNs <= 0 || cosNg <= 0 || cosNsNg <= 0) return cosNg > 0 ? 1.0f : 0.0f;
  const float g = std::min(1.0f, cosNg / (cosNs * cosNsNg));
  return -g * g * g + g * g + g;  // the smooth form of the paper's eq. 4
}

Rgb Bsdf::evaluate(Vec3f wi, float* pdf) const {
  *pdf = 0;
  if (std::holds_alternative<std::monostate>(lobes_)) return {};
  const Vec3f local = frame_.frame.toLocal(wi);
  if (!consistentSide(wi, local.z)) return {};
  Rgb f = std::visit(
      [&](const auto& b) -> Rgb {
        if constexpr (std::is_same_v<std::decay_t<decltype(b)>, std::monostate>)
          return {};
        else
          return b.evaluate(frame_.wo, local, pdf);
      },
      lobes_);
  if (frame_.terminator && dot(wi, frame_.ng) > 0)
    f *= terminatorShadowing(frame_.ng, frame_.frame.n, wi);
  return f;
}

std::optional<BsdfSample> Bsdf::sample(Vec2f u, float uLobe, uint32_t lobes) const {
  std::optional<BsdfSample> s = std::visit(
      [&](const auto& b) -> std::optional<BsdfSample> {
        if constexpr (std::is_same_v<std::decay_t<decltype(b)>, std::monostate>)
          return std::nullopt;
        else
          return b.sample(frame_.wo, u, uLobe, lobes);
      },
      lobes_);
  if (!s) return s;
  const float localZ = s->wi.z;
  s->wi = frame_.frame.fromLocal(s->wi);
  const Vec3f ng = frame_.ng;
  if (s->flags & kBsdfSpecular) {
    if ((s->flags & kBsdfReflection) && dot(s->wi, ng) <= 0) {
      // A mirror direction about a strongly tilted shading normal (normal maps, coarse smooth
      // meshes) can point into the surface; fold it back above the geometric plane rather
      // than lose it.
      s->wi = normalize(s->wi - ng * (2 * dot(s->wi, ng)));
      return s;
    }
    if (!consistentSide(s->wi, localZ)) return std::nullopt;
    return s;
  }
  if (!consistentSide(s->wi, localZ)) return std::nullopt;
  if (frame_.terminator && dot(s->wi, ng) > 0)
    s->f *= terminatorShadowing(ng, frame_.frame.n, s->wi);
  return s;
}

uint32_t Bsdf::flags() const {
  return std::visit(
      [](const auto& b) -> uint32_t {
        if constexpr (std::is_same_v<std::decay_t<decltype(b)>, std::monostate>)
          return kBsdfNone;
        else
          return b.flags();
      },
      lobes_);
}

}  // namespace glint
