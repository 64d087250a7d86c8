// glint — the accelerator factory: backends chosen by name.
#include "geometry/accel/accelerator.h"

#include <algorithm>
#include <cmath>

#include "geometry/accel/embree_accel.h"
#include "geometry/accel/kdtree.h"
#include "geometry/error.h"

namespace glint {

std::optional<FarHitStretch> farHitStretch(const Ray& ray, float t) {
  if (!(t < kInfinity)) return std::nullopt;
  const double dLength =
      std::sqrt(double(ray.d.x) * ray.d.x + double(ray.d.y) * ray.d.y + double(ray.d.z) * ray.d.z);
  const double length = double(t) * dLength;
  double origin = 0, hitScale = 0;
  for (int i = 0; i < 3; ++i) {
    origin = std::max(origin, std::abs(double(ray.o[i])));
    hitScale = std::max(hitScale, std::abs(double(ray.o[i]) + double(ray.d[i]) * t));
  }
  if (!(length > kFarHit * hitScale) || !(dLength > 0)) return std::nullopt;
  // The stretch reaches 2^-15 of |o| + t |d| (some 256 float steps of it) before and after
  // the hit: far more than traversal's t error, and small beside the ray's length.
  const double margin = (origin + length) * 0x1p-15 / dLength;
  float start = std::max(float(double(t) - margin), ray.tMin);
  if (double(start) > double(t) - margin && start > ray.tMin) start = std::nextafter(start, 0.0f);
  FarHitStretch s;
  s.shift = start;
  for (int i = 0; i < 3; ++i) s.ray.o[i] = float(double(ray.o[i]) + double(ray.d[i]) * start);
  s.ray.d = ray.d;
  s.ray.tMin = 0;
  s.ray.tMax = float(std::min(double(t) + margin, double(ray.tMax)) - start);
  s.ray.time = ray.time;
  return s;
}

std::unique_ptr<Accelerator> makeAccelerator(const std::string& name, const GeometryScene& scene) {
  if (name == "embree") return std::make_unique<EmbreeAccelerator>(scene);
  if (name == "kdtree") return std::make_unique<KdTreeAccelerator>(scene, KdSplitMethod::Sah);
  if (name == "kdtree-median")
    return std::make_unique<KdTreeAccelerator>(scene, KdSplitMethod::Median);
  throw InputError("unknown accelerator '" + name + "'");
}

std::vector<std::string> acceleratorNames() { return {"embree", "kdtree", "kdtree-median"}; }

}  // namespace glint
