// glint — bump mapping, normal maps and snow.
#include "materials/bump.h"

#include <algorithm>
#include <cmath>

#include "geometry/mesh.h"

namespace glint {

Vec3f clampToHemisphere(Vec3f ns, Vec3f ng) {
  // Keep at least ~1 degree above the surface so the shading frame stays well defined.
  constexpr float kMinCos = 0.02f;
  const float c = dot(ns, ng);
  if (c >= kMinCos) return ns;
  return normalize(ns + ng * (kMinCos - c));
}

Vec3f reflectionSafeNormal(Vec3f ns, Vec3f ng, Vec3f wo) {
  const float z = dot(wo, ng);  // >= 0: ng faces wo
  const float q = std::min(0.9f * z, 0.01f);
  const float c = dot(ns, ng);
  if (2 * dot(wo, ns) * c - z >= q) return ns;  // reflect(wo, ns) . ng
  // n(theta) = cos(theta) ng + sin(theta) x, with x the unit tangential part of ns: then
  // reflect(wo, n) . ng = 2 (wo.n)(n.ng) - z = wx sin(2 theta) + z cos(2 theta)
  //                     = A cos(2 theta - phi),  A = |(wx, z)|, phi = atan2(wx, z).
  // It is z >= q at theta = 0 and below q at ns's own angle, so the largest theta that keeps
  // it at q is (phi + acos(q / A)) / 2.
  Vec3f x = ns - ng * c;
  const float lx = length(x);
  if (!(lx > 0)) return ns;  // ns = ng: the mirror direction is wo's own height above
  x = x / lx;
  const float wx = dot(wo, x);
  const float A = std::sqrt(wx * wx + z * z);
  if (!(A > 0)) return ng;
  const float theta = 0.5f * (std::atan2(wx, z) + std::acos(std::clamp(q / A, -1.0f, 1.0f)));
  if (!(theta > 0)) return ng;
  return normalize(ng * std::cos(theta) + x * std::sin(theta));
}

// ---------------------------------------------------------------------------------------------
// Bump mapping
// ---------------------------------------------------------------------------------------------

Vec2f BumpMap::heightDerivatives(const SurfaceInteraction& si, bool forceFiniteDifferences) const {
  TexturePoint tp(si);
  Vec3f gradient;
  if (!forceFiniteDifferences && height_->scalarGradient(tp, &gradient))
    return Vec2f{dot(gradient, si.dpdu), dot(gradient, si.dpdv)} * strength_;
  // Central differences over half the pixel footprint in u and v (pbrt's choice), or a small
  // fixed fraction of the uv unit when the footprint is unknown.
  auto step = [](float a, float b) {
    float d = 0.5f * (std::abs(a) + std::abs(b));
    return d > 0 ? d : 5e-4f;
  };
  const float du = step(si.duvdx.x, si.duvdy.x), dv = step(si.duvdx.y, si.duvdy.y);
  auto heightAt = [&](float su, float sv) {
    TexturePoint q = tp;
    q.p = tp.p + si.dpdu * su + si.dpdv * sv;
    q.uv = tp.uv + Vec2f{su, sv};
    return height_->scalar(q);
  };
  return Vec2f{(heightAt(du, 0) - heightAt(-du, 0)) / (2 * du),
               (heightAt(0, dv) - heightAt(0, -dv)) / (2 * dv)} *
         strength_;
}

void BumpMap::apply(SurfaceInteraction& si) const {
  if (lengthSquared(cross(si.dpdu, si.dpdv)) == 0) return;
  const Vec2f dh = heightDerivatives(si, false);
  const Vec3f n = si.ns;
  // Displace the shading surface, whose tangent plane is ns's: a smooth-shaded triangle's
  // dp/du and dp/dv span its flat face, and their cross product would replace the
  // interpolated normal by the face normal (facets) even where the height is constant.
  const Vec3f dpdu = si.dpdu - n * (dot(n, si.dpdu) - dh.x);
  const Vec3f dpdv = si.dpdv - n * (dot(n, si.dpdv) - dh.y);
  Vec3f bumped = cross(dpdu, dpdv);
  // cross(dp/du, dp/dv) may face either side; the bumped normal keeps the side of ns.
  if (dot(cross(si.dpdu, si.dpdv), n) < 0) bumped = -bumped;
  const float len = length(bumped);
  if (!(len > 0) || !std::isfinite(len)) return;
  si.ns = clampToHemisphere(bumped / len, si.ng);
  si.dpdu = dpdu;
  si.dpdv = dpdv;
}

// ---------------------------------------------------------------------------------------------
// Normal maps
// ---------------------------------------------------------------------------------------------

namespace {
// dp/du1 and dp/dv1 from dp/du, dp/dv and J = d uv1 / d uv (columns si.duv1du = (a, c),
// si.duv1dv = (b, d)): dp/d uv1 = dp/d uv J^-1, whose columns are (d dp/du - c dp/dv) / det J
// and (a dp/dv - b dp/du) / det J. dp/du and dp/dv where J is singular (no second set: J is
// the identity).
void dpdUv1(const SurfaceInteraction& si, Vec3f* dpdu1, Vec3f* dpdv1) {
  const float a = si.duv1du.x, c = si.duv1du.y, b = si.duv1dv.x, d = si.duv1dv.y;
  const float det = a * d - b * c;
  if (!(std::abs(det) > 1e-12f) || !std::isfinite(det)) {
    *dpdu1 = si.dpdu, *dpdv1 = si.dpdv;
    return;
  }
  *dpdu1 = (si.dpdu * d - si.dpdv * c) / det;
  *dpdv1 = (si.dpdv * a - si.dpdu * b) / det;
}
}  // namespace

bool tangentFrame(const SurfaceInteraction& si, Vec3f front, Vec3f* t, Vec3f* b, int uvSet) {
  const bool given = lengthSquared(si.tangent) > 0;
  Vec3f dpdu = si.dpdu, dpdv = si.dpdv;
  if (!given && uvSet == 1) dpdUv1(si, &dpdu, &dpdv);
  const Vec3f source = given ? si.tangent : dpdu;
  const Vec3f projected = source - front * dot(front, source);
  if (!(lengthSquared(projected) > 0)) return false;
  *t = normalize(projected);
  // Without a TANGENT (analytic shapes, meshes whose material gained a normal map after
  // loading; scenes/build.cpp derives per-vertex tangents for the rest) the handedness comes
  // from the uv layout, so that a mirrored layout is not shown inverted (the Khronos reference
  // viewer's cross(n, t) alone inverts it).
  *b = cross(front, *t) * (given ? si.bitangentSign : uvHandedness(front, dpdu, dpdv));
  return true;
}

void NormalMap::apply(SurfaceInteraction& si) const {
  // Work in the front face's frame (as the glTF reference viewer does) and flip the result
  // for back faces, so a double-sided surface shows the same relief from both sides.
  // The tangent is the mesh's TANGENT when it has one (with its bitangent handedness), else
  // dp/du from the UVs, as glTF prescribes: bitangent = cross(normal, tangent) * w.
  const Vec3f front = si.frontFace ? si.ns : -si.ns;
  Vec3f t, b;
  if (!tangentFrame(si, front, &t, &b, map_->uvSet())) {  // any frame around the normal
    t = Frame::fromZ(front).s;
    b = cross(front, t) * (lengthSquared(si.tangent) > 0 ? si.bitangentSign : 1.0f);
  }
  const Vec4f c = map_->evaluate(TexturePoint(si));
  const Vec3f local{(2 * c.x - 1) * scale_, (2 * c.y - 1) * scale_, 2 * c.z - 1};
  Vec3f m = t * local.x + b * local.y + front * local.z;
  const float len = length(m);
  if (!(len > 0) || !std::isfinite(len)) return;
  m = m / len;
  si.ns = clampToHemisphere(si.frontFace ? m : -m, si.ng);
}

// ---------------------------------------------------------------------------------------------
// Snow
// ---------------------------------------------------------------------------------------------

void SnowPerturbation::apply(SurfaceInteraction& si) const {
  const Vec3f p = si.objectFromWorld ? si.objectFromWorld->point(si.p) : si.p;
  uint64_t key = mixBits(seed_ + 0x9e3779b97f4a7c15ull);
  for (int axis = 0; axis < 3; ++axis)
    key = mixBits(key ^ uint64_t(int64_t(std::floor(p[axis] / grain_))));
  // A random vector in the unit ball, by rejection from a deterministic sequence.
  Vec3f v;
  for (uint64_t i = 0;; ++i) {
    uint64_t h = mixBits(key + i);
    auto unit = [](uint64_t bits) { return float(bits & 0x1fffff) * 0x1p-20f - 1.0f; };
    v = {unit(h), unit(h >> 21), unit(h >> 42)};
    if (lengthSquared(v) <= 1 || i == 16) break;
  }
  Vec3f n = si.ns + v * amount_;
  const float len = length(n);
  if (!(len > 0)) return;
  si.ns = clampToHemisphere(n / len, si.ng);
}

}  // namespace glint
