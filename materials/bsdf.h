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
#include <variant>

#include "geometry/interaction.h"
#include "materials/bxdfs.h"

namespace glint {

// The shading frame of a hit: ns (+Z), the geometric normal, and wo in local coordinates.
struct BsdfFrame {
  Frame frame;
  Vec3f ng;
  Vec3f wo;                 // local
  bool terminator = false;  // apply the shadow-terminator term (the normal was perturbed)

  BsdfFrame() = default;
  BsdfFrame(const SurfaceInteraction& si, bool perturbed)
      : frame(Frame::fromZ(si.ns)), ng(si.ng), wo(frame.toLocal(si.wo)), terminator(perturbed) {}
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
  Bsdf(const BsdfFrame& frame, Lobes lobes) : frame_(frame), lobes_(std::move(lobes)) {}

  // f(wo, wi) without the cosine (zero for delta lobes), and in *pdf the solid-angle density
  // with which sample() (all lobes) returns wi: one evaluation for both (MIS needs both).
  Rgb evaluate(Vec3f wi, float* pdf) const;
  // f alone.
  Rgb f(Vec3f wi) const {
    float unused;
    return evaluate(wi, &unused);
  }
  // Samples wi given two uniform numbers for the direction and one for the lobe choice,
  // restricted to `lobes` (see bxdfs.h).
  std::optional<BsdfSample> sample(Vec2f u, float uLobe, uint32_t lobes = kBsdfAllLobes) const;
  // The density alone.
  float pdf(Vec3f wi) const {
    float p;
    evaluate(wi, &p);
    return p;
  }
  // The kinds of lobes at this hit (kBsdfNone when it does not scatter).
  uint32_t flags() const;
  // The shading normal the BSDF is built around.
  Vec3f ns() const { return frame_.frame.n; }

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
    return lambertF(wi, frame_.frame.n, frame_.ng, frame_.terminator, rOverPi);
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
  // Whether world direction wi (local z `z`) is on the geometric side its lobe needs.
  bool consistentSide(Vec3f wi, float z) const {
    const float g = dot(wi, frame_.ng);
    return z > 0 ? g > 0 : g < 0;
  }

  BsdfFrame frame_;
  Lobes lobes_;
};


}  // namespace glint
