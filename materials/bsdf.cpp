// glint — the BSDF at one hit: BxDF dispatch and the geometric-side rules.
#include "materials/bsdf.h"

namespace glint {

float terminatorShadowing(Vec3f ng, Vec3f ns, Vec3f wi) {
  const float cosNs = dot(ns, wi), cosNg = dot(ng, wi), cosNsNg = dot(ns, ng);
  if (cosNs <= 0 || cosNg <= 0 || cosNsNg <= 0) return cosNg > 0 ? 1.0f : 0.0f;
  const float g = std::min(1.0f, cosNg / (cosNs * cosNsNg));
  return -g * g * g + g * g + g;  // the smooth form of the paper's eq. 4
}

Rgb Bsdf::f(Vec3f wi) const {
  if (std::holds_alternative<std::monostate>(lobes_)) return {};
  const Vec3f local = frame_.frame.toLocal(wi);
  if (!consistentSide(wi, local.z)) return {};
  Rgb f = std::visit(
      [&](const auto& b) -> Rgb {
        if constexpr (std::is_same_v<std::decay_t<decltype(b)>, std::monostate>)
          return {};
        else
          return b.f(frame_.wo, local);
      },
      lobes_);
  if (frame_.terminator && dot(wi, frame_.ng) > 0)
    f *= terminatorShadowing(frame_.ng, frame_.frame.n, wi);
  return f;
}

float Bsdf::pdf(Vec3f wi) const {
  if (std::holds_alternative<std::monostate>(lobes_)) return 0;
  const Vec3f local = frame_.frame.toLocal(wi);
  if (!consistentSide(wi, local.z)) return 0;
  return std::visit(
      [&](const auto& b) -> float {
        if constexpr (std::is_same_v<std::decay_t<decltype(b)>, std::monostate>)
          return 0;
        else
          return b.pdf(frame_.wo, local);
      },
      lobes_);
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
