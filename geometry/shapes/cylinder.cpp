// glint — ray/cylinder: the infinite cylinder's span (a 2D closest-approach quadratic, in
// double) clipped by the y slab; one crossing per boundary event even on the cap rims.
#include "geometry/shapes/cylinder.h"

#include <cassert>
#include <numbers>

#include "geometry/sampling.h"
#include "geometry/shapes/primitive_math.h"

namespace glint {

using namespace prim;

Cylinder::Cylinder(float radius, float height, bool capped)
    : radius_(radius), height_(height), capped_(capped) {
  assert(std::isfinite(radius) && std::isfinite(height) && radius > 0 && height > 0);
}

Bounds3f Cylinder::bounds() const { return {{-radius_, 0, -radius_}, {radius_, height_, radius_}}; }

bool Cylinder::sideSpan(const Ray& ray, Span* out, double* t0, double* t1) const {
  double f[2] = {ray.o.x, ray.o.z}, ef[2] = {0, 0}, d[2] = {ray.d.x, ray.d.z};
  if (d[0] == 0 && d[1] == 0) {
    // Parallel to the axis: inside (rim included) for the whole line, or never.
    if (f[0] * f[0] + f[1] * f[1] > double(radius_) * radius_) return false;
    out->enter = {-kInfinity, 0, 0};
    out->exit = {kInfinity, 0, 0};
    *t0 = *t1 = 0;
    return true;
  }
  Roots r;
  if (!ballRoots(f, ef, d, 2, radius_, &r)) return false;
  out->enter = toCrossing(r.t0, r.e0, 0);
  out->exit = toCrossing(r.t1, r.e1, 0);
  *t0 = r.t0, *t1 = r.t1;
  return true;
}

bool Cylinder::span(const Ray& ray, const SurfaceTolerance& tolerance, Span* out) const {
  if (!capped_) return false;
  Span side, ys;
  double t0, t1;
  if (!sideSpan(ray, &side, &t0, &t1)) return false;
  if (!slab(ray.o.y, ray.d.y, 0, height_, 1, 2, &ys)) return false;
  if (tolerance.none()) return intersectSpans(side, ys, out);
  const float speed = std::sqrt(ray.d.x * ray.d.x + ray.d.z * ray.d.z);
  auto width = [&](Crossing* c) {
    setRevolvedTieWidth(
        c, ray, tolerance,
        [](Vec3f p, float rho) {
          return rho > 0 ? Vec3f{p.x / rho, 0, p.z / rho} : Vec3f{1, 0, 0};
        },
        radius_, speed);
  };
  const Span parts[2] = {side, ys};
  return leafSpan(parts, 2, std::sqrt(4 * radius_ * radius_ + height_ * height_) / length(ray.d),
                  width, out);
}

bool Cylinder::intersect(const Ray& ray, ShapeHit* hit) const {
  if (capped_) {
    Span s;
    return span(ray, {}, &s) && firstAccepted(ray, s, hit);
  }
  // Open tube: infinite crossings are never accepted.
  Span side;
  double t[2];
  return sideSpan(ray, &side, &t[0], &t[1]) && firstOnOpenSide(ray, side, t, height_, hit);
}

ShapeSurface Cylinder::surface(const Ray& ray, const ShapeHit& hit, SurfaceDetails details) const {
  V3 pd = rayPoint(ray, hit.t);
  double r = radius_, h = height_;
  ShapeSurface s;
  if (hit.part == 0) {
    // Re-project radially onto the side, y clamped onto the tube.
    double rho = std::sqrt(pd.x * pd.x + pd.z * pd.z);
    double x = rho > 0 ? pd.x * (r / rho) : r, z = rho > 0 ? pd.z * (r / rho) : 0;
    double y = std::clamp(pd.y, 0.0, h);
    double slack = gammaD(8) * (r + h);
    s.p = roundedPoint({x, y, z}, {slack, slack, slack}, &s.pError);
    s.n = normalized({x, 0, z});
    if (details.uv) {
      double phi = std::atan2(z, x);
      if (phi < 0) phi += 2 * kPiD;
      s.uv = {float(phi / (2 * kPiD)), float(y / h)};
    }
    if (details.tangents) {
      s.dpdu = (V3(-z, 0, x) * (2 * kPiD)).toFloat();
      s.dpdv = {0, height_, 0};
    }
    return s;
  }
  // Caps: y exact on the cap plane, (x, z) clamped into the disk.
  double y = hit.part == 1 ? 0.0 : h;
  double x = pd.x, z = pd.z, rho = std::sqrt(x * x + z * z);
  if (rho > r) x *= r / rho, z *= r / rho;
  double slack = gammaD(8) * r;
  s.p = roundedDiskPoint(x, y, z, r, slack, &s.pError);
  s.n = {0, hit.part == 1 ? -1.0f : 1.0f, 0};
  if (details.uv) s.uv = capUv(x, z, r);
  if (details.tangents) s.dpdu = {2 * radius_, 0, 0}, s.dpdv = {0, 0, 2 * radius_};
  return s;
}

}  // namespace glint

// --- Sampling ---------------------------------------------------------------------------------

namespace glint {

using namespace prim;

RevolvedView Cylinder::visibleFrom(Vec3f ref) const {
  if (!capped_) return {};  // an open tube shows its inside through the ends: all of it
  // dot(n, p) = r along every generator, so they face ref where rho cos(phi - phiRef) > r.
  const unsigned caps = (ref.y < 0 ? 0b010u : 0u) | (ref.y > height_ ? 0b100u : 0u);
  return revolvedView(ref, radius_, caps, 0b110u);
}

double Cylinder::visibleAreas(const RevolvedView& v, double areas[3]) const {
  const double r = radius_, capArea = kPiD * r * r;
  areas[0] = 2 * v.halfAngle * r * height_;
  areas[1] = (v.caps & 0b010) ? capArea : 0.0;
  areas[2] = (v.caps & 0b100) ? capArea : 0.0;
  return areas[0] + areas[1] + areas[2];
}

float Cylinder::area() const {
  double areas[3];
  return float(visibleAreas(RevolvedView{kPiD, kPiD, capped_ ? 0b110u : 0u}, areas));
}

std::optional<ShapeSample> Cylinder::sampleVisible(const RevolvedView& v, Vec2f u) const {
  double areas[3];
  const double total = visibleAreas(v, areas);
  const int part = pickPart(areas, 3, total, &u.x);
  const double r = radius_, h = height_;
  ShapeSample s;
  s.pdf = float(1 / total);
  if (part == 0) {
    const double phi = v.phi0 + v.halfAngle * (2 * double(u.y) - 1);
    const double x = r * std::cos(phi), z = r * std::sin(phi), y = h * u.x;
    const double slack = gammaD(8) * (r + h);
    s.p = roundedPoint({x, y, z}, {slack, slack, slack}, &s.pError);
    s.n = normalized({x, 0, z});
    s.uv = {float(angleAroundY(x, z) / (2 * kPiD)), u.x};
    return s;
  }
  s = part == 1 ? sampleCap(u, r, 0, -1) : sampleCap(u, r, h, 1);
  s.pdf = float(1 / total);
  return s;
}

std::optional<ShapeSample> Cylinder::sample(Vec2f u) const {
  return sampleVisible(RevolvedView{kPiD, kPiD, capped_ ? 0b110u : 0u}, u);
}

std::optional<ShapeSample> Cylinder::sample(Vec3f ref, Vec2f u) const {
  return sampleVisible(visibleFrom(ref), u);
}

float Cylinder::pdf(Vec3f ref, Vec3f p) const {
  const RevolvedView v = visibleFrom(ref);
  double areas[3];
  const double total = visibleAreas(v, areas);
  // The part p lies on: the nearest of the side and the cap planes.
  const double rho = std::sqrt(double(p.x) * p.x + double(p.z) * p.z);
  const double dSide = std::abs(rho - radius_);
  int part = 0;
  if (capped_ && std::min(std::abs(p.y), std::abs(p.y - height_)) < dSide)
    part = std::abs(p.y) < std::abs(p.y - height_) ? 1 : 2;
  return revolvedPdf(v, areas, total, part, p);
}

std::unique_ptr<Shape> Cylinder::create(ShapeParameters& params) {
  const float radius = params.positive("radius"), height = params.positive("height");
  return std::make_unique<Cylinder>(radius, height, params.flag("capped", true));
}

}  // namespace glint
