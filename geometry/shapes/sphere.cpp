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

bool Sphere::span(const Ray& ray, const SurfaceTolerance& tolerance, Span* out) const {
  {
    // About half the rays Embree sends here (those that hit the bounding box) pass the ball by
    // a wide margin. In float, the line's squared distance from the centre is off by a few
    // ulps of |f|^2 (f = origin - centre); past r^2 by 1e-4 (|f|^2 + r^2), far beyond that,
    // the double solve below would find the line certainly missing too.
    const Vec3f fo = ray.o - center_;
    const float A = dot(ray.d, ray.d);
    if (A > 0) {
      const Vec3f l = fo - ray.d * (dot(fo, ray.d) / A);
      const float r2 = radius_ * radius_;
      if (dot(l, l) - r2 > 1e-4f * (dot(fo, fo) + r2)) return false;
    }
  }
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
  if (!tolerance.none()) {
    const float speed = length(ray.d);
    for (Crossing* c : {&out->enter, &out->exit}) {
      const Vec3f p = ray.o + ray.d * c->t;
      setTieWidth(c, ray, tolerance, p, (p - center_) / radius_, radius_, speed);
    }
  }
  return true;
}

bool Sphere::intersect(const Ray& ray, ShapeHit* hit) const {
  Span s;
  return span(ray, {}, &s) && firstAccepted(ray, s, hit);
}

ShapeSurface Sphere::surface(const Ray& ray, const ShapeHit& hit, SurfaceDetails details) const {
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
  if (details.uv) {
    double theta = std::acos(cosTheta);
    double phi = std::atan2(rel.z, rel.x);
    if (phi < 0) phi += 2 * kPiD;
    s.uv = {float(phi / (2 * kPiD)), float(theta / kPiD)};
  }
  if (details.tangents) {
    // p(u, v) = c + r (sin(theta) cos(phi), cos(theta), sin(theta) sin(phi)). cos(phi) and
    // sin(phi) straight from the point (x and z over their length in the xz plane), not from
    // phi; at a pole phi is atan2(0, 0) = 0.
    double sinTheta = std::sqrt(std::max(0.0, 1 - cosTheta * cosTheta));
    const double rho = std::sqrt(rel.x * rel.x + rel.z * rel.z);
    const double cosPhi = rho > 0 ? rel.x / rho : 1.0, sinPhi = rho > 0 ? rel.z / rho : 0.0;
    s.dpdu = (V3(-rel.z, 0, rel.x) * (2 * kPiD)).toFloat();
    s.dpdv = (V3(cosTheta * cosPhi, -sinTheta, cosTheta * sinPhi) * (kPiD * radius_)).toFloat();
  }
  return s;
}

}  // namespace glint

// --- Sampling ---------------------------------------------------------------------------------

namespace glint {

using namespace prim;

namespace {
// The cone a sphere subtends from a point at squared distance d2 > r^2 from its centre: the
// solid angle 2 pi (1 - cos), with 1 - cos as sin^2 / (1 + cos), which keeps its precision for
// distant spheres (where 1 - cos would cancel to nothing).
struct SubtendedCone {
  double sin2Max, cosMax, oneMinusCosMax;
  SubtendedCone(double d2, double r) {
    sin2Max = r * r / d2;
    cosMax = std::sqrt(std::max(0.0, 1 - sin2Max));
    oneMinusCosMax = sin2Max / (1 + cosMax);
  }
  double solidAngle() const { return 2 * kPiD * oneMinusCosMax; }
};

// The area density at unit-normal point (n) p of directions uniform in a cone of solid angle
// omega from ref: cos / (dist^2 omega), 0 on the side turned away.
float coneAreaDensity(V3 ref, V3 p, V3 n, double omega) {
  const V3 d = ref - p;
  const double dist2 = dot(d, d), c = dot(n, d);
  return c > 0 ? float(c / (std::sqrt(dist2) * dist2 * omega)) : 0.0f;
}

// The point of a sphere in unit outward direction `dir`, with surface()'s uv.
ShapeSample pointAt(Vec3f center, float radius, V3 dir) {
  const V3 c(center), rel = dir * double(radius);
  ShapeSample s;
  const double slack = gammaD(8) * (std::abs(c.x) + std::abs(c.y) + std::abs(c.z) + radius);
  s.p = roundedPoint(c + rel, {slack, slack, slack}, &s.pError);
  s.n = dir.toFloat();
  // surface()'s uv: around +Y from +X towards +Z, and down from +Y.
  s.uv = {float(angleAroundY(dir.x, dir.z) / (2 * kPiD)),
          float(std::acos(std::clamp(dir.y, -1.0, 1.0)) / kPiD)};
  return s;
}
}  // namespace

std::optional<ShapeSample> Sphere::sample(Vec2f u) const {
  const double y = 1 - 2 * double(u.x), rho = std::sqrt(std::max(0.0, 1 - y * y));
  const double phi = 2 * kPiD * u.y;
  ShapeSample s = pointAt(center_, radius_, {rho * std::cos(phi), y, rho * std::sin(phi)});
  s.pdf = 1 / area();
  return s;
}

std::optional<ShapeSample> Sphere::sample(Vec3f ref, Vec2f u) const {
  const V3 c(center_), f = V3(ref) - c;
  const double d2 = dot(f, f), r = radius_;
  if (d2 <= r * r) return sample(u);
  // A uniform direction in the cone, then the point it first meets on the sphere, found from
  // the angle alpha at the centre rather than by intersecting a ray (inaccurate at the edge).
  const SubtendedCone cone(d2, r);
  // With t = 1 - cos(theta) uniform in [0, 1 - cosMax], sin^2 = t (2 - t) without cancellation.
  const double t = u.x * cone.oneMinusCosMax;
  const double cosTheta = 1 - t, sin2Theta = t * (2 - t);
  const double cosAlpha = sin2Theta / std::sqrt(cone.sin2Max) +
                          cosTheta * std::sqrt(std::max(0.0, 1 - sin2Theta / cone.sin2Max));
  const double sinAlpha = std::sqrt(std::max(0.0, 1 - cosAlpha * cosAlpha));
  const double phi = 2 * kPiD * u.y;
  // An orthonormal frame around w = (ref - c) / |ref - c| (Duff et al.'s branchless basis).
  const V3 w = f * (1 / std::sqrt(d2));
  const double sign = std::copysign(1.0, w.z), a = -1 / (sign + w.z), b = w.x * w.y * a;
  const V3 e1(1 + sign * w.x * w.x * a, sign * b, -sign * w.x), e2(b, sign + w.y * w.y * a, -w.y);
  V3 dir = e1 * (sinAlpha * std::cos(phi)) + e2 * (sinAlpha * std::sin(phi)) + w * cosAlpha;
  dir = dir * (1 / std::sqrt(dot(dir, dir)));
  ShapeSample s = pointAt(center_, radius_, dir);
  s.pdf = coneAreaDensity(V3(ref), c + dir * r, dir, cone.solidAngle());
  return s;
}

float Sphere::pdf(Vec3f ref, Vec3f p) const {
  const V3 c(center_), f = V3(ref) - c;
  const double d2 = dot(f, f), r = radius_;
  if (d2 <= r * r) return 1 / area();
  const V3 rel = V3(p) - c;
  const V3 n = rel * (1 / std::sqrt(dot(rel, rel)));
  return coneAreaDensity(V3(ref), c + n * r, n, SubtendedCone(d2, r).solidAngle());
}

std::unique_ptr<Shape> Sphere::create(ShapeParameters& params) {
  const Vec3f center = params.vector("center", Vec3f{0, 0, 0});
  return std::make_unique<Sphere>(center, params.positive("radius"));
}

}  // namespace glint
