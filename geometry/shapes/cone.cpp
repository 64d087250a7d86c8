// glint — ray/cone: the quadratic x^2 + z^2 = k^2 (h - y)^2 solved in double from the point of
// the line closest to the apex (less cancellation for far rays), restricted to the lower
// nappe and clipped by the y slab; one crossing per boundary event even on the base rim.
#include "geometry/shapes/cone.h"

#include <cassert>
#include <limits>
#include <numbers>

#include "geometry/sampling.h"
#include "geometry/shapes/primitive_math.h"

namespace glint {

using namespace prim;

Cone::Cone(float radius, float height, bool capped)
    : radius_(radius), height_(height), capped_(capped) {
  assert(std::isfinite(radius) && std::isfinite(height) && radius > 0 && height > 0);
}

Bounds3f Cone::bounds() const { return {{-radius_, 0, -radius_}, {radius_, height_, radius_}}; }

bool Cone::nappeSpan(const Ray& ray, Span* out, double tRoot[2]) const {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  double h = height_, k2 = (double(radius_) * radius_) / (h * h);
  V3 o(ray.o), d(ray.d);
  // Start from the point of the line closest to the apex.
  V3 apex(0, h, 0);
  double dd = dot(d, d);
  double tc = dd > 0 ? dot(apex - o, d) / dd : 0;
  V3 oc = o + d * tc;
  V3 eo = (abs(o) + abs(d * tc)) * gammaD(4);
  double w = h - oc.y, ew = eo.y + gammaD(1) * (h + std::abs(oc.y));
  double A = d.x * d.x + d.z * d.z - k2 * d.y * d.y;
  double B = oc.x * d.x + oc.z * d.z + k2 * w * d.y;
  double C = oc.x * oc.x + oc.z * oc.z - k2 * w * w;
  double eA = gammaD(6) * (d.x * d.x + d.z * d.z + k2 * d.y * d.y);
  double eB = gammaD(8) * (std::abs(oc.x * d.x) + std::abs(oc.z * d.z) + k2 * std::abs(w * d.y)) +
              eo.x * std::abs(d.x) + eo.z * std::abs(d.z) + k2 * ew * std::abs(d.y);
  double eC = gammaD(8) * (oc.x * oc.x + oc.z * oc.z + k2 * w * w) +
              (2 * std::abs(oc.x) + eo.x) * eo.x + (2 * std::abs(oc.z) + eo.z) * eo.z +
              k2 * (2 * std::abs(w) + ew) * ew;
  auto shifted = [&](double t, double e) {
    return toCrossing(t + tc, e + gammaD(1) * std::abs(t + tc), 0);
  };
  const Crossing minusInf{-kInfinity, 0, 0}, plusInf{kInfinity, 0, 0};
  if (A == 0) {
    // Parallel to a generator: Q(t) = 2 B t + C <= 0 is a half-line.
    if (B == 0) {
      if (C > 0) return false;
      *out = {minusInf, plusInf};
      tRoot[0] = tRoot[1] = nan;
      return true;
    }
    double t = -C / (2 * B);
    double e = (eC + 2 * std::abs(t) * eB) / (2 * std::abs(B)) + gammaD(1) * std::abs(t);
    if (B > 0)
      *out = {minusInf, shifted(t, e)}, tRoot[0] = nan, tRoot[1] = t + tc;
    else
      *out = {shifted(t, e), plusInf}, tRoot[0] = t + tc, tRoot[1] = nan;
    return true;
  }
  double D = B * B - A * C;
  double eD = 2 * std::abs(B) * eB + eB * eB + std::abs(A) * eC + std::abs(C) * eA + eA * eC +
              gammaD(3) * (B * B + std::abs(A * C));
  if (A > 0 && D + eD < 0) return false;  // certainly misses the double cone
  Roots r;
  if (!solveQuadratic(A, eA, B, eB, C, eC, std::max(D, 0.0), eD, &r)) return false;
  Crossing c0 = shifted(r.t0, r.e0), c1 = shifted(r.t1, r.e1);
  if (A > 0) {
    // Between the roots; both on one nappe, the slab discards the upper one.
    *out = {c0, c1}, tRoot[0] = r.t0 + tc, tRoot[1] = r.t1 + tc;
  } else if (d.y < 0) {
    // Steeper than the cone, going down: the lower nappe is after the later root.
    *out = {c1, plusInf}, tRoot[0] = r.t1 + tc, tRoot[1] = nan;
  } else {
    *out = {minusInf, c0}, tRoot[0] = nan, tRoot[1] = r.t0 + tc;
  }
  return true;
}

bool Cone::span(const Ray& ray, const SurfaceTolerance& tolerance, Span* out) const {
  if (!capped_) return false;
  Span side, ys;
  double t[2];
  if (!nappeSpan(ray, &side, t)) return false;
  // Entering through y = height can only be at the apex: label it as the side.
  if (!slab(ray.o.y, ray.d.y, 0, height_, 1, 0, &ys)) return false;
  if (tolerance.none()) return intersectSpans(side, ys, out);
  // The side's normal is along (x, k rho, z); at the apex, where it has none, the direction
  // of the ray stands in (the narrowest width).
  const float k = radius_ / height_;
  auto width = [&](Crossing* c) {
    setRevolvedTieWidth(c, ray, tolerance, [&](Vec3f p, float rho) {
      return rho > 0 ? Vec3f{p.x, k * rho, p.z} / (rho * std::sqrt(1 + k * k)) : normalize(ray.d);
    });
  };
  const Span parts[2] = {side, ys};
  return leafSpan(parts, 2, std::sqrt(4 * radius_ * radius_ + height_ * height_) / length(ray.d),
                  width, out);
}

bool Cone::intersect(const Ray& ray, ShapeHit* hit) const {
  if (capped_) {
    Span s;
    return span(ray, {}, &s) && firstAccepted(ray, s, hit);
  }
  Span side;
  double t[2];
  return nappeSpan(ray, &side, t) && firstOnOpenSide(ray, side, t, height_, hit);
}

ShapeSurface Cone::surface(const Ray& ray, const ShapeHit& hit, SurfaceDetails details) const {
  V3 pd = rayPoint(ray, hit.t);
  double r = radius_, h = height_, k = r / h;
  ShapeSurface s;
  if (hit.part == 0) {
    // cos(phi) and sin(phi) straight from the point (x and z over their length in the xz
    // plane); at the apex phi is 0.
    double rho = std::sqrt(pd.x * pd.x + pd.z * pd.z);
    double cosPhi = rho > 0 ? pd.x / rho : 1.0, sinPhi = rho > 0 ? pd.z / rho : 0.0;
    // Gradient of x^2 + z^2 - k^2 (h - y)^2, written per unit radius (finite at the apex).
    s.n = normalized({cosPhi, k, sinPhi});
    // The point on the cone at height y, re-projected radially.
    auto place = [&](double y) {
      double want = k * (h - y);
      double slack = gammaD(8) * (r + h);
      s.p = roundedPoint({want * cosPhi, y, want * sinPhi}, {slack, slack, slack}, &s.pError);
      return V3(want * cosPhi, y, want * sinPhi);
    };
    double y = std::clamp(pd.y, 0.0, h);
    V3 q = place(y);
    // The side meets the base (and itself at the apex) at acute angles: a ray spawned from
    // within its offset of those edges along -n would leave through the other face. Such
    // points move along the surface just far enough (the hit is that uncertain anyway).
    double offset =
        std::abs(s.n.x) * s.pError.x + std::abs(s.n.y) * s.pError.y + std::abs(s.n.z) * s.pError.z;
    double norm = std::sqrt(1 + k * k);
    double yMin = 4 * offset * k / norm + 2 * s.pError.y;
    double wMin = 4 * offset * std::max(0.0, 1 - k * k) / (2 * k * norm) + 2 * s.pError.y;
    if (y < yMin && yMin < h / 2)
      q = place(yMin);
    else if (h - y < wMin && wMin < h / 2)
      q = place(h - wMin);
    if (details.uv) {
      double phi = rho > 0 ? std::atan2(pd.z, pd.x) : 0;
      if (phi < 0) phi += 2 * kPiD;
      s.uv = {float(phi / (2 * kPiD)), float(q.y / h)};
    }
    if (details.tangents) {
      s.dpdu = (V3(-q.z, 0, q.x) * (2 * kPiD)).toFloat();
      s.dpdv = (V3(-k * cosPhi, 1, -k * sinPhi) * h).toFloat();
    }
    return s;
  }
  double x = pd.x, z = pd.z, rho = std::sqrt(x * x + z * z);
  if (rho > r) x *= r / rho, z *= r / rho;
  double slack = gammaD(8) * r;
  s.p = roundedDiskPoint(x, 0, z, r, slack, &s.pError);
  s.n = {0, -1, 0};
  if (details.uv) s.uv = capUv(x, z, r);
  if (details.tangents) s.dpdu = {2 * radius_, 0, 0}, s.dpdv = {0, 0, 2 * radius_};
  return s;
}

}  // namespace glint

// --- Sampling ---------------------------------------------------------------------------------

namespace glint {

using namespace prim;

RevolvedView Cone::visibleFrom(Vec3f ref) const {
  if (!capped_) return {};  // an open cone shows its inside through the base: all of it
  // dot(n, p) = k h along every generator (n ∝ (cos phi, k, sin phi), k = r / h), so they face
  // ref where rho cos(phi - phiRef) > k (h - y).
  const double k = double(radius_) / height_;
  return revolvedView(ref, k * (height_ - double(ref.y)), ref.y < 0 ? 0b10u : 0u, 0b10u);
}

double Cone::visibleAreas(const RevolvedView& v, double areas[2]) const {
  const double r = radius_, h = height_;
  areas[0] = v.halfAngle * r * std::sqrt(r * r + h * h);  // of pi r L for the whole side
  areas[1] = (v.caps & 0b10) ? kPiD * r * r : 0.0;
  return areas[0] + areas[1];
}

float Cone::area() const {
  double areas[2];
  return float(visibleAreas(RevolvedView{kPiD, kPiD, capped_ ? 0b10u : 0u}, areas));
}

std::optional<ShapeSample> Cone::sampleVisible(const RevolvedView& v, Vec2f u) const {
  double areas[2];
  const double total = visibleAreas(v, areas);
  const int part = pickPart(areas, 2, total, &u.x);
  const double r = radius_, h = height_;
  ShapeSample s;
  s.pdf = float(1 / total);
  if (part == 0) {
    // The area within distance t of the apex grows as t^2: t = sqrt(u) is uniform by area.
    const double t = std::sqrt(double(u.x));
    const double phi = v.phi0 + v.halfAngle * (2 * double(u.y) - 1);
    const double c = std::cos(phi), sn = std::sin(phi), y = h * (1 - t);
    const double slack = gammaD(8) * (r + h);
    s.p = roundedPoint({r * t * c, y, r * t * sn}, {slack, slack, slack}, &s.pError);
    s.n = normalized({h * c, r, h * sn});
    s.uv = {float(angleAroundY(c, sn) / (2 * kPiD)), float(y / h)};
    return s;
  }
  s = sampleCap(u, r, 0, -1);
  s.pdf = float(1 / total);
  return s;
}

std::optional<ShapeSample> Cone::sample(Vec2f u) const {
  return sampleVisible(RevolvedView{kPiD, kPiD, capped_ ? 0b10u : 0u}, u);
}

std::optional<ShapeSample> Cone::sample(Vec3f ref, Vec2f u) const {
  return sampleVisible(visibleFrom(ref), u);
}

float Cone::pdf(Vec3f ref, Vec3f p) const {
  const RevolvedView v = visibleFrom(ref);
  double areas[2];
  const double total = visibleAreas(v, areas);
  // The part p lies on: the nearer of the side and the base plane.
  const double r = radius_, h = height_, k = r / h;
  const double rho = std::sqrt(double(p.x) * p.x + double(p.z) * p.z);
  const double dSide = std::abs(rho - k * (h - p.y)) / std::sqrt(1 + k * k);
  return revolvedPdf(v, areas, total, capped_ && std::abs(p.y) < dSide ? 1 : 0, p);
}

std::unique_ptr<Shape> Cone::create(ShapeParameters& params) {
  const float radius = params.positive("radius"), height = params.positive("height");
  return std::make_unique<Cone>(radius, height, params.flag("capped", true));
}

}  // namespace glint
