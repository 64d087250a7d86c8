// glint — scattering at a smooth dielectric interface: exact Fresnel reflectance and Snell's
// refraction, for the glass shaders (specular.h) and the microfacet models.
//
// Conventions (pbrt-v4's): directions point away from the surface; `n` is the surface normal
// and may face either side; eta = n_transmitted / n_incident for light arriving from the side
// n points to (outside -> inside for eta = n_glass / n_air).
#pragma once

#include <algorithm>
#include <cmath>

#include "geometry/math.h"

namespace glint {

// Unpolarised Fresnel reflectance of a smooth dielectric interface for an incident direction
// with cosine cosThetaI to the normal, exactly (the average of the s and p polarisations, not
// Schlick's approximation). cosThetaI < 0 means the light arrives from the inside: eta is
// inverted. Returns 1 under total internal reflection and exactly 0 for eta == 1.
inline float fresnelDielectric(float cosThetaI, float eta) {
  cosThetaI = std::clamp(cosThetaI, -1.0f, 1.0f);
  if (cosThetaI < 0) {
    eta = 1 / eta;
    cosThetaI = -cosThetaI;
  }
  if (eta == 1) return 0;  // no interface
  const float sin2ThetaI = 1 - cosThetaI * cosThetaI;
  const float sin2ThetaT = sin2ThetaI / (eta * eta);
  if (sin2ThetaT >= 1) return 1;  // total internal reflection
  const float cosThetaT = std::sqrt(std::max(0.0f, 1 - sin2ThetaT));
  const float rParallel = (eta * cosThetaI - cosThetaT) / (eta * cosThetaI + cosThetaT);
  const float rPerpendicular = (cosThetaI - eta * cosThetaT) / (cosThetaI + eta * cosThetaT);
  return (rParallel * rParallel + rPerpendicular * rPerpendicular) / 2;
}

// Refracts the unit direction wi (pointing away from the surface) through the interface with
// normal n by Snell's law: n_i sin(theta_i) = n_t sin(theta_t). Returns false under total
// internal reflection. When wi is on the side n does not point to, the interface is crossed
// the other way: n is flipped and eta inverted; `etaRelative` receives the eta that applied.
inline bool refract(Vec3f wi, Vec3f n, float eta, float* etaRelative, Vec3f* wt) {
  float cosThetaI = dot(n, wi);
  if (cosThetaI < 0) {
    eta = 1 / eta;
    cosThetaI = -cosThetaI;
    n = -n;
  }
  const float sin2ThetaI = std::max(0.0f, 1 - cosThetaI * cosThetaI);
  const float sin2ThetaT = sin2ThetaI / (eta * eta);
  if (sin2ThetaT >= 1) return false;
  const float cosThetaT = std::sqrt(1 - sin2ThetaT);
  *wt = -wi / eta + (cosThetaI / eta - cosThetaT) * n;
  if (etaRelative) *etaRelative = eta;
  return true;
}

}  // namespace glint
