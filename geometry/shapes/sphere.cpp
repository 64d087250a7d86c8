// glint — ray/sphere intersection: closest-approach discriminant, stable quadratic, in double
// with conservative error bounds (see primitive_math.h).
#include "geometry/shapes/sphere.h"

#include <cassert>
#include <numbers>

#include "geometry/shapes/primitive_math.h"

namespace glint {

using namespace prim;

Sphere::Sphere(Vec3f center, float radius) : center_(center), radius_(radius) {
  assert(isFinite(center) && std::isfinite(radius) && radius > 0);
}

Bounds3f Sphere::bounds() const {
  Vec3f r{radius_, radius_, radius_};
  // Round outwards so the float box contains the exact ball.
  Bounds3f b{center_ - r, center_ + r};
  for (int i = 0; i < 3; ++i)
    b.lower[i] = nextFloatDown(b.lower[i]), b.upper[i] = nextFloatUp(b.upper[i]);
  return b;
}

bool Sphere::span(const Ray& ray, Span* out) const {
  double f[3], ef[3], d[3];
  for (int i = 0; i < 3; ++i) {
    f[i] = double(ray.o[i]) - double(center_[i]);
    ef[i] = kEpsD * std::abs(f[i]);
    d[i] = ray.d[i];
  }
  Roots r;
  if (!ballRoots(f, ef, d, 3, radius_, &r)) return false;
  out->enter = toCrossing(r.t0, r.e0, 0);
  out->exit = toCrossing(r.t1, r.e1, 0);
  return true;
}

bool Sphere::intersect(const Ray& ray, ShapeHit* hit) const {
  Span s;
  return span(ray, &s) && firstAccepted(ray, s, hit);
}

ShapeSurface Sphere::surface(const Ray& ray, const ShapeHit& hit) const {
  V3 c(center_);
  V3 v = rayPoint(ray, hit.t) - c;
  double len = std::sqrt(dot(v, v));
  // Re-project onto the sphere so the only error left is the final rounding to float.
  V3 rel = len > 0 ? v * (double(radius_) / len) : V3(0, radius_, 0);
  V3 p = c + rel;
  ShapeSurface s;
  double slack = gammaD(8) * (std::abs(c.x) + std::abs(c.y) + std::abs(c.z) + radius_);
  s.p = roundedPoint(p, {slack, slack, slack}, &s.pError);
  s.n = normalized(rel);
  double cosTheta = std::clamp(rel.y / radius_, -1.0, 1.0);
  double theta = std::acos(cosTheta);
  double phi = std::atan2(rel.z, rel.x);
  if (phi < 0) phi += 2 * kPiD;
  s.uv = {float(phi / (2 * kPiD)), float(theta / kPiD)};
  // p(u, v) = c + r (sin(theta) cos(phi), cos(theta), sin(theta) sin(phi)).
  double sinTheta = std::sqrt(std::max(0.0, 1 - cosTheta * cosTheta));
  double cosPhi = std::cos(phi), sinPhi = std::sin(phi);
  s.dpdu = (V3(-rel.z, 0, rel.x) * (2 * kPiD)).toFloat();
  s.dpdv = (V3(cosTheta * cosPhi, -sinTheta, cosTheta * sinPhi) * (kPiD * radius_)).toFloat();
  return s;
}

}  // namespace glint
