// glint — eyelight, Lambert and Phong.
#include "materials/basic_materials.h"

#include "geometry/sampling.h"

namespace glint {

// ---------------------------------------------------------------------------------------------
// Lambert
// ---------------------------------------------------------------------------------------------

Rgb LambertMaterial::eval(const SurfaceInteraction& si, Vec3f wi) const {
  if (dot(wi, si.ng) <= 0 || dot(wi, si.ns) <= 0) return {};
  return diffuse_.evaluate(si) * kInvPi;
}

std::optional<BsdfSample> LambertMaterial::sample(const SurfaceInteraction& si, Vec2f u,
                                                  float) const {
  Vec3f local = sampleCosineHemisphere(u);
  Vec3f wi = Frame::fromZ(si.ns).fromLocal(local);
  if (dot(wi, si.ng) <= 0 || local.z <= 0) return std::nullopt;
  return BsdfSample{diffuse_.evaluate(si) * kInvPi, wi, cosineHemispherePdf(local.z),
                    kBsdfDiffuse | kBsdfReflection};
}

float LambertMaterial::pdf(const SurfaceInteraction& si, Vec3f wi) const {
  if (dot(wi, si.ng) <= 0) return 0;
  return cosineHemispherePdf(dot(wi, si.ns));
}

// ---------------------------------------------------------------------------------------------
// Phong
// ---------------------------------------------------------------------------------------------

PhongMaterial::PhongMaterial(ColorParam diffuse, Rgb specular, float shininess,
                             ColorParam emission)
    : SimpleMaterial(diffuse, emission), specular_(specular), shininess_(shininess) {}

float PhongMaterial::specularProbability(const SurfaceInteraction& si) const {
  float kd = luminance(diffuse_.evaluate(si)), ks = luminance(specular_);
  return kd + ks > 0 ? ks / (kd + ks) : 0;
}

Rgb PhongMaterial::eval(const SurfaceInteraction& si, Vec3f wi) const {
  if (dot(wi, si.ng) <= 0 || dot(wi, si.ns) <= 0) return {};
  Rgb f = diffuse_.evaluate(si) * kInvPi;
  float cosAlpha = dot(reflect(si.wo, si.ns), wi);
  if (cosAlpha > 0)
    f += specular_ * ((shininess_ + 2) / (2 * kPi) * std::pow(cosAlpha, shininess_));
  return f;
}

std::optional<BsdfSample> PhongMaterial::sample(const SurfaceInteraction& si, Vec2f u,
                                                float uLobe) const {
  Vec3f wi;
  if (uLobe < specularProbability(si)) {
    // cos^n lobe around the mirror direction: cos(alpha) = u^(1/(n+1)).
    float cosA = std::pow(u.x, 1 / (shininess_ + 1));
    float sinA = std::sqrt(std::max(0.0f, 1 - cosA * cosA));
    float phi = 2 * kPi * u.y;
    Vec3f local{sinA * std::cos(phi), sinA * std::sin(phi), cosA};
    wi = Frame::fromZ(reflect(si.wo, si.ns)).fromLocal(local);
  } else {
    wi = Frame::fromZ(si.ns).fromLocal(sampleCosineHemisphere(u));
  }
  if (dot(wi, si.ng) <= 0 || dot(wi, si.ns) <= 0) return std::nullopt;
  float p = pdf(si, wi);
  if (p <= 0) return std::nullopt;
  return BsdfSample{eval(si, wi), wi, p, kBsdfGlossy | kBsdfReflection};
}

float PhongMaterial::pdf(const SurfaceInteraction& si, Vec3f wi) const {
  if (dot(wi, si.ng) <= 0) return 0;
  float ps = specularProbability(si);
  float cosAlpha = dot(reflect(si.wo, si.ns), wi);
  float specPdf = cosAlpha > 0 ? (shininess_ + 1) / (2 * kPi) * std::pow(cosAlpha, shininess_) : 0;
  return (1 - ps) * cosineHemispherePdf(dot(wi, si.ns)) + ps * specPdf;
}

}  // namespace glint
