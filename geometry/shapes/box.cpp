// glint — ray/box slabs in double, with the face a crossing comes from as its part.
#include "geometry/shapes/box.h"

#include <cassert>
#include <cstdio>
#include <string>

#include "geometry/shapes/primitive_math.h"

namespace glint {

using namespace prim;

Box::Box(Vec3f lower, Vec3f upper) : lower_(lower), upper_(upper) {
  assert(isFinite(lower) && isFinite(upper));
  assert(lower.x < upper.x && lower.y < upper.y && lower.z < upper.z);
}

bool Box::span(const Ray& ray, const SurfaceTolerance& tolerance, Span* out) const {
  Span s{{-kInfinity, 0, 0}, {kInfinity, 0, 0}};
  if (tolerance.none()) {
    for (int a = 0; a < 3; ++a) {
      Span sa;
      uint32_t lo = uint32_t(2 * a), hi = lo + 1;
      if (!slab(ray.o[a], ray.d[a], lower_[a], upper_[a], lo, hi, &sa)) return false;
      if (!intersectSpans(s, sa, &s)) return false;
    }
  } else {
    Span slabs[3];
    for (int a = 0; a < 3; ++a) {
      uint32_t lo = uint32_t(2 * a), hi = lo + 1;
      if (!slab(ray.o[a], ray.d[a], lower_[a], upper_[a], lo, hi, &slabs[a])) return false;
    }
    auto width = [&](Crossing* c) { setTieWidth(c, ray, tolerance, axisNormal(int(c->part / 2))); };
    if (!leafSpan(slabs, 3, length(upper_ - lower_) / length(ray.d), width, &s)) return false;
  }
  *out = s;
  return true;
}

bool Box::intersect(const Ray& ray, ShapeHit* hit) const {
  Span s;
  return span(ray, {}, &s) && firstAccepted(ray, s, hit);
}

ShapeSurface Box::surface(const Ray& ray, const ShapeHit& hit, SurfaceDetails details) const {
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
  if (details.uv)
    s.uv = {std::clamp((s.p[ua] - lower_[ua]) / su, 0.0f, 1.0f),
            std::clamp((s.p[va] - lower_[va]) / sv, 0.0f, 1.0f)};
  if (details.tangents) s.dpdu[ua] = su, s.dpdv[va] = sv;
  return s;
}

}  // namespace glint

// --- Sampling ---------------------------------------------------------------------------------

namespace glint {

using namespace prim;

namespace {
// (u, v) axes per face axis, as surface() measures them: X -> (z, y), Y -> (x, z), Z -> (x, y).
constexpr int kU[3] = {2, 0, 0}, kV[3] = {1, 2, 1};
constexpr unsigned kAllFaces = 0x3f;
}  // namespace

double Box::faceArea(int face) const {
  const int axis = face / 2;
  return (double(upper_[kU[axis]]) - lower_[kU[axis]]) *
         (double(upper_[kV[axis]]) - lower_[kV[axis]]);
}

float Box::area() const {
  double a = 0;
  for (int f = 0; f < 6; ++f) a += faceArea(f);
  return float(a);
}

unsigned Box::facesSeenFrom(Vec3f ref) const {
  unsigned faces = 0;
  for (int a = 0; a < 3; ++a) {
    if (ref[a] < lower_[a]) faces |= 1u << (2 * a);
    if (ref[a] > upper_[a]) faces |= 1u << (2 * a + 1);
  }
  return faces ? faces : kAllFaces;
}

std::optional<ShapeSample> Box::sampleFaces(unsigned faces, Vec2f u) const {
  double areas[6], total = 0;
  for (int f = 0; f < 6; ++f) total += areas[f] = (faces >> f & 1) ? faceArea(f) : 0.0;
  const int face = pickPart(areas, 6, total, &u.x);
  const int axis = face / 2, ua = kU[axis], va = kV[axis];
  V3 p;
  double pd[3];
  pd[axis] = face % 2 ? upper_[axis] : lower_[axis];
  pd[ua] = lower_[ua] + double(u.x) * (double(upper_[ua]) - lower_[ua]);
  pd[va] = lower_[va] + double(u.y) * (double(upper_[va]) - lower_[va]);
  p = {pd[0], pd[1], pd[2]};
  ShapeSample s;
  V3 slack = abs(p) * gammaD(4);
  double sl[3] = {slack.x, slack.y, slack.z};
  sl[axis] = 0;  // exact: the face plane is a float
  s.p = roundedPoint(p, {sl[0], sl[1], sl[2]}, &s.pError);
  // Clamped onto the face like surface()'s points, so the uv stays in [0, 1].
  for (int i = 0; i < 3; ++i) s.p[i] = std::clamp(s.p[i], lower_[i], upper_[i]);
  s.n = {};
  s.n[axis] = face % 2 ? 1.0f : -1.0f;
  s.uv = u;
  s.pdf = float(1 / total);
  return s;
}

std::optional<ShapeSample> Box::sample(Vec2f u) const { return sampleFaces(kAllFaces, u); }

std::optional<ShapeSample> Box::sample(Vec3f ref, Vec2f u) const {
  return sampleFaces(facesSeenFrom(ref), u);
}

float Box::pdf(Vec3f ref, Vec3f p) const {
  // The face p lies on: the nearest face plane (the hit normal's sign cannot say which side).
  int face = 0;
  float nearest = kInfinity;
  for (int f = 0; f < 6; ++f) {
    const float d = std::abs(p[f / 2] - (f % 2 ? upper_[f / 2] : lower_[f / 2]));
    if (d < nearest) nearest = d, face = f;
  }
  const unsigned faces = facesSeenFrom(ref);
  if (!(faces >> face & 1)) return 0;
  double total = 0;
  for (int f = 0; f < 6; ++f)
    if (faces >> f & 1) total += faceArea(f);
  return float(1 / total);
}

namespace {
// "(x, y, z)" for messages.
std::string toString(Vec3f v) {
  char text[96];
  std::snprintf(text, sizeof text, "(%g, %g, %g)", v.x, v.y, v.z);
  return text;
}
}  // namespace

std::unique_ptr<Shape> Box::create(ShapeParameters& params) {
  const Vec3f lower = params.vector("min"), upper = params.vector("max");
  for (int i = 0; i < 3; ++i)
    if (!(lower[i] < upper[i]))
      params.invalid("max", "must be greater than 'min' in every component, got min " +
                                toString(lower) + ", max " + toString(upper));
  return std::make_unique<Box>(lower, upper);
}

}  // namespace glint
