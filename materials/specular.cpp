// glint — mirror and glass.
#include "materials/specular.h"

#include "geometry/sampling.h"
#include "materials/scattering.h"

namespace glint {

MirrorMaterial::MirrorMaterial(ColorParam reflectance) : reflectance_(reflectance) {
  uses(reflectance_);
}

std::optional<BsdfSample> MirrorMaterial::sampleBsdf(const SurfaceInteraction& si, Vec2f, float,
                                                     uint32_t lobes) const {
  if (!(lobes & kBsdfReflection)) return std::nullopt;
  Vec3f wi = reflect(si.wo, si.ns);
  float cosI = std::abs(dot(wi, si.ns));
  if (cosI == 0) return std::nullopt;
  return BsdfSample{reflectance_.evaluate(si) / cosI, wi, 1, kBsdfSpecular | kBsdfReflection};
}

GlassMaterial::GlassMaterial(float ior, ColorParam transmittance)
    : ior_(ior), transmittance_(transmittance) {
  uses(transmittance_);
  traits_.refraction = true;
}

std::optional<BsdfSample> GlassMaterial::sampleBsdf(const SurfaceInteraction& si, Vec2f,
                                                    float uLobe, uint32_t lobes) const {
  // ns faces wo; eta is the ratio across the interface in the direction light leaves wo's side.
  const float eta = si.frontFace ? ior_ : 1 / ior_;
  const float cosO = dot(si.wo, si.ns);
  const float R = fresnelDielectric(cosO, eta), T = 1 - R;
  const float pr = (lobes & kBsdfReflection) ? R : 0;
  const float pt = (lobes & kBsdfTransmission) ? T : 0;
  if (pr + pt <= 0) return std::nullopt;

  if (uLobe < pr / (pr + pt)) {
    Vec3f wi = reflect(si.wo, si.ns);
    float cosI = std::abs(dot(wi, si.ns));
    if (cosI == 0) return std::nullopt;
    return BsdfSample{Rgb{R, R, R} / cosI, wi, pr / (pr + pt), kBsdfSpecular | kBsdfReflection};
  }
  Vec3f wi;
  float etaCrossed = 1;
  if (!refract(si.wo, si.ns, eta, &etaCrossed, &wi)) return std::nullopt;
  float cosI = std::abs(dot(wi, si.ns));
  if (cosI == 0) return std::nullopt;
  Rgb f = transmittance_.evaluate(si) * (T / (cosI * etaCrossed * etaCrossed));
  return BsdfSample{f, wi, pt / (pr + pt), kBsdfSpecular | kBsdfTransmission, etaCrossed};
}

}  // namespace glint
