// glint — ray/parallelogram in double.
#include "geometry/shapes/quad.h"

#include <cassert>

#include "geometry/shapes/primitive_math.h"

namespace glint {

using namespace prim;

Quad::Quad(Vec3f corner, Vec3f edgeU, Vec3f edgeV) : corner_(corner), edgeU_(edgeU), edgeV_(edgeV) {
  assert(isFinite(corner) && isFinite(edgeU) && isFinite(edgeV));
  V3 n = cross(V3(edgeU), V3(edgeV));
  assert(dot(n, n) > 0);
  normal_ = normalized(n);
}

Bounds3f Quad::bounds() const {
  Bounds3f b;
  V3 c(corner_), u(edgeU_), v(edgeV_);
  for (V3 p : {c, c + u, c + v, c + u + v}) {
    // Rounded outwards: the corners are sums.
    Vec3f lo, hi;
    for (int i = 0; i < 3; ++i) {
      float f = float(p[i]);
      lo[i] = double(f) > p[i] ? nextFloatDown(f) : f;
      hi[i] = double(f) < p[i] ? nextFloatUp(f) : f;
    }
    b.extend(lo);
    b.extend(hi);
  }
  return b;
}

void Quad::coordinates(const double p[3], double* a, double* b) const {
  V3 w = V3(p[0], p[1], p[2]) - V3(corner_), u(edgeU_), v(edgeV_);
  V3 n = cross(u, v);
  double nn = dot(n, n);
  *a = dot(n, cross(w, v)) / nn;
  *b = dot(n, cross(u, w)) / nn;
}

bool Quad::intersect(const Ray& ray, ShapeHit* hit) const {
  V3 u(edgeU_), v(edgeV_), d(ray.d), rel = V3(corner_) - V3(ray.o);
  V3 n = cross(u, v);
  V3 absN{std::abs(u.y * v.z) + std::abs(u.z * v.y), std::abs(u.z * v.x) + std::abs(u.x * v.z),
          std::abs(u.x * v.y) + std::abs(u.y * v.x)};
  double den = dot(d, n);
  if (den == 0) return false;
  double num = dot(rel, n);
  double t = num / den;
  double e = (gammaD(6) * dot(abs(rel), absN) + std::abs(t) * gammaD(5) * dot(abs(d), absN)) /
                 std::abs(den) +
             gammaD(1) * std::abs(t);
  V3 p = V3(ray.o) + d * t;
  double pa[3] = {p.x, p.y, p.z}, a, b;
  coordinates(pa, &a, &b);
  if (a < 0 || a > 1 || b < 0 || b > 1) return false;
  Crossing c = toCrossing(t, e, 0);
  if (!accepts(ray, c)) return false;
  hit->t = c.t;
  hit->part = 0;
  return true;
}

ShapeSurface Quad::surface(const Ray& ray, const ShapeHit& hit, SurfaceDetails details) const {
  V3 pd = rayPoint(ray, hit.t);
  double pa[3] = {pd.x, pd.y, pd.z}, a, b;
  coordinates(pa, &a, &b);
  a = std::clamp(a, 0.0, 1.0), b = std::clamp(b, 0.0, 1.0);
  // Rebuilt from (a, b): on the plane up to double rounding.
  V3 c(corner_), u(edgeU_), v(edgeV_);
  V3 p = c + u * a + v * b;
  double slack =
      gammaD(8) * (dot(abs(c), V3(1, 1, 1)) + dot(abs(u), V3(1, 1, 1)) + dot(abs(v), V3(1, 1, 1)));
  ShapeSurface s;
  s.p = roundedPoint(p, {slack, slack, slack}, &s.pError);
  s.n = normal_;
  if (details.uv) s.uv = {float(a), float(b)};
  if (details.tangents) s.dpdu = edgeU_, s.dpdv = edgeV_;
  return s;
}

}  // namespace glint

// --- Sampling ---------------------------------------------------------------------------------

namespace glint {

using namespace prim;

float Quad::area() const { return length(cross(edgeU_, edgeV_)); }

std::optional<ShapeSample> Quad::sample(Vec2f u) const {
  const V3 c(corner_), eu(edgeU_), ev(edgeV_);
  ShapeSample s;
  const double slack = gammaD(4) * dot(abs(c) + abs(eu) + abs(ev), V3(1, 1, 1));
  s.p = roundedPoint(c + eu * double(u.x) + ev * double(u.y), {slack, slack, slack}, &s.pError);
  s.n = normal_;
  s.uv = u;
  s.pdf = 1 / area();
  return s;
}

std::unique_ptr<Shape> Quad::create(ShapeParameters& params) {
  const Vec3f corner = params.vector("corner");
  const Vec3f edgeU = params.vector("edge_u"), edgeV = params.vector("edge_v");
  // Relative test: the edges span a parallelogram of non-zero area.
  if (!(length(cross(edgeU, edgeV)) > 1e-6f * length(edgeU) * length(edgeV)))
    params.invalid("edge_v", "must not be parallel to 'edge_u' (or zero)");
  return std::make_unique<Quad>(corner, edgeU, edgeV);
}

}  // namespace glint
