// glint — the BSDF at one hit: a shading frame plus one BxDF whose parameters the material has
// already read (materials/bxdfs.h). What every integrator evaluates, samples and weighs by MIS;
// it never reads a texture and never allocates, so integrators may call it as often as they
// like (once per light in Whitted, twice per VPL in instant radiosity) and keep it (a VPL
// keeps the BSDF of its vertex).
//
// Directions here are world-space unit vectors pointing away from the surface; wo is fixed
// when the BSDF is made. Bsdf adds to the BxDF what depends on the geometric normal:
//   - reflection must stay on wo's side of the geometric surface and transmission must cross
//     it, or light would leak through a surface whose shading normal is tilted (f, pdf and
//     sample agree on this);
//   - a delta reflection about a strongly tilted shading normal that points into the surface
//     is folded back above the geometric plane (a lost ray shows as a black fringe on mirrors);
//   - bumped surfaces multiply f by the shadow-terminator term (Chiang et al. 2019).
#pragma once

#include <algorithm>
#include <optional>
#include <type_traits>
#include <utility>
#include <variant>

#include "geometry/interaction.h"
#include "materials/bxdfs.h"

namespace glint {

// The shading frame of a hit: the normals and wo in world space and, for the BxDFs that work in
// a local frame (bxdfs.h), the tangent frame about ns with wo in it. That part is built only
// for them: the lobes about the normal alone (diffuse, mirror, glass) need none.
struct BsdfFrame {
  Vec3f ns;                 // the shading normal (unit, in ng's hemisphere)
  Vec3f ng;                 // the geometric normal
  Vec3f wo;                 // towards the viewer
  bool terminator = false;  // apply the shadow-terminator term (the normal was perturbed)
  bool hasLocal = false;    // `local` and `woLocal` are set
  Frame local;              // s, t and ns
  Vec3f woLocal;            // wo in `local`
};

// Chiang, Li and Burley (2019), "Taming the Shadow Terminator": a shadowing term for shading
// normals that differ from the geometric one, smooth and 1 wherever ns = ng. Multiplying the
// reflected light by it removes the hard terminator that bump maps otherwise show on lit
// spheres, at the price of slightly darkening strongly bumped grazing regions.
// Inline: instant radiosity's VPL loop applies it twice per VPL.
inline float terminatorShadowing(Vec3f ng, Vec3f ns, Vec3f wi) {
  const float cosNs = dot(ns, wi), cosNg = dot(ng, wi), cosNsNg = dot(ns, ng);
  if (cosNs <= 0 || cosNg <= 0 || cosNsNg <= 0) return cosNg > 0 ? 1.0f : 0.0f;
  const float g = std::min(1.0f, cosNg / (cosNs * cosNsNg));
  return -g * g * g + g * g + g;  // the smooth form of the paper's eq. 4
}

class Bsdf {
 public:
  using Lobes =
      std::variant<std::monostate, DiffuseBxdf, PhongBxdf, MirrorBxdf, GlassBxdf, PbrBxdf>;

  // No scattering at all (unlit materials): f, pdf zero, sample() fails, flags() none.
  Bsdf() = default;
  // The BSDF at si: makeLobes(this) puts the material's lobes in place (emplace), then the
  // frame of si.ns, si.ng and si.wo is set. Built in place, neither is copied (a copied frame
  // and variant were a large part of a mirror hit's time). The frame comes last so that a
  // caller that inlines evaluate() and sample() (the integrators) takes ns, ng and wo from the
  // values just stored rather than loading them back after the material's virtual call: a
  // 12-byte vector loaded across two recent stores cannot be forwarded from them, and such
  // loads stood out in mirror's profile.
  template <class MakeLobes>
  Bsdf(const SurfaceInteraction& si, bool perturbed, MakeLobes&& makeLobes) {
    makeLobes(this);
    frame_.ns = si.ns;
    frame_.ng = si.ng;
    frame_.wo = si.wo;
    frame_.terminator = perturbed;
    if (!frame_.hasLocal && inLocalFrame()) buildLocalFrame(si);
  }
  // Makes the lobes a BxDF of type B built from args, in place. Aggregates (DiffuseBxdf,
  // MirrorBxdf, GlassBxdf) are built from parentheses only by compilers with C++20's
  // parenthesised aggregate initialisation (GCC 10, Clang 16; Debian 12's Clang 14 has not):
  // there they are built with braces and moved in (a few floats).
  template <class B, class... Args>
  B& emplace(Args&&... args) {
    if constexpr (std::is_constructible_v<B, Args&&...>)
      return lobes_.template emplace<B>(std::forward<Args>(args)...);
    else
      return lobes_.template emplace<B>(B{std::forward<Args>(args)...});
  }
  // The local part of si's frame, built now: for a material that takes directions into it
  // before it makes its BxDF (glTF's anisotropy direction and coat normal).
  const BsdfFrame& buildLocalFrame(const SurfaceInteraction& si) {
    frame_.local = Frame::fromZ(si.ns);
    frame_.woLocal = frame_.local.toLocal(si.wo);
    frame_.hasLocal = true;
    return frame_;
  }

  // f(wo, wi) without the cosine (zero for delta lobes), and in *pdf the solid-angle density
  // with which sample() (all lobes) returns wi: one evaluation for both (MIS needs both).
  // Always inline (as sample()): integrators call it once per light sample, and inlined it
  // reads the frame from registers (see the constructor).
  [[gnu::always_inline]] Rgb evaluate(Vec3f wi, float* pdf) const {
    *pdf = 0;
    Rgb f = dispatch([&](const auto& b) -> Rgb {
      using B = std::decay_t<decltype(b)>;
      if constexpr (std::is_same_v<B, std::monostate>) {
        return {};
      } else if constexpr (B::kAboutNormal) {
        if (!consistentSide(wi, dot(wi, frame_.ns))) return {};
        return b.evaluate(frame_.ns, frame_.wo, wi, pdf);
      } else {
        const Vec3f local = frame_.local.toLocal(wi);
        if (!consistentSide(wi, local.z)) return {};
        return b.evaluate(frame_.woLocal, local, pdf);
      }
    });
    if (frame_.terminator && dot(wi, frame_.ng) > 0)
      f *= terminatorShadowing(frame_.ng, frame_.ns, wi);
    return f;
  }
  // f alone.
  Rgb f(Vec3f wi) const {
    float unused;
    return evaluate(wi, &unused);
  }
  // Samples wi given two uniform numbers for the direction and one for the lobe choice,
  // restricted to `lobes` (see bxdfs.h), into *s. False when there is no sample (*s is then
  // unspecified).
  [[gnu::always_inline]] bool sample(Vec2f u, float uLobe, BsdfSample* s,
                                     uint32_t lobes = kBsdfAllLobes) const {
    float cosI = 0;  // wi's cosine to the shading normal
    const bool sampled = dispatch([&](const auto& b) {
      using B = std::decay_t<decltype(b)>;
      if constexpr (std::is_same_v<B, std::monostate>) {
        return false;
      } else if constexpr (B::kAboutNormal) {
        if (!b.sample(frame_.ns, frame_.wo, u, uLobe, lobes, s)) return false;
        cosI = dot(s->wi, frame_.ns);
        return true;
      } else {
        if (!b.sample(frame_.woLocal, u, uLobe, lobes, s)) return false;
        cosI = s->wi.z;
        s->wi = frame_.local.fromLocal(s->wi);
        return true;
      }
    });
    if (!sampled) return false;
    const Vec3f ng = frame_.ng;
    if (s->flags & kBsdfSpecular) {
      if ((s->flags & kBsdfReflection) && dot(s->wi, ng) <= 0) return foldReflection(cosI, s);
      return consistentSide(s->wi, cosI);
    }
    if (!consistentSide(s->wi, cosI)) return false;
    if (frame_.terminator && dot(s->wi, ng) > 0) s->f *= terminatorShadowing(ng, frame_.ns, s->wi);
    return true;
  }
  // The same as an optional, for callers outside the integrators' inner loops (tests).
  std::optional<BsdfSample> sample(Vec2f u, float uLobe, uint32_t lobes = kBsdfAllLobes) const {
    BsdfSample s;
    if (!sample(u, uLobe, &s, lobes)) return std::nullopt;
    return s;
  }
  // The density alone.
  float pdf(Vec3f wi) const {
    float p;
    evaluate(wi, &p);
    return p;
  }
  // The kinds of lobes at this hit (kBsdfNone when it does not scatter).
  uint32_t flags() const;
  // The narrowest lobe sample() can choose, as a microfacet roughness alpha: 0 for a delta
  // lobe, 1 when no lobe is narrower than a diffuse one (Lambert; Phong by its exponent,
  // Walter et al.'s alpha = sqrt(2 / (n + 2))).
  float narrowestAlpha() const;
  // The probability with which sample() picks a diffuse-like lobe (Lambert, Phong's diffuse,
  // glTF's diffuse layers, sheen, a rough metal's multiple scattering): 1 for Lambert, 0 for a
  // mirror.
  float diffuseProbability() const;
  // The shading normal the BSDF is built around.
  Vec3f ns() const { return frame_.ns; }

  // A caller evaluating one BSDF in many directions (instant radiosity's VPL loop) can skip
  // the general evaluation for a Lambert lobe: f(wi) is then R / pi where wi is on the side of
  // both the shading and the geometric normal, zero elsewhere, times the terminator term where
  // the normal was perturbed. lambertR() returns R / pi for a Lambert BSDF (nullopt for every
  // other), lambertF() computes f from it exactly as f() does.
  std::optional<Rgb> lambertR() const {
    const DiffuseBxdf* d = std::get_if<DiffuseBxdf>(&lobes_);
    if (!d) return std::nullopt;
    return d->R * kInvPi;
  }
  Rgb lambertF(Vec3f wi, Rgb rOverPi) const {
    return lambertF(wi, frame_.ns, frame_.ng, frame_.terminator, rOverPi);
  }
  // The same for a BSDF known by its normals and terminator flag (kept apart by the caller).
  static Rgb lambertF(Vec3f wi, Vec3f ns, Vec3f ng, bool terminator, Rgb rOverPi) {
    if (!(dot(wi, ns) > 0) || !(dot(wi, ng) > 0)) return {};
    return terminator ? rOverPi * terminatorShadowing(ng, ns, wi) : rOverPi;
  }
  // The geometric normal, and whether the terminator term applies.
  Vec3f ng() const { return frame_.ng; }
  bool terminator() const { return frame_.terminator; }

  // What a shadow ray crossing this surface along `w`, straight and unrefracted, keeps: the
  // tint of the surface's specular transmission and its Fresnel reflectance R, taken from the
  // outside (the side the surface's front faces; `frontFace` says whether this hit is on that
  // side) at w's angle to the shading normal, so that a pane's entry and exit see the same R
  // as the refracted light really does. Zero tint for a surface light cannot cross straight
  // (everything but glass and glTF transmission). Whitted's shadows through glass
  // (WhittedIntegrator) combine two crossings into the pane's (1 - R)^2 / (1 - R^2).
  struct StraightCrossing {
    Rgb tint;
    float R = 0;
  };
  StraightCrossing straightCrossing(Vec3f w, bool frontFace) const;

 private:
  // A delta reflection s (cosine cosI to ns) that points below the geometric surface, folded
  // back above it; false if that fails.
  bool foldReflection(float cosI, BsdfSample* s) const;
  // Whether the lobes work in the local frame.
  bool inLocalFrame() const {
    return std::holds_alternative<PhongBxdf>(lobes_) || std::holds_alternative<PbrBxdf>(lobes_);
  }
  // Calls f with the BxDF the lobes hold (std::monostate for none). Written out rather than
  // std::visit, which GCC does not inline here: that was a call per evaluation, a quarter of
  // mirror's profile.
  template <class F>
  auto dispatch(F&& f) const -> decltype(f(std::monostate{})) {
    if (const auto* b = std::get_if<DiffuseBxdf>(&lobes_)) return f(*b);
    if (const auto* b = std::get_if<MirrorBxdf>(&lobes_)) return f(*b);
    if (const auto* b = std::get_if<GlassBxdf>(&lobes_)) return f(*b);
    if (const auto* b = std::get_if<PhongBxdf>(&lobes_)) return f(*b);
    if (const auto* b = std::get_if<PbrBxdf>(&lobes_)) return f(*b);
    return f(std::monostate{});
  }
  // Whether world direction wi (cosine `z` to the shading normal) is on the geometric side its
  // lobe needs.
  bool consistentSide(Vec3f wi, float z) const {
    const float g = dot(wi, frame_.ng);
    return z > 0 ? g > 0 : g < 0;
  }

  BsdfFrame frame_;
  Lobes lobes_;
};

}  // namespace glint
