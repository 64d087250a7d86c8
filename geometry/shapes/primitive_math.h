// glint — internal numerics shared by the analytic primitives (not a public interface).
//
// Why double: the primitives take float rays and float parameters, but solve in double. With
// 29 spare mantissa bits the rounding of the solve is far below a float ULP, so the error
// bounds below can be simple and generous (first-order terms with slack) and still come out
// at about one float ULP of t. The final rounding to float is added to every bound exactly.
//
// Where float is enough, float: a slab (box faces, cylinder and cone caps) is one subtraction
// and one division, bounded exactly in float at 1-3 ULPs of t; the plane settles most rays in
// float and defers to double where its bound is loose or it is a CSG leaf (Plane::span); a
// translated shape's ray goes to object space in float (PlacedShape::toObject). Each gave 3-8%
// of a CSG-heavy render (benchmarks/README.md, "Analytic shapes and CSG"). The quadrics stay in
// double: a float sphere's bound (closest-approach form) is 20-40 ULPs of t, too loose to keep.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "geometry/math.h"
#include "geometry/ray.h"
#include "geometry/sampling.h"
#include "geometry/shape.h"

namespace glint::prim {

inline constexpr double kPiD = std::numbers::pi;
inline constexpr double kEpsD = 0x1p-53;  // unit roundoff of double
// Bound on the relative error of n double operations, doubled for first-order slack.
constexpr double gammaD(int n) { return 2 * (n * kEpsD) / (1 - n * kEpsD); }

struct V3 {
  double x = 0, y = 0, z = 0;
  V3() = default;
  constexpr V3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
  explicit constexpr V3(Vec3f v) : x(v.x), y(v.y), z(v.z) {}
  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  Vec3f toFloat() const { return {float(x), float(y), float(z)}; }
};
constexpr V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
constexpr V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
constexpr V3 operator*(V3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
constexpr double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 abs(V3 a) { return {std::abs(a.x), std::abs(a.y), std::abs(a.z)}; }
constexpr V3 cross(V3 a, V3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// A double t with absolute error bound `err`, rounded to a float Crossing whose tError also
// covers the rounding to float.
inline Crossing toCrossing(double t, double err, uint32_t part) {
  Crossing c;
  c.t = float(t);
  c.part = part;
  if (!std::isfinite(c.t)) return c;  // beyond float range: never accepted as a hit
  double e = err + std::abs(t - double(c.t));
  c.tError = float(e);
  if (double(c.tError) < e) c.tError = nextFloatUp(c.tError);
  return c;
}

// The contract of Shape::intersect for one candidate crossing.
inline bool accepts(const Ray& ray, const Crossing& c) {
  return c.t - c.tError > ray.tMin && c.t <= ray.tMax && c.t < kInfinity;
}

// The first crossing of a span the ray accepts.
inline bool firstAccepted(const Ray& ray, const Span& s, ShapeHit* hit) {
  for (const Crossing* c : {&s.enter, &s.exit})
    if (accepts(ray, *c)) {
      hit->t = c->t;
      hit->part = c->part;
      return true;
    }
  return false;
}

// The first crossing of an open tube or cone side (a surface, not a solid) the ray accepts:
// `t` holds the side's two roots in double, and a root counts only where its point lies on
// the side, 0 <= y <= height. Both faces are hittable; a NaN root (a degenerate line) never is.
inline bool firstOnOpenSide(const Ray& ray, const Span& side, const double t[2], double height,
                            ShapeHit* hit) {
  const Crossing* c[2] = {&side.enter, &side.exit};
  for (int i = 0; i < 2; ++i) {
    if (std::isnan(t[i])) continue;
    double y = double(ray.o.y) + t[i] * double(ray.d.y);
    if (y < 0 || y > height || !accepts(ray, *c[i])) continue;
    hit->t = c[i]->t;
    hit->part = 0;
    return true;
  }
  return false;
}

// The error bound of a point computed in double (within `slack` per axis of the exact
// surface point) and then rounded to float.
inline Vec3f roundedPoint(V3 p, V3 slack, Vec3f* error) {
  Vec3f pf = p.toFloat();
  for (int i = 0; i < 3; ++i) {
    double e = slack[i] + std::abs(p[i] - double(pf[i]));
    float ef = float(e);
    (*error)[i] = double(ef) < e ? nextFloatUp(ef) : ef;
  }
  return pf;
}

// A point of a disk (cap) of radius r in a plane y = const, rounded to float and then nudged
// towards the axis until the float point is inside the disk: a cap hit on a rim never lies
// outside the side wall, so rays spawned from it into the solid do not re-enter at the rim.
inline Vec3f roundedDiskPoint(double x, double y, double z, double r, double slack, Vec3f* error) {
  Vec3f p = roundedPoint({x, y, z}, {slack, 0, slack}, error);
  for (int i = 0; i < 4 && double(p.x) * p.x + double(p.z) * p.z > r * r; ++i) {
    p.x = p.x > 0 ? nextFloatDown(p.x) : (p.x < 0 ? nextFloatUp(p.x) : p.x);
    p.z = p.z > 0 ? nextFloatDown(p.z) : (p.z < 0 ? nextFloatUp(p.z) : p.z);
  }
  error->x = nextFloatUp(error->x + std::abs(p.x - float(x)));
  error->z = nextFloatUp(error->z + std::abs(p.z - float(z)));
  return p;
}

// The uv of a point (x, z) on a disk of radius r about the y axis (disks, cylinder and cone
// caps): x and z mapped to [0, 1].
inline Vec2f capUv(double x, double z, double r) {
  return {std::clamp(float(x / (2 * r) + 0.5), 0.0f, 1.0f),
          std::clamp(float(z / (2 * r) + 0.5), 0.0f, 1.0f)};
}

// A uniform point on the cap of radius r in the plane y, facing `normalY` (+1 or -1): the
// cylinder's and the cone's caps, with the uv their surface() gives (x and z mapped to [0, 1]).
// The caller sets the pdf.
inline ShapeSample sampleCap(Vec2f u, double r, double y, float normalY) {
  ShapeSample s;
  const Vec2f q = sampleConcentricDisk(u);
  const double x = q.x * r, z = q.y * r;
  s.p = roundedDiskPoint(x, y, z, r, gammaD(8) * r, &s.pError);
  s.n = {0, normalY, 0};
  s.uv = capUv(x, z, r);
  return s;
}

// Roots t0 <= t1 of A t^2 + 2 B t + C = 0, each with an absolute error bound.
struct Roots {
  double t0 = 0, e0 = 0, t1 = 0, e1 = 0;
};

// Solves the quadratic in the stable form (q = -(B + sign(B) sqrt(D)), t = q/A, t = C/q)
// given the discriminant D = B^2 - AC (computed by the caller, possibly by a better-conditioned
// formula) and absolute error bounds of every input. False when D < 0 or A == 0.
inline bool solveQuadratic(double A, double eA, double B, double eB, double C, double eC, double D,
                           double eD, Roots* r) {
  if (!(D >= 0) || A == 0) return false;
  double s = std::sqrt(D);
  // sqrt amplifies the discriminant's error near tangency: |sqrt(D') - sqrt(D)| <= min(e/s, √e).
  double eS = (s > 0 ? std::min(eD / s, std::sqrt(eD)) : std::sqrt(eD)) + gammaD(1) * s;
  double q = -(B + std::copysign(s, B));
  double eq = eB + eS + gammaD(1) * std::abs(q);
  double ta, ea, tb, eb;
  if (q == 0) {  // B == 0 and D == 0: the double root t = 0 (then C == 0 too)
    ta = tb = 0;
    ea = eb = std::sqrt((eC + eD) / std::abs(A));
  } else {
    ta = q / A;
    ea = (eq + std::abs(ta) * eA) / std::abs(A) + gammaD(1) * std::abs(ta);
    tb = C / q;
    eb = (eC + std::abs(tb) * eq) / std::abs(q) + gammaD(1) * std::abs(tb);
  }
  if (ta > tb) std::swap(ta, tb), std::swap(ea, eb);
  *r = {ta, ea, tb, eb};
  return true;
}

// Line-vs-ball roots in n dimensions (sphere: n = 3; cylinder: n = 2 in the xz plane), with
// the discriminant from the line's closest approach to the centre (Ray Tracing Gems, ch. 7):
// D = A (r^2 - |f - (B/A) d|^2), well conditioned for far or tiny balls. `f` = origin - centre
// with per-axis error `ef`. False when the line misses or A == 0.
inline bool ballRoots(const double* f, const double* ef, const double* d, int n, double r,
                      Roots* out) {
  double A = 0, B = 0, C = 0, absB = 0, ff = 0, efd = 0;
  for (int i = 0; i < n; ++i) {
    A += d[i] * d[i];
    B += f[i] * d[i];
    absB += std::abs(f[i] * d[i]);
    ff += f[i] * f[i];
    efd += ef[i] * std::abs(d[i]);
  }
  if (A == 0) return false;
  double r2 = r * r;
  C = ff - r2;
  double eA = gammaD(3) * A;
  double eB = gammaD(3) * absB + efd;
  double eC = gammaD(4) * (ff + r2);
  for (int i = 0; i < n; ++i) eC += 2 * std::abs(f[i]) * ef[i] * (1 + gammaD(2));
  double s = B / A;
  double es = (eB + std::abs(s) * eA) / A + gammaD(1) * std::abs(s);
  double l2 = 0, el2 = 0;
  for (int i = 0; i < n; ++i) {
    double li = f[i] - s * d[i];
    double eli = ef[i] + es * std::abs(d[i]) + gammaD(2) * (std::abs(f[i]) + std::abs(s * d[i]));
    l2 += li * li;
    el2 += 2 * std::abs(li) * eli + eli * eli;
  }
  el2 += gammaD(3) * l2;
  double dp = r2 - l2;
  double edp = el2 + gammaD(2) * (r2 + l2);
  if (dp + edp < 0) return false;  // certainly misses
  double D = A * std::max(dp, 0.0);
  double eD = A * edp + std::abs(dp) * eA + gammaD(1) * D;
  return solveQuadratic(A, eA, B, eB, C, eC, D, eD, out);
}

// The slab lo <= o + t d <= hi on one axis, as crossings with the given parts; for d == 0 the
// slab is the whole line or nothing.
//
// Solved in float, the one solve here that is not in double: (lo - o) / d rounds twice, so the
// computed t is within gamma(2) |t| (first order) of the exact one, and gamma(3) |t|, itself
// rounded once, still bounds that. That is one to three float ULPs of t where the double solve
// gives half of one, at a fraction of the cost (a box is three slabs and is the commonest CSG
// leaf). A t beyond float range carries no error bound and is never accepted as a hit, as in
// toCrossing.
inline bool slab(float o, float d, float lo, float hi, uint32_t partLo, uint32_t partHi, Span* s) {
  if (d == 0) {
    if (o < lo || o > hi) return false;
    s->enter = {-kInfinity, 0, partLo};
    s->exit = {kInfinity, 0, partHi};
    return true;
  }
  const float ta = (lo - o) / d, tb = (hi - o) / d;
  auto crossing = [](float t, uint32_t part) {
    return Crossing{t, std::isfinite(t) ? gamma(3) * std::abs(t) : 0.0f, part};
  };
  const Crossing ca = crossing(ta, partLo), cb = crossing(tb, partHi);
  const bool flip = ta > tb;
  s->enter = flip ? cb : ca;
  s->exit = flip ? ca : cb;
  return true;
}

// Intersection of two spans of the same line; false when empty.
inline bool intersectSpans(const Span& a, const Span& b, Span* out) {
  Span r;
  r.enter = a.enter.t >= b.enter.t ? a.enter : b.enter;
  r.exit = a.exit.t <= b.exit.t ? a.exit : b.exit;
  if (r.enter.t > r.exit.t) return false;
  *out = r;
  return true;
}

// --- Sampling helpers -------------------------------------------------------------------------

// Picks one of `n` parts with probability area / total (parts of area 0 never), returning its
// index and rescaling *u to [0, 1) within it for reuse.
inline int pickPart(const double* areas, int n, double total, float* u) {
  double x = double(*u) * total;
  int i = 0;
  while (i < n - 1 && (x >= areas[i] || areas[i] == 0)) x -= areas[i++];
  *u = areas[i] > 0 ? std::min(float(x / areas[i]), 0x1.fffffep-1f) : 0.0f;
  return i;
}

// The half-width of the range of angles phi around the receiver's own (atan2(z, x) of it)
// where the generators of a surface of revolution face a receiver at distance `rho` from the
// axis: rho cos(phi - phiRef) > c, with c = r for a cylinder and k (h - y) for a cone
// (dot(n, p) is constant along a generator). In [0, pi].
inline double visibleHalfAngle(double c, double rho) {
  if (!(rho > 0)) return c < 0 ? kPiD : 0.0;
  const double x = c / rho;
  return x <= -1 ? kPiD : (x >= 1 ? 0.0 : std::acos(x));
}

// The angle of (x, z) around +Y from +X towards +Z, in [0, 2pi): the surfaces' u.
inline double angleAroundY(double x, double z) {
  double phi = std::atan2(z, x);
  return phi < 0 ? phi + 2 * kPiD : phi;
}

// What a receiver may see of a solid of revolution about +Y (cylinder, cone): the side's
// generators for angles phi0 +- halfAngle, and the caps, one bit per part (part 0 is the side).
// The default is the whole side.
struct RevolvedView {
  double phi0 = kPiD, halfAngle = kPiD;
  unsigned caps = 0;

  // Whether the side point (x, z) is on one of the visible generators.
  bool seesSide(double x, double z) const {
    return std::abs(std::remainder(angleAroundY(x, z) - phi0, 2 * kPiD)) <= halfAngle;
  }
};

// The view from `ref` of a capped solid of revolution whose generators face ref where
// rho cos(phi - phiRef) > c (see visibleHalfAngle), with `caps` the caps ref is beyond; a
// receiver that sees neither side nor caps is inside and sees everything (`allCaps`).
inline RevolvedView revolvedView(Vec3f ref, double c, unsigned caps, unsigned allCaps) {
  const double rho = std::sqrt(double(ref.x) * ref.x + double(ref.z) * ref.z);
  RevolvedView seen{angleAroundY(ref.x, ref.z), visibleHalfAngle(c, rho), caps};
  return seen.halfAngle > 0 || seen.caps ? seen : RevolvedView{kPiD, kPiD, allCaps};
}

// The density of a uniform-by-area draw over the visible parts (`areas`, by part, summing to
// `total`) at the surface point p on `part`.
inline float revolvedPdf(const RevolvedView& view, const double* areas, double total, int part,
                         Vec3f p) {
  const bool seen = part == 0 ? view.seesSide(p.x, p.z) : areas[part] > 0;
  return seen ? float(1 / total) : 0.0f;
}

inline Vec3f toFloat(V3 v) { return v.toFloat(); }
inline Vec3f normalized(V3 v) { return (v * (1 / std::sqrt(dot(v, v)))).toFloat(); }

// Point o + t d in double (the ray is float; t the float t of the hit).
inline V3 rayPoint(const Ray& ray, float t) { return V3(ray.o) + V3(ray.d) * double(t); }

// Sets the tie width of a crossing of `ray` where the surface's unit normal is n (either
// sign), and the crossing's normal n. The width is the surface's tolerance along n at the
// crossing point over |d . n|, the t-range in which the line stays within the tolerance of the
// surface to first order. For a curved
// surface of radius `radius` (with `speed` the ray's speed across the curvature) the width is
// at most sqrt(tau (2 r + tau)) / speed, how long a tangent line stays within tau of the curve.
// Infinite crossings keep width 0. In float: a tolerance is a doubled bound, and 1e-5 covers
// this estimate's own rounding.
// `p` is the crossing's point, o + t d, for callers that already have it.
inline void setTieWidth(Crossing* c, const Ray& ray, const SurfaceTolerance& tolerance, Vec3f p,
                        Vec3f n, float radius = 0, float speed = 0) {
  if (!(std::abs(c->t) < kInfinity)) return;
  const float ap[3] = {std::abs(p.x), std::abs(p.y), std::abs(p.z)};
  float tau = 0;
  for (int k = 0; k < 3; ++k) {
    if (n[k] == 0) continue;
    const auto& row = tolerance.m[size_t(k)];
    tau += std::abs(n[k]) * (row[0] * ap[0] + row[1] * ap[1] + row[2] * ap[2] + row[3]);
  }
  const float dn = std::abs(dot(ray.d, n));
  float w = tau / dn;  // +inf for a ray along the surface
  if (radius > 0 && (2 * radius + tau) * dn * dn < tau * speed * speed)
    w = std::sqrt(tau * (2 * radius + tau)) / speed;
  c->tieWidth = w * (1 + 1e-5f);
  c->n = n;
}
inline void setTieWidth(Crossing* c, const Ray& ray, const SurfaceTolerance& tolerance, Vec3f n) {
  setTieWidth(c, ray, tolerance, ray.o + ray.d * c->t, n);
}

// The unit normal of an axis-aligned face crossed on `axis` (the sign does not matter).
inline Vec3f axisNormal(int axis) { return {float(axis == 0), float(axis == 1), float(axis == 2)}; }

// A CSG leaf's span (a tolerance given) from its components' spans: a box's three slabs, a
// capped cylinder's or cone's side and caps. `width(c)` sets a crossing's tie width and normal
// (setTieWidth); `extent` is the leaf's size along the ray (in t). Returns false for a miss.
// Two things differ from the plain intersection of the components:
//
//  * The line may run along a face within the leaf's tolerance of it: the face's crossing is
//    then so wide (its tie width exceeds `extent`) that where the line crosses that face is not
//    defined, and which side of it the line is on across the leaf is decided by rounding. When
//    such a face bounds the span and the line stays within its width of it over the rest of the
//    leaf, it does not bound the span (the other components do): the line counts as inside
//    along it. Two leaves meant to share that face then agree: a union of two boxes meant to
//    touch (5e-8 apart as written) showed the one box's inner face where a ray ran along the
//    seam between them.
//  * Components that do not overlap by no more than their crossings' rounding bounds and tie
//    widths: the line passes within the tolerance of an edge, outside it. A twin leaf (the same
//    solid written another way, or a neighbour meant to touch it) may be entered there, and its
//    crossings must find these two to tie with, or an inner face of the twin would bound the
//    result, or a sliver of it survive the operators. The span is then one of zero length at
//    the better placed crossing (the narrower tie width), the other one moved there with its
//    error bound grown by the move, each keeping its face. Zero-length spans are dropped at the
//    root of the tree (CsgShape).
template <class Width>
bool leafSpan(const Span* parts, int n, float extent, Width width, Span* out) {
  // The later entry and the earlier exit of the components, optionally without component `skip`.
  auto meet = [&](int skip, int* enterIndex, int* exitIndex) {
    Span s;
    *enterIndex = *exitIndex = -1;
    for (int i = 0; i < n; ++i) {
      if (i == skip) continue;
      if (*enterIndex < 0 || parts[i].enter.t > s.enter.t)
        s.enter = parts[i].enter, *enterIndex = i;
      if (*exitIndex < 0 || parts[i].exit.t < s.exit.t) s.exit = parts[i].exit, *exitIndex = i;
    }
    return s;
  };
  int ie = -1, ix = -1;
  Span s = meet(-1, &ie, &ix);
  width(&s.enter);
  width(&s.exit);
  // A bounding crossing (`end`, of component `index`) on a face the line runs along gives way
  // to the other components' when the line stays within its width of that face up to there.
  auto runsAlong = [&](Crossing Span::*end, int index, float sign) {
    Crossing& c = s.*end;
    if (n < 2 || c.tieWidth <= extent) return;
    int je = -1, jx = -1;
    Span others = meet(index, &je, &jx);
    Crossing& o = others.*end;
    width(&o);
    if (sign * (c.t - o.t) <= c.tieWidth + c.tError + o.tError) c = o;
  };
  runsAlong(&Span::enter, ie, 1);
  runsAlong(&Span::exit, ix, -1);
  if (s.enter.t > s.exit.t) {
    if (!crossingsTie(s.enter, s.exit)) return false;
    const float gap = s.enter.t - s.exit.t;
    const bool enterWider = s.enter.tieWidth > s.exit.tieWidth;
    Crossing& moved = enterWider ? s.enter : s.exit;
    moved.t = enterWider ? s.exit.t : s.enter.t;
    moved.tError = nextFloatUp(moved.tError + gap);
  }
  *out = s;
  return true;
}

// The tie width of a crossing of a capped solid of revolution about +Y (cylinder, cone): part 0
// is the side, whose unit normal at a point p at distance rho from the axis is
// sideNormal(p, rho); the other parts are caps. `radius` and `speed` as for setTieWidth.
template <class SideNormal>
void setRevolvedTieWidth(Crossing* c, const Ray& ray, const SurfaceTolerance& tolerance,
                         SideNormal sideNormal, float radius = 0, float speed = 0) {
  if (c->part != 0) {
    setTieWidth(c, ray, tolerance, axisNormal(1));
    return;
  }
  const Vec3f p = ray.o + ray.d * c->t;
  setTieWidth(c, ray, tolerance, p, sideNormal(p, std::sqrt(p.x * p.x + p.z * p.z)), radius, speed);
}

}  // namespace glint::prim
