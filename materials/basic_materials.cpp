// glint — eyelight, Lambert, Phong and Blinn-Phong.
#include "materials/basic_materials.h"

#include "geometry/sampling.h"

namespace glint {

SimpleMaterial::SimpleMaterial(ColorParam diffuse, ColorParam emission)
    : diffuse_(diffuse), emission_(emission) {
  uses(diffuse_);
  uses(emission_);
  traits_.emits = !emission_.isBlack();
}

// ---------------------------------------------------------------------------------------------
// Lambert
// ---------------------------------------------------------------------------------------------

Rgb LambertMaterial::evalBsdf(const SurfaceInteraction& si, Vec3f wi) const {
  if (dot(wi, si.ng) <= 0 || dot(wi, si.ns) <= 0) return {};
  return diffuse_.evaluate(si) * kInvPi;
}

std::optional<BsdfSample> LambertMaterial::sampleBsdf(const SurfaceInteraction& si, Vec2f u, float,
                                                      uint32_t lobes) const {
  if (!(lobes & kBsdfReflection)) return std::nullopt;
  Vec3f local = sampleCosineHemisphere(u);
  Vec3f wi = Frame::fromZ(si.ns).fromLocal(local);
  if (dot(wi, si.ng) <= 0 || local.z <= 0) return std::nullopt;
  return BsdfSample{diffuse_.evaluate(si) * kInvPi, wi, cosineHemispherePdf(local.z),
                    kBsdfDiffuse | kBsdfReflection};
}

float LambertMaterial::pdfBsdf(const SurfaceInteraction& si, Vec3f wi) const {
  if (dot(wi, si.ng) <= 0) return 0;
  return cosineHemispherePdf(dot(wi, si.ns));
}

// ---------------------------------------------------------------------------------------------
// Phong and Blinn-Phong
// ---------------------------------------------------------------------------------------------

PhongMaterial::PhongMaterial(ColorParam diffuse, Rgb specular, float shininess, ColorParam emission,
                             bool blinn)
    : SimpleMaterial(diffuse, emission),
      specular_(specular),
      shininess_(shininess),
      blinn_(blinn) {}

float PhongMaterial::specularProbability(const SurfaceInteraction& si) const {
  float kd = luminance(diffuse_.evaluate(si)), ks = luminance(specular_);
  return kd + ks > 0 ? ks / (kd + ks) : 0;
}

float PhongMaterial::specularLobe(const SurfaceInteraction& si, Vec3f wi) const {
  const float n = shininess_;
  if (!blinn_) {
    float cosAlpha = dot(reflect(si.wo, si.ns), wi);
    return cosAlpha > 0 ? (n + 2) / (2 * kPi) * std::pow(cosAlpha, n) : 0;
  }
  Vec3f h = si.wo + wi;
  if (lengthSquared(h) == 0) return 0;
  h = normalize(h);
  const float cosH = dot(h, si.ns), hDotWi = dot(h, wi);
  const float cosI = dot(wi, si.ns), cosO = dot(si.wo, si.ns);
  const float denominator = hDotWi * std::max(cosI, cosO);
  if (cosH <= 0 || denominator <= 0) return 0;
  return (n + 1) / (8 * kPi) * std::pow(cosH, n) / denominator;
}

float PhongMaterial::specularPdf(const SurfaceInteraction& si, Vec3f wi) const {
  const float n = shininess_;
  if (!blinn_) {
    float cosAlpha = dot(reflect(si.wo, si.ns), wi);
    return cosAlpha > 0 ? (n + 1) / (2 * kPi) * std::pow(cosAlpha, n) : 0;
  }
  // Half vectors are drawn with density (n+1)/(2 pi) cos^n(theta_h); the Jacobian of
  // reflection about h is 1 / (4 h.wo).
  Vec3f h = si.wo + wi;
  if (lengthSquared(h) == 0) return 0;
  h = normalize(h);
  const float cosH = dot(h, si.ns), hDotWo = dot(h, si.wo);
  if (cosH <= 0 || hDotWo <= 0) return 0;
  return (n + 1) / (2 * kPi) * std::pow(cosH, n) / (4 * hDotWo);
}

Rgb PhongMaterial::evalBsdf(const SurfaceInteraction& si, Vec3f wi) const {
  if (dot(wi, si.ng) <= 0 || dot(wi, si.ns) <= 0) return {};
  return diffuse_.evaluate(si) * kInvPi + specular_ * specularLobe(si, wi);
}

std::optional<BsdfSample> PhongMaterial::sampleBsdf(const SurfaceInteraction& si, Vec2f u,
                                                    float uLobe, uint32_t lobes) const {
  if (!(lobes & kBsdfReflection)) return std::nullopt;
  Vec3f wi;
  if (uLobe < specularProbability(si)) {
    // A cos^n lobe around the mirror direction (Phong) or the normal (Blinn's half vector):
    // cos = u^(1/(n+1)).
    float cosA = std::pow(u.x, 1 / (shininess_ + 1));
    float sinA = std::sqrt(std::max(0.0f, 1 - cosA * cosA));
    float phi = 2 * kPi * u.y;
    Vec3f local{sinA * std::cos(phi), sinA * std::sin(phi), cosA};
    if (blinn_) {
      Vec3f h = Frame::fromZ(si.ns).fromLocal(local);
      wi = reflect(si.wo, h);
    } else {
      wi = Frame::fromZ(reflect(si.wo, si.ns)).fromLocal(local);
    }
  } else {
    wi = Frame::fromZ(si.ns).fromLocal(sampleCosineHemisphere(u));
  }
  if (dot(wi, si.ng) <= 0 || dot(wi, si.ns) <= 0) return std::nullopt;
  float p = pdfBsdf(si, wi);
  if (p <= 0) return std::nullopt;
  return BsdfSample{evalBsdf(si, wi), wi, p, kBsdfGlossy | kBsdfReflection};
}

float PhongMaterial::pdfBsdf(const SurfaceInteraction& si, Vec3f wi) const {
  if (dot(wi, si.ng) <= 0 || dot(wi, si.ns) <= 0) return 0;  // sample() rejects these
  float ps = specularProbability(si);
  return (1 - ps) * cosineHemispherePdf(dot(wi, si.ns)) + ps * specularPdf(si, wi);
}

}  // namespace glint
