// glint — ray/box slabs in double, with the face a crossing comes from as its part.
#include "geometry/shapes/box.h"

#include <cassert>

#include "geometry/shapes/primitive_math.h"

namespace glint {

using namespace prim;

Box::Box(Vec3f lower, Vec3f upper) : lower_(lower), upper_(upper) {
  assert(isFinite(lower) && isFinite(upper));
  assert(lower.x < upper.x && lower.y < upper.y && lower.z < upper.z);
}

bool Box::span(const Ray& ray, Span* out) const {
  Span s{{-kInfinity, 0, 0}, {kInfinity, 0, 0}};
  for (int a = 0; a < 3; ++a) {
    Span sa;
    uint32_t lo = uint32_t(2 * a), hi = lo + 1;
    if (!slab(ray.o[a], ray.d[a], lower_[a], upper_[a], lo, hi, &sa)) return false;
    if (!intersectSpans(s, sa, &s)) return false;
  }
  *out = s;
  return true;
}

bool Box::intersect(const Ray& ray, ShapeHit* hit) const {
  Span s;
  return span(ray, &s) && firstAccepted(ray, s, hit);
}

ShapeSurface Box::surface(const Ray& ray, const ShapeHit& hit) const {
  int axis = int(hit.part / 2) % 3;
  bool upperFace = hit.part % 2 == 1;
  V3 pd = rayPoint(ray, hit.t);
  ShapeSurface s;
  double tErr = gammaD(4) * std::abs(double(hit.t)) + std::abs(double(hit.t)) * 0x1p-23;
  for (int i = 0; i < 3; ++i) {
    if (i == axis) {
      // The face coordinate is exact: the point lies on the face plane.
      s.p[i] = upperFace ? upper_[i] : lower_[i];
      s.pError[i] = 0;
    } else {
      // Clamped onto the face so the point is on the box even near edges.
      double c = std::clamp(pd[i], double(lower_[i]), double(upper_[i]));
      s.p[i] = std::clamp(float(c), lower_[i], upper_[i]);
      double e = std::abs(c - double(s.p[i])) + tErr * std::abs(double(ray.d[i])) +
                 gammaD(4) * std::abs(c);
      s.pError[i] = nextFloatUp(float(e));
    }
  }
  s.n = {};
  s.n[axis] = upperFace ? 1.0f : -1.0f;
  // (u, v) axes per face: X -> (z, y), Y -> (x, z), Z -> (x, y).
  static constexpr int kU[3] = {2, 0, 0}, kV[3] = {1, 2, 1};
  int ua = kU[axis], va = kV[axis];
  float su = upper_[ua] - lower_[ua], sv = upper_[va] - lower_[va];
  s.uv = {std::clamp((s.p[ua] - lower_[ua]) / su, 0.0f, 1.0f),
          std::clamp((s.p[va] - lower_[va]) / sv, 0.0f, 1.0f)};
  s.dpdu = {};
  s.dpdv = {};
  s.dpdu[ua] = su;
  s.dpdv[va] = sv;
  return s;
}

}  // namespace glint
