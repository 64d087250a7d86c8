// glint — ray/plane, in float where its error bound is tight, else in double; the solid is
// dot(p - point, n) <= 0.
#include "geometry/shapes/plane.h"

#include <cassert>
#include <cmath>

#include "geometry/shapes/primitive_math.h"

namespace glint {

using namespace prim;

Plane::Plane(Vec3f point, Vec3f normal, float uvScale)
    : point_(point), normal_(normalize(normal)), uvScale_(uvScale) {
  assert(isFinite(point) && isFinite(normal) && lengthSquared(normal) > 0 && uvScale > 0);
  frame_ = Frame::fromZ(normal_);
}

Bounds3f Plane::bounds() const {
  return {{-kInfinity, -kInfinity, -kInfinity}, {kInfinity, kInfinity, kInfinity}};
}

Plane::FloatSolve Plane::floatSolve(const Ray& ray) const {
  // With bounds on every rounding: s, the subtraction and the dot product; dn, the dot product;
  // each bound times 1 + gamma(2) for its own rounding.
  const Vec3f rel = ray.o - point_;
  FloatSolve f;
  f.s = dot(rel, normal_), f.dn = dot(ray.d, normal_);
  f.es = gamma(5) * dot(abs(rel), abs(normal_)) * (1 + gamma(2));
  f.edn = gamma(3) * dot(abs(ray.d), abs(normal_)) * (1 + gamma(2));
  return f;
}

bool Plane::span(const Ray& ray, const SurfaceTolerance& tolerance, Span* out) const {
  return spanFrom(floatSolve(ray), ray, tolerance, out);
}

bool Plane::spanFrom(const FloatSolve& f, const Ray& ray, const SurfaceTolerance& tolerance,
                     Span* out) const {
  const Crossing minusInf{-kInfinity, 0, 0}, plusInf{kInfinity, 0, 0};
  {
    // In float first (f). Where the crossing's bound is within 16u |t| (u the unit roundoff;
    // about 9u |t| for an axis-aligned plane, where the ray's origin is not close to the plane
    // and the ray does not graze it), the float crossing stands; otherwise the double solve
    // below decides. Not for CSG leaves (a tolerance given): there a crossing's error bound is
    // part of its tie width, and 16u |t| would merge faces that the double solve's ULP keeps
    // apart (a thin skin seen from afar).
    const float t = -f.s / f.dn, absT = std::abs(t);
    // The quotient of two bounded values plus its own rounding; 1 + gamma(8) covers |t| against
    // the exact quotient and the seven roundings of this line.
    const float e =
        ((f.es + absT * f.edn) / (std::abs(f.dn) - f.edn) + gamma(1) * absT) * (1 + gamma(8));
    if (tolerance.none() && std::abs(f.dn) > 2 * f.edn && std::isfinite(t) &&
        e <= 16 * kMachineEpsilon * absT) {
      const Crossing c{t, e, 0};
      *out = f.dn > 0 ? Span{minusInf, c} : Span{c, plusInf};
      return true;
    }
  }
  V3 n(normal_), rel = V3(ray.o) - V3(point_), d(ray.d);
  double s = dot(rel, n), es = gammaD(4) * dot(abs(rel), abs(n));
  double dn = dot(d, n), edn = gammaD(3) * dot(abs(d), abs(n));
  if (dn == 0) {
    if (s > 0) return false;
    *out = {minusInf, plusInf};
    return true;
  }
  double t = -s / dn;
  double e = (es + std::abs(t) * edn) / std::abs(dn) + gammaD(1) * std::abs(t);
  Crossing c = toCrossing(t, e, 0);
  if (!tolerance.none()) setTieWidth(&c, ray, tolerance, normal_);
  // Moving along the normal means leaving the half-space.
  *out = dn > 0 ? Span{minusInf, c} : Span{c, plusInf};
  return true;
}

bool Plane::intersect(const Ray& ray, ShapeHit* hit) const {
  // Most rays meet the plane behind their origin: shadow rays leaving a floor, or any ray
  // above it heading up. "Certainly on one side and certainly heading away", by the float
  // bounds, settles them; the rest take the span from the same float values.
  const FloatSolve f = floatSolve(ray);
  if (ray.tMin >= 0 && ((f.s > f.es && f.dn > f.edn) || (f.s < -f.es && f.dn < -f.edn)))
    return false;
  Span s;
  return spanFrom(f, ray, {}, &s) && firstAccepted(ray, s, hit);
}

ShapeSurface Plane::surface(const Ray& ray, const ShapeHit& hit, SurfaceDetails details) const {
  // In float. p = o + t d is near the hit; projecting it onto the plane leaves it off the
  // plane by the projection's own roundings alone, whatever p's error was (so pError bounds
  // the distance to the plane, which is what spawned rays must clear; where on the plane the
  // hit lies is t's business). With rel = p - q and s = rel . n (both rounded): s is within
  // gamma(4) sum_j |rel_j n_j| of the exact signed distance (the subtraction and the dot
  // product); n_i s inherits that times |n_i|, plus gamma(3) |n_i s| for n's own length
  // (|n|^2 = 1 within a few ulps) and the product's rounding; the final subtraction rounds
  // once more, u |on_i|. The bound therefore grows with the distance from the plane's anchor
  // point only through rel, and with the point's magnitude only by its last rounding: two
  // float steps at 1e6, where summing every coordinate (an earlier bound) offset shadow rays
  // by 3 units and lost every shadow on a floor there.
  const Vec3f p = ray.o + ray.d * hit.t;
  const Vec3f rel = p - point_;
  const float dist = dot(rel, normal_);
  const Vec3f on = p - normal_ * dist;
  const float along = gamma(4) * dot(abs(rel), abs(normal_)) + gamma(3) * std::abs(dist);
  ShapeSurface s;
  s.p = on;
  for (int i = 0; i < 3; ++i)  // 1 + gamma(4): this line's own roundings
    s.pError[i] =
        nextFloatUp((std::abs(normal_[i]) * along + gamma(1) * std::abs(on[i])) * (1 + gamma(4)));
  s.n = normal_;
  if (details.uv) {
    const Vec3f onPlane = on - point_;
    s.uv = {dot(onPlane, frame_.s) / uvScale_, dot(onPlane, frame_.t) / uvScale_};
  }
  if (details.tangents) s.dpdu = frame_.s * uvScale_, s.dpdv = frame_.t * uvScale_;
  return s;
}

std::unique_ptr<Shape> Plane::create(ShapeParameters& params) {
  const Vec3f point = params.vector("point", Vec3f{0, 0, 0});
  const Vec3f n = params.vector("normal", Vec3f{0, 1, 0});
  if (n == Vec3f{}) params.invalid("normal", "must not be zero");
  // Normalized in double: tiny or huge components would under- or overflow in float.
  const double len = std::sqrt(double(n.x) * n.x + double(n.y) * n.y + double(n.z) * n.z);
  const Vec3f unit{float(n.x / len), float(n.y / len), float(n.z / len)};
  return std::make_unique<Plane>(point, unit, params.positive("uv_scale", 1.0f));
}

}  // namespace glint
