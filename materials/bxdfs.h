// glint — the scattering functions (BxDFs) a material's BSDF is made of. Every direction is a
// unit vector pointing away from the surface, wo is the direction towards the viewer, and f
// excludes the cosine factor.
//
// A BxDF is a small value holding parameters already read from the material's textures (the
// material's `bsdf` makes one per hit, materials/material.h); none of its functions reads a
// texture or allocates. They come in two kinds, by the frame they work in:
//   - in the local shading frame (the shading normal is +Z): PhongBxdf and PbrBxdf, whose
//     lobes need the tangent directions (the mirror direction's cone, anisotropy, a coat's own
//     normal). Each offers
//       evaluate(wo, wi, &pdf)           the BSDF value f (zero for delta lobes), and in pdf the
//                                        solid-angle density of sample() over all lobes:
//                                        together, because both need the same terms (cos^n,
//                                        GGX D and G) and next-event estimation with MIS needs
//                                        both,
//       sample(wo, u, uLobe, lobes, &s)  a direction with f and pdf, restricted to `lobes`,
//                                        written to s; false when there is none (s is then
//                                        unspecified),
//       flags()                          which kinds of lobes it has at this hit;
//   - about the shading normal alone (kAboutNormal): DiffuseBxdf, MirrorBxdf, GlassBxdf, which
//     need only cosines to the normal and reflection or refraction about it. Their evaluate and
//     sample take world directions and the shading normal n first, (n, wo, wi, &pdf) and
//     (n, wo, u, uLobe, lobes, &s), so that a hit on them builds no tangent frame and
//     transforms nothing into it (the diffuse lobe builds one when it samples).
// Samples go out through a pointer rather than a returned std::optional: the optional was built
// field by field on the stack and then copied with wide loads that could not be forwarded from
// those stores (about a fifth of mirror's profile, benchmarks/README).
// Which side of the *geometric* surface a direction lies on is Bsdf's business (bsdf.h): a
// BxDF only knows the shading normal.
#pragma once

#include <cstdint>

#include "geometry/math.h"
#include "geometry/sampling.h"
#include "materials/scattering.h"

namespace glint {

enum BsdfFlags : uint32_t {
  kBsdfNone = 0,
  kBsdfUnlit = 1u << 0,  // not lit by lights: colour x |cos| towards the eye (eyelight)
  kBsdfDiffuse = 1u << 1,
  kBsdfGlossy = 1u << 2,
  kBsdfSpecular = 1u << 3,  // delta lobes (mirror, glass): f and pdf are zero
  kBsdfReflection = 1u << 4,
  kBsdfTransmission = 1u << 5,
};
// Both hemispheres: the default lobe selection of sample().
inline constexpr uint32_t kBsdfAllLobes = kBsdfReflection | kBsdfTransmission;

struct BsdfSample {
  Rgb f;  // f(wo, wi), without the cosine
  Vec3f wi;
  float pdf = 0;  // solid-angle density (for delta lobes: the discrete probability)
  uint32_t flags = kBsdfNone;
  float eta = 1;  // relative index of refraction crossed (transmission), else 1

  // The path throughput factor f |cos| / pdf along the normal n.
  Rgb weight(Vec3f n) const { return f * (std::abs(dot(wi, n)) / pdf); }
};

// The lobe restriction of sample(): `lobes` holds kBsdfReflection and/or kBsdfTransmission
// (the hemispheres allowed) and optionally kBsdfSpecular (delta lobes only). pdf and f are
// then those of the restricted choice, so an integrator may follow the reflected and the
// transmitted lobe separately (Whitted) or pick one (path tracing).

// Ideal diffuse reflection: f = R / pi. About the normal.
struct DiffuseBxdf {
  static constexpr bool kAboutNormal = true;
  Rgb R;

  Rgb evaluate(Vec3f n, Vec3f, Vec3f wi, float* pdf) const {
    const float cosI = dot(wi, n);
    *pdf = cosineHemispherePdf(cosI);
    return cosI > 0 ? R * kInvPi : Rgb{};
  }
  bool sample(Vec3f n, Vec3f, Vec2f u, float, uint32_t lobes, BsdfSample* s) const {
    if (!(lobes & kBsdfReflection) || (lobes & kBsdfSpecular)) return false;
    const Vec3f local = sampleCosineHemisphere(u);
    if (local.z <= 0) return false;
    s->wi = Frame::fromZ(n).fromLocal(local);
    s->f = R * kInvPi;
    s->pdf = cosineHemispherePdf(local.z);
    s->flags = kBsdfDiffuse | kBsdfReflection;
    s->eta = 1;
    return true;
  }
  uint32_t flags() const { return kBsdfDiffuse | kBsdfReflection; }
};

// A diffuse lobe plus an energy-normalised cos^n specular lobe (kd + ks <= 1 per channel never
// reflects more than it receives; the scene builder checks it):
//   Phong (Lafortune & Willems 1994): ks (n+2)/(2 pi) cos^n(alpha), alpha between wi and the
//     mirror direction of wo.
//   Blinn-Phong, in Ashikhmin & Shirley's (2000) normalisation:
//     ks (n+1)/(8 pi) cos^n(theta_h) / ((h.wi) max(cos theta_i, cos theta_o)),
//     whose cosine-weighted integral is at most 1 for every wo (the classic (n+8)/(8 pi)
//     factor exceeds 1 near normal incidence).
// The specular lobe is sampled with probability ks / (kd + ks) (luminances).
struct PhongBxdf {
  static constexpr bool kAboutNormal = false;
  Rgb kd, ks;
  float shininess = 1;
  bool blinn = false;
  float pSpecular = 0;  // set by the constructor

  // noexcept here and in PbrBxdf: std::variant's emplace then builds the BxDF in place, where
  // otherwise it builds a temporary variant and copies it.
  PhongBxdf(Rgb kd, Rgb ks, float shininess, bool blinn) noexcept;
  Rgb evaluate(Vec3f wo, Vec3f wi, float* pdf) const;
  bool sample(Vec3f wo, Vec2f u, float uLobe, uint32_t lobes, BsdfSample* s) const;
  uint32_t flags() const { return kBsdfDiffuse | kBsdfGlossy | kBsdfReflection; }
  float narrowestAlpha() const;
  float diffuseProbability() const { return 1 - pSpecular; }
};

// Reflects everything into the mirror direction, tinted by R. About the normal.
struct MirrorBxdf {
  static constexpr bool kAboutNormal = true;
  Rgb R;

  Rgb evaluate(Vec3f, Vec3f, Vec3f, float* pdf) const { return *pdf = 0, Rgb{}; }
  bool sample(Vec3f n, Vec3f wo, Vec2f, float, uint32_t lobes, BsdfSample* s) const {
    if (!(lobes & kBsdfReflection)) return false;
    const float cosO = dot(wo, n);
    if (cosO == 0) return false;
    s->wi = n * (2 * cosO) - wo;
    s->f = R / std::abs(cosO);
    s->pdf = 1;
    s->flags = kBsdfSpecular | kBsdfReflection;
    s->eta = 1;
    return true;
  }
  uint32_t flags() const { return kBsdfSpecular | kBsdfReflection; }
};

// A smooth dielectric interface (Snell's law, exact Fresnel, total internal reflection). eta is
// the relative index across the surface for light leaving wo's side: the material's index
// when the ray arrives on the front face, its inverse from inside. T tints the refracted
// light; radiance crossing is scaled by 1/eta^2 (compressed into a narrower cone). About the
// normal.
struct GlassBxdf {
  static constexpr bool kAboutNormal = true;
  float eta = 1.5f;
  Rgb T{1, 1, 1};

  Rgb evaluate(Vec3f, Vec3f, Vec3f, float* pdf) const { return *pdf = 0, Rgb{}; }
  bool sample(Vec3f n, Vec3f wo, Vec2f, float uLobe, uint32_t lobes, BsdfSample* s) const {
    const float cosO = dot(wo, n);
    const float R = fresnelDielectric(cosO, eta), Tr = 1 - R;
    const float pr = (lobes & kBsdfReflection) ? R : 0;
    const float pt = (lobes & kBsdfTransmission) ? Tr : 0;
    if (pr + pt <= 0) return false;
    if (uLobe < pr / (pr + pt)) {
      if (cosO == 0) return false;
      s->wi = n * (2 * cosO) - wo;
      s->f = Rgb{R, R, R} / std::abs(cosO);
      s->pdf = pr / (pr + pt);
      s->flags = kBsdfSpecular | kBsdfReflection;
      s->eta = 1;
      return true;
    }
    float etaCrossed = 1;
    if (!refract(wo, n, eta, &etaCrossed, &s->wi)) return false;
    const float cosI = std::abs(dot(s->wi, n));
    if (cosI == 0) return false;
    s->f = T * (Tr / (cosI * etaCrossed * etaCrossed));
    s->pdf = pt / (pr + pt);
    s->flags = kBsdfSpecular | kBsdfTransmission;
    s->eta = etaCrossed;
    return true;
  }
  uint32_t flags() const { return kBsdfSpecular | kBsdfReflection | kBsdfTransmission; }
};

// One hit's values of the glTF material (pbr.h), read from its textures by PbrMaterial: the
// metallic-roughness base and the layers of glTF's material extensions. Defaults leave a layer
// out. Directions (coatNormal, anisotropyDirection) are in the BSDF's local shading frame.
struct PbrHit {
  Rgb base{1, 1, 1};
  float metallic = 0, roughness = 1;
  float transmission = 0;      // KHR_materials_transmission
  float eta = 1.5f;            // relative index across the surface seen from wo's side
  bool thinWalled = false;     // transmission passes a thin sheet (no refraction, no volume)
  float specular = 1;          // KHR_materials_specular: strength
  Rgb specularColor{1, 1, 1};  //   and colour of the dielectric's F0
  float clearcoat = 0, clearcoatRoughness = 0;  // KHR_materials_clearcoat
  Vec3f coatNormal{0, 0, 1};
  Rgb sheenColor{0, 0, 0};  // KHR_materials_sheen
  float sheenRoughness = 0;
  float diffuseTransmission = 0;  // KHR_materials_diffuse_transmission
  Rgb diffuseTransmissionColor{1, 1, 1};
  float iridescence = 0, iridescenceIor = 1.3f, iridescenceThickness = 0;  // nm
  float anisotropy = 0;             // KHR_materials_anisotropy: strength in [0, 1]
  Vec2f anisotropyDirection{1, 0};  //   and the direction of the stretched roughness
  float dispersion = 0;             // KHR_materials_dispersion (20 / Abbe number)
};

// glTF's metallic-roughness model with its material extensions (see pbr.h for the model and
// its deliberate changes): GGX reflection (Schlick-tinted for the metal, exact Fresnel with
// KHR_materials_specular's colour and strength, or a thin film's, for the dielectric; Kulla-
// Conty multiple scattering for the metal), a diffuse layer and diffuse transmission under the
// specular reflection's albedo scaling, GGX refraction (or a thin sheet's transmission), under
// a Charlie sheen and a GGX clear coat. Below alpha 1e-3 the
// reflections and the refraction are delta lobes. The lobe weights (Fresnel at wo, the layers'
// albedos at wo) are computed once, by the constructor.
struct PbrBxdf {
  static constexpr bool kAboutNormal = false;
  // base: base colour; roughness: perceptual, in [0, 1]; metallic, transmission in [0, 1];
  // eta: relative index across the surface seen from wo's side.
  PbrBxdf(Vec3f wo, Rgb base, float metallic, float roughness, float transmission,
          float eta) noexcept;
  PbrBxdf(Vec3f wo, const PbrHit& hit) noexcept;
  // f and pdf share D, G and the half vector.
  Rgb evaluate(Vec3f wo, Vec3f wi, float* pdf) const;
  bool sample(Vec3f wo, Vec2f u, float uLobe, uint32_t lobes, BsdfSample* s) const;
  uint32_t flags() const;
  float narrowestAlpha() const;  // see Bsdf::narrowestAlpha
  float diffuseProbability() const {
    return p_.p[kDiff] + p_.p[kMulti] + p_.p[kDiffTrans] + p_.p[kSheen];
  }

  // The lobes sample() chooses among.
  // kMulti: the rough metal's multiple scattering (Kulla-Conty), sampled by its own density
  // (microfacet_albedo.h); kDiff: the dielectric's diffuse layer, by the cosine.
  enum Lobe { kCoat, kSheen, kSpec, kDiff, kMulti, kDiffTrans, kTrans, kLobeCount };
  struct LobeProbabilities {
    float p[kLobeCount] = {};
    // A rough interface that refracts: its reflection (kSpec) and refraction (kTrans) share
    // one microfacet sample, split between them by the Fresnel factor at that microfacet
    // (pbrt-v4's DielectricBxDF). `interface` = p[kSpec] + p[kTrans]; each side may be
    // masked off by the requested lobes.
    bool grouped = false, reflects = false, refracts = false;
    float interface = 0;
  };

  PbrHit hit;
  float alphaX = 1, alphaY = 1;  // GGX roughness along the (anisotropy-rotated) local x and y
  float coatAlpha = 1;
  bool smooth = false;      // the base's specular lobes are deltas
  bool coatSmooth = false;  // the coat's reflection is a delta
  bool anisotropic = false;

  // The dielectric's Fresnel reflectance (specular colour and strength, thin film) at cosine c
  // between the view and the (micro)surface normal.
  Rgb dielectricFresnel(float c) const;
  // The clear coat's Fresnel reflectance (index 1.5) times its strength.
  float coatFresnel(float c) const;
  // The dielectric's specular reflection albedo E_spec(mu) (the Fresnel-weighted GGX albedo,
  // microfacet_albedo.h; the Fresnel reflectance itself when smooth) at view cosine mu, and
  // its cosine-weighted average: what the diffuse layer's albedo scaling uses.
  Rgb dielectricAlbedo(float mu) const;
  Rgb dielectricAverageAlbedo() const;

 private:
  struct Eval {
    Rgb f;
    float pdf = 0;
  };
  Eval evaluateLocal(Vec3f wo, Vec3f wi, const LobeProbabilities& pr) const;
  // The share of a grouped interface's samples (LobeProbabilities::grouped) that reflect off
  // the microfacet of normal wm (wo . wm > 0) with the relative index `eta`.
  float reflectShare(Vec3f wo, Vec3f wm, float eta, const LobeProbabilities& pr) const;
  LobeProbabilities lobeProbabilities(uint32_t lobes) const;
  Rgb dielectricFresnel(float c, float eta) const;
  Rgb metalFresnel(float c) const;      // Schlick from the base colour, or the film on the metal
  float channelEta(int channel) const;  // the dispersed relative index of one colour channel
  // The local frame turned so that x is the anisotropy direction, and back.
  Vec3f toAniso(Vec3f v) const;
  Vec3f fromAniso(Vec3f v) const;
  // The local frame to the coat's (its normal as z), and back.
  Vec3f toCoat(Vec3f v) const;
  Vec3f fromCoat(Vec3f v) const;
  // wo's weights per lobe (their directional albedos, roughly) and what they sample by.
  float w_[kLobeCount] = {};
  LobeProbabilities p_;
  Rgb fresnelWo_;            // the dielectric's reflectance at wo.n
  float coatFresnelWo_ = 0;  // the coat's reflectance at wo (its own normal)
  // What the layers above leave the base at wo: (1 - coat F(wo)) (1 - max(sheenColor) E(wo)).
  float baseScaleWo_ = 1;
  // The perceptual roughness the albedo tables are read at (anisotropy: the geometric mean).
  float tableRoughness_ = 1;
  // The diffuse layer's albedo scaling, the part of wo: (1 - E_spec(wo)) / (1 - E_spec,avg).
  Rgb diffuseScaleWo_;
  // The rough metal's multiple-scattering lobe (Kulla-Conty), the part of wo:
  // F_ms (1 - E(wo)) / (pi (1 - E_avg)); its value at wi is that times 1 - E(wi).
  Rgb metalMultipleWo_;
  Vec3f toCoat_[3];  // rows: the coat frame's axes in the local frame
};

}  // namespace glint
