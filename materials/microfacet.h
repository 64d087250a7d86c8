// glint — the Trowbridge–Reitz (GGX) microfacet distribution with Smith masking and sampling
// of the visible normals. A building block for the rough conductor, dielectric and plastic
// shaders; no material uses it yet.
//
// Everything lives in the local shading frame: the macro-surface normal is +Z and every
// direction is a unit vector pointing away from the surface. Microfacet normals wm lie in the
// upper hemisphere. The distribution may be anisotropic (alphaX along X, alphaY along Y);
// glint's materials use it isotropically.
//
// The formulas follow Walter et al. 2007 ("Microfacet Models for Refraction through Rough
// Surfaces"), Heitz 2014 ("Understanding the Masking-Shadowing Function in Microfacet-Based
// BRDFs") and Heitz 2018 ("Sampling the GGX Distribution of Visible Normals"); the structure
// follows pbrt-v4's TrowbridgeReitzDistribution. Each quantity is written in the form that
// stays finite at grazing angles: D and Lambda use the unit vector's components directly, so
// tan^2(theta) is never formed and a normal on the horizon does not divide by zero.
#pragma once

#include <algorithm>
#include <cassert>
#include <cmath>

#include "geometry/math.h"
#include "geometry/sampling.h"

namespace glint {

class TrowbridgeReitzDistribution {
 public:
  // Maps a perceptual roughness in [0, 1] to alpha = roughness^2 (the glTF / Disney mapping),
  // clamped below at 1e-4 so that D stays finite. Alphas under 1e-3 are effectivelySmooth():
  // callers treat roughness below about 0.03 as a perfect mirror or glass.
  static float roughnessToAlpha(float roughness) { return std::max(roughness * roughness, 1e-4f); }

  // An isotropic distribution; alpha > 0 (see roughnessToAlpha).
  explicit TrowbridgeReitzDistribution(float alpha) : TrowbridgeReitzDistribution(alpha, alpha) {}
  // An anisotropic distribution: alphaX is the roughness along local X, alphaY along Y.
  TrowbridgeReitzDistribution(float alphaX, float alphaY) : alphaX_(alphaX), alphaY_(alphaY) {
    assert(alphaX > 0 && alphaY > 0 && std::isfinite(alphaX) && std::isfinite(alphaY));
  }

  float alphaX() const { return alphaX_; }
  float alphaY() const { return alphaY_; }

  // True when the surface is so smooth that the caller should use a specular (delta) lobe:
  // D is then too peaked to sample or integrate in float.
  bool effectivelySmooth() const { return std::max(alphaX_, alphaY_) < 1e-3f; }

  // Density of microfacet normals per unit solid angle and unit projected macro-surface area:
  // the integral of D(wm) cos(theta_m) over the upper hemisphere is 1. wm is a unit vector;
  // D depends on wm.z only through its square.
  float D(Vec3f wm) const {
    // With cos^2 + sin^2 = 1 the textbook 1 / (pi ax ay cos^4 (1 + tan^2 (...))^2) becomes
    // 1 / (pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2): no tan^2, finite on the horizon.
    const float sx = wm.x / alphaX_, sy = wm.y / alphaY_;
    const float q = sx * sx + sy * sy + wm.z * wm.z;
    const float denominator = kPi * alphaX_ * alphaY_ * q * q;
    return denominator > 0 ? 1 / denominator : 0;
  }

  // Smith's auxiliary function: the projected area of microfacets that face away from w (and
  // are hidden), per unit projected area of those that face it. 0 at normal incidence, +inf
  // on the horizon (w.z = 0).
  float Lambda(Vec3f w) const {
    // alpha^2 tan^2(theta), with alpha the roughness along w's azimuth.
    const float ax = alphaX_ * w.x, ay = alphaY_ * w.y;
    const float numerator = ax * ax + ay * ay, cos2 = w.z * w.z;
    if (numerator == 0) return 0;
    if (cos2 == 0) return kInfinity;
    const float a2tan2 = numerator / cos2;
    if (std::isinf(a2tan2)) return kInfinity;
    // (sqrt(1 + t) - 1) / 2, rewritten to avoid cancellation for small t.
    return a2tan2 / (2 * (1 + std::sqrt(1 + a2tan2)));
  }

  // Smith masking: the fraction of the microfacets facing w that w sees, in [0, 1]. 0 on the
  // horizon.
  float G1(Vec3f w) const { return 1 / (1 + Lambda(w)); }

  // Height-correlated Smith masking-shadowing: the fraction of microfacets seen from both wo
  // and wi, in [0, min(G1(wo), G1(wi))].
  float G(Vec3f wo, Vec3f wi) const { return 1 / (1 + Lambda(wo) + Lambda(wi)); }

  // Distribution of the normals visible from w, per unit solid angle of wm:
  // G1(w) / |cos theta(w)| D(wm) max(0, w . wm). Integrates to 1 over the upper hemisphere
  // of wm. A w below the surface is treated as -w (the surface seen from inside), so
  // D(-w, wm) == D(w, wm). Zero for wm below the horizon or facing away from w.
  float D(Vec3f w, Vec3f wm) const {
    const float cosTheta = std::abs(w.z);
    if (cosTheta == 0 || wm.z <= 0) return 0;
    const float cosM = w.z > 0 ? dot(w, wm) : -dot(w, wm);
    if (cosM <= 0) return 0;
    return G1(w) / cosTheta * D(wm) * cosM;
  }

  // Samples a microfacet normal visible from w with density D(w, wm) (Heitz 2018). The result
  // is a unit vector with wm.z > 0 and, up to rounding, facing w (or -w when w.z < 0).
  Vec3f Sample_wm(Vec3f w, Vec2f u) const {
    // Stretch w to the configuration where the distribution is the unit-roughness one: there
    // the visible normals are those of a hemisphere, uniformly distributed in its projection.
    Vec3f wh = normalize(Vec3f{alphaX_ * w.x, alphaY_ * w.y, w.z});
    if (wh.z < 0) wh = -wh;
    // A basis around wh; T1 is horizontal, so it degenerates only when wh is the normal.
    const Vec3f t1 = wh.z < 0.99999f ? normalize(cross(Vec3f{0, 0, 1}, wh)) : Vec3f{1, 0, 0};
    const Vec3f t2 = cross(wh, t1);
    // A uniform point on the unit disk perpendicular to wh, squashed onto the part of the disk
    // that the hemisphere's projection covers (a half disk joined to half an ellipse).
    Vec2f p = sampleConcentricDisk(u);
    const float h = std::sqrt(std::max(0.0f, 1 - p.x * p.x));
    const float s = (1 + wh.z) / 2;
    p.y = (1 - s) * h + s * p.y;
    // Lift it onto the hemisphere, then unstretch the normal.
    const float pz = std::sqrt(std::max(0.0f, 1 - p.x * p.x - p.y * p.y));
    const Vec3f nh = p.x * t1 + p.y * t2 + pz * wh;
    return normalize(Vec3f{alphaX_ * nh.x, alphaY_ * nh.y, std::max(1e-6f, nh.z)});
  }

  // Solid-angle density with which Sample_wm(w, u) returns wm: D(w, wm).
  float PDF(Vec3f w, Vec3f wm) const { return D(w, wm); }

 private:
  float alphaX_, alphaY_;
};

}  // namespace glint
