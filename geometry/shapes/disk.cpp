// glint — ray/disk in double.
#include "geometry/shapes/disk.h"

#include <cassert>

#include "geometry/sampling.h"
#include "geometry/shapes/primitive_math.h"

namespace glint {

using namespace prim;

Disk::Disk(float radius) : radius_(radius) { assert(std::isfinite(radius) && radius > 0); }

bool Disk::intersect(const Ray& ray, ShapeHit* hit) const {
  if (ray.d.y == 0) return false;
  double t = -double(ray.o.y) / double(ray.d.y);
  double x = ray.o.x + t * double(ray.d.x), z = ray.o.z + t * double(ray.d.z);
  if (x * x + z * z > double(radius_) * radius_) return false;
  Crossing c = toCrossing(t, gammaD(1) * std::abs(t), 0);
  if (!accepts(ray, c)) return false;
  hit->t = c.t;
  hit->part = 0;
  return true;
}

ShapeSurface Disk::surface(const Ray& ray, const ShapeHit& hit, SurfaceDetails details) const {
  prim::V3 pd = rayPoint(ray, hit.t);
  double r = radius_, x = pd.x, z = pd.z, rho = std::sqrt(x * x + z * z);
  if (rho > r) x *= r / rho, z *= r / rho;
  ShapeSurface s;
  double slack = gammaD(8) * r;
  s.p = roundedDiskPoint(x, 0, z, r, slack, &s.pError);
  s.n = {0, 1, 0};
  if (details.uv) s.uv = prim::capUv(x, z, r);
  if (details.tangents) s.dpdu = {2 * radius_, 0, 0}, s.dpdv = {0, 0, 2 * radius_};
  return s;
}

}  // namespace glint

// --- Sampling ---------------------------------------------------------------------------------

namespace glint {

std::optional<ShapeSample> Disk::sample(Vec2f u) const {
  const Vec2f q = sampleConcentricDisk(u);
  const double r = radius_, x = q.x * r, z = q.y * r;
  ShapeSample s;
  s.p = prim::roundedDiskPoint(x, 0, z, r, prim::gammaD(8) * r, &s.pError);
  s.n = {0, 1, 0};
  s.uv = prim::capUv(x, z, r);
  s.pdf = 1 / area();
  return s;
}

std::unique_ptr<Shape> Disk::create(ShapeParameters& params) {
  return std::make_unique<Disk>(params.positive("radius"));
}

}  // namespace glint
