// glint — analytic shapes: the small interface every sphere, box, cylinder, cone, plane, disk,
// quad and CSG tree implements, and PlacedShape, a shape under an affine transform.
//
// Hits are two-phase (Mitsuba 3's preliminary intersection, pbrt-v4's Shape): traversal asks
// only for t and a `part` (which face, side or cap was hit); surface details (point with its
// rounding-error bound, normal, uv, dp/du, dp/dv) are computed once, for the final hit.
//
// Sampling (area lights): a shape reports its area, draws points uniformly by area, and, for a
// receiving point, draws only from the part of its surface that point may see (closed convex
// solids skip the faces turned away; a sphere samples the cone it subtends). Every density is
// per unit area in the space the shape is asked in: unlike solid angle, area density follows an
// affine placement exactly (times the Jacobian, see PlacedShape), so the light converts to solid
// angle once, in world space. Shapes that cannot be sampled (the infinite plane, CSG trees) have
// area() == 0.
//
// Adding a shape: one header + one .cpp in geometry/shapes/ (intersection, surface, sampling and
// parameter reading side by side, one uv convention) and one line in geometry/shapes/
// registry.cpp; scene files, area lights and `glint info` then know it (geometry/README.md).
//
// Robustness contract (tested in tests/geometry/shapes_test.cpp): a hit is reported only when
// its t is certainly greater than ray.tMin once t's own rounding error is accounted for, so a
// ray spawned from a hit (origin offset past the hit point's error bound, see ray.h) never
// re-hits the surface it leaves. There is no fixed epsilon anywhere.
#pragma once

#include <bit>
#include <cstdint>
#include <memory>
#include <optional>

#include "geometry/math.h"
#include "geometry/ray.h"

namespace glint {

// What traversal records about a hit on a shape.
struct ShapeHit {
  float t = kInfinity;
  // Which piece of the surface was hit: shape-specific and < 8 for primitives (e.g. box face,
  // cylinder side or cap). CSG trees encode (leaf << 3) | leaf's part.
  uint32_t part = 0;
};

// Surface details at a hit, in the space the shape was asked in (object space for Shape,
// world space for PlacedShape).
struct ShapeSurface {
  Vec3f p;           // hit point, re-projected onto the surface where that is exact
  Vec3f pError;      // conservative bound on |p - exact point|, per axis
  Vec3f n;           // unit geometric normal: outward for solids; for open surfaces the side
                     // documented by the shape (the renderer shades both sides)
  Vec2f uv;          // surface parameterisation (see each shape)
  Vec3f dpdu, dpdv;  // partial derivatives of p with respect to uv (bump mapping)
};

// Which of a surface's optional details surface() works out; the point, its error bound and
// the normal it always does. A material without textures reads no uv, and one without bump
// or normal maps or filtered textures no dp/du and dp/dv (SurfaceNeeds): for a sphere the uv
// alone is an acos and an atan2 per hit. Details not asked for are zero.
struct SurfaceDetails {
  bool uv = true;
  bool tangents = true;  // dpdu and dpdv
};

// A point drawn on a shape's surface.
struct ShapeSample {
  Vec3f p;        // on the surface
  Vec3f pError;   // conservative bound on |p - exact point|, per axis
  Vec3f n;        // unit normal: outward for solids, as surface() reports it for open surfaces
  Vec2f uv;       // the uv surface() gives at p
  float pdf = 0;  // density per unit area (in the space the shape was asked in)
};

// Where a ray's line crosses a solid's boundary.
struct Crossing {
  float t = 0;
  float tError = 0;  // conservative bound on |t - exact t|
  uint32_t part = 0;
  // How far t may move if the surface moves within its SurfaceTolerance (span()'s argument):
  // the tolerance along the normal over |d . n|. 0 without a tolerance. CSG ties use it.
  float tieWidth = 0;
  // The surface's unit normal there (either sign), in the space the span was asked in; set
  // with the tie width (zero without a tolerance, and for infinite t). CSG ties pair crossings
  // of the same surface only (sameSurface).
  Vec3f n;
};

// Two crossings that cannot be told apart: their t values differ by no more than their rounding
// bounds and tie widths together (CSG's tie rule, geometry/csg.h).
inline bool crossingsTie(const Crossing& a, const Crossing& b) {
  if (a.t == b.t) return true;  // includes equal infinities
  return std::abs(a.t - b.t) <= (a.tError + b.tError) + (a.tieWidth + b.tieWidth);
}

// Whether two crossings may lie on one surface: their normals are parallel (either sign) to
// within 0.8 degrees, or one of them is unknown. Faces that coincide as meant are parallel to
// within their rounding (1e-6); two faces meeting at an edge are not, however close to the
// edge the ray passes.
inline bool sameSurface(const Crossing& a, const Crossing& b) {
  const float d = a.n.x * b.n.x + a.n.y * b.n.y + a.n.z * b.n.z;
  const bool unknown =
      (a.n.x == 0 && a.n.y == 0 && a.n.z == 0) || (b.n.x == 0 && b.n.y == 0 && b.n.z == 0);
  return unknown || std::abs(d) >= 0.9999f;
}

// How far a solid's stored surface may lie from the surface its author meant, per axis of the
// space the shape is asked in: at a point p, sum_j m[k][j] |p_j| + m[k][3] along axis k (a
// bound linear in the point, as an affine map's error is). CSG leaves get one from the written
// precision of their numbers and of the transforms composed to place them
// (CsgShape::addLeaf); everything else passes none.
struct SurfaceTolerance {
  std::array<std::array<float, 4>, 3> m{};
  // True when every entry is zero (+0 or -0). Branch-free over the twelve entries: every CSG
  // leaf span asks, and the early-exit loop this replaced was a percent of a CSG render.
  bool none() const {
    uint32_t bits = 0;
    for (const auto& row : m)
      for (float x : row) bits |= std::bit_cast<uint32_t>(x) & 0x7fffffffu;
    return bits == 0;
  }
};

// The part of a ray's whole line (all real t, not only [tMin, tMax]) inside a convex solid:
// the line enters at `enter` and leaves at `exit`, enter.t <= exit.t. For unbounded solids
// (a plane's half-space) enter.t may be -inf or exit.t +inf. CSG trees are built from these.
struct Span {
  Crossing enter, exit;
};

class Shape {
 public:
  virtual ~Shape() = default;
  // "sphere", "box", ... for messages and `glint info`.
  virtual const char* typeName() const = 0;
  // An independent copy (a scene description keeps the shapes its loader made and checked;
  // each build of a render scene takes its own).
  virtual std::unique_ptr<Shape> clone() const = 0;
  // Object-space bounds. Unbounded shapes (the infinite plane) have infinite components;
  // accelerators keep such shapes out of their hierarchies and test them directly.
  virtual Bounds3f bounds() const = 0;
  // The closest hit with tMin < t <= tMax (t certainly > tMin given its error bound).
  // `ray.d` need not be unit length; t is in units of |d|.
  virtual bool intersect(const Ray& ray, ShapeHit* hit) const = 0;
  // Whether any hit exists with tMin < t <= tMax (shadow rays).
  virtual bool occluded(const Ray& ray) const {
    ShapeHit hit;
    return intersect(ray, &hit);
  }
  // Surface details of a hit this shape reported for `ray` (`details`: which optional ones).
  virtual ShapeSurface surface(const Ray& ray, const ShapeHit& hit,
                               SurfaceDetails details) const = 0;
  // Surface area; 0 when the shape cannot be sampled (and so cannot be an area light).
  virtual float area() const { return 0; }
  // A point uniform by area for u in [0, 1)^2; nullopt when area() == 0.
  virtual std::optional<ShapeSample> sample(Vec2f u) const {
    (void)u;
    return std::nullopt;
  }
  // A point for a receiver at `ref`, drawn from the part of the surface ref may see (default:
  // all of it, by area); pdf per unit area.
  virtual std::optional<ShapeSample> sample(Vec3f ref, Vec2f u) const {
    (void)ref;
    return sample(u);
  }
  // The density per unit area of sample(ref, ·) at the surface point p (0 where it never draws).
  virtual float pdf(Vec3f ref, Vec3f p) const {
    (void)ref, (void)p;
    const float a = area();
    return a > 0 ? 1 / a : 0.0f;
  }
  // The unit normal of a flat shape (quad, disk), zero for others: bounds a light's emission.
  virtual Vec3f flatNormal() const { return {}; }

  // --- Constructive solid geometry. A leaf of a CSG tree must be a solid and answer span();
  // a tree (CsgShape) has a material slot per leaf. Every other shape keeps the defaults. They
  // stay virtuals of Shape rather than a Solid subclass: whether a cylinder or cone is a solid
  // is decided at run time (capped or not), and the placed-shape wrapper forwards them
  // (docs/design.md).

  // True for closed convex solids that can be CSG leaves (sphere, box, capped cylinder and
  // cone, the plane as the half-space below it).
  virtual bool isSolid() const { return false; }
  // For solids: the span of the ray's line inside the solid; false when the line misses it.
  // With a tolerance, each crossing's tieWidth says how far it may move with the surface.
  virtual bool span(const Ray& ray, const SurfaceTolerance& tolerance, Span* out) const {
    (void)ray, (void)tolerance, (void)out;
    return false;
  }
  // Which material slot a hit part uses: 0 for primitives, the leaf index for CSG trees.
  virtual uint32_t materialSlot(uint32_t part) const {
    (void)part;
    return 0;
  }
  // Number of material slots (CSG: one per leaf).
  virtual uint32_t materialSlotCount() const { return 1; }
};

// True when `b` has an infinite component (an unbounded shape).
inline bool isUnbounded(const Bounds3f& b) {
  for (int i = 0; i < 3; ++i)
    if (std::isinf(b.lower[i]) || std::isinf(b.upper[i])) return true;
  return false;
}

// 1 / d per axis, 0 where d is 0: what segmentMissesBox takes.
inline Vec3f reciprocalDirection(Vec3f d) {
  Vec3f r;
  for (int i = 0; i < 3; ++i) r[i] = d[i] != 0 ? 1 / d[i] : 0.0f;
  return r;
}

// True when the part of the ray's line with t in [tLo, tHi] certainly misses the box (the whole
// line: tLo = -inf, tHi = inf). Conservative: the slab distances are widened by their rounding
// error (pbrt-v4's gamma(3) idea), so a line that grazes the box is never culled. Unbounded
// boxes are never culled.
// invD is reciprocalDirection(ray.d) (CSG computes it once per query, not once per node).
inline bool segmentMissesBox(const Ray& ray, Vec3f invD, const Bounds3f& b, float tLo, float tHi) {
  if (isUnbounded(b) || b.empty()) return b.empty();
  float tNear = -kInfinity, tFar = kInfinity;
  for (int i = 0; i < 3; ++i) {
    if (ray.d[i] == 0) {
      if (ray.o[i] < b.lower[i] || ray.o[i] > b.upper[i]) return true;
      continue;
    }
    const float inv = invD[i];
    float t0 = (b.lower[i] - ray.o[i]) * inv, t1 = (b.upper[i] - ray.o[i]) * inv;
    if (t0 > t1) std::swap(t0, t1);
    constexpr float w = 2 * gamma(3);
    t0 = t0 > 0 ? t0 * (1 - w) : t0 * (1 + w);  // moved down
    t1 = t1 > 0 ? t1 * (1 + w) : t1 * (1 - w);  // moved up
    tNear = std::max(tNear, t0);
    tFar = std::min(tFar, t1);
  }
  return tNear > tFar || tFar < tLo || tNear > tHi;
}

// A shape placed by an affine transform (any invertible 3x4: translation, rotation,
// non-uniform scale, shear). Rays are taken to object space with the rounding error of the
// transformed origin accounted for (pbrt-v4's Transform::ApplyInverse(Ray)); t values are
// those of the caller's ray. Surface details come back in the caller's space, normals through
// the inverse transpose, the point's error bound grown by the transform's own error.
class PlacedShape {
 public:
  // `shape` must outlive this; `placement` = destination-from-object (e.g. worldFromObject).
  PlacedShape(const Shape* shape, const Transform& placement);

  const Shape& shape() const { return *shape_; }
  const Transform& placement() const { return placement_; }
  // Bounds in the destination space; all-infinite when the shape is unbounded.
  Bounds3f bounds() const;
  bool intersect(const Ray& ray, ShapeHit* hit) const;
  bool occluded(const Ray& ray) const;
  ShapeSurface surface(const Ray& ray, const ShapeHit& hit, SurfaceDetails details = {}) const;
  // `tolerance` is in the shape's object space.
  bool span(const Ray& ray, const SurfaceTolerance& tolerance, Span* out) const;

  // Sampling in the destination space (see Shape): densities per unit destination area, the
  // object density divided by the placement's area Jacobian |det M| |M^-T n_object| at the
  // point. Exact for any affine placement.
  // The destination area: exact under a similarity, else a stratified estimate (not cheap).
  float area() const;
  std::optional<ShapeSample> sample(Vec2f u) const;
  // `ref` in the destination space; visibility is affine-invariant, so the shape decides it in
  // object space.
  std::optional<ShapeSample> sample(Vec3f ref, Vec2f u) const;
  // The density of sample(ref, ·) at the destination surface point p with unit normal n
  // (either sign).
  float pdf(Vec3f ref, Vec3f p, Vec3f n) const;
  // The shape's flat normal in the destination space (zero for curved shapes).
  Vec3f flatNormal() const;

 private:
  // A destination-space point in object space (double inverse, then rounded).
  Vec3f objectPoint(Vec3f p) const;
  // An object-space sample moved to the destination space.
  ShapeSample toDestination(const ShapeSample& s) const;

  // `ray` in object space, with its origin moved forward past the transform's rounding error,
  // and, for a ray that starts far from the shape (farther from its box than kFarReach times
  // the box's size), along its line to the box first, in double: the shape then works with t
  // values and coordinates of its own size (seen from 1e4 units, the two faces of a 4e-5 wall
  // are less than t's rounding apart). `shift` receives the t offset to add to object-space t
  // values, `shiftError` its uncertainty, and `originError` (when given) a bound on the
  // object-space origin's error per axis.
  Ray toObject(const Ray& ray, float* shift, float* shiftError, Vec3f* originError = nullptr) const;
  // Whether an object-space origin is farther from the shape's box than farReach_.
  bool startsFar(const double o[3]) const;
  bool startsFar(Vec3f o) const {
    const double od[3] = {o.x, o.y, o.z};
    return startsFar(od);
  }
  static constexpr float kFarReach = 8;

  const Shape* shape_;
  Transform placement_;
  bool identity_;
  bool translationOnly_ = false;  // the 3x3 part is the identity (and the shift is not zero)
  double inverse_[3][3];          // of placement_'s 3x3 part, in double (see the constructor)
  double inverseRelError_;        // relative error bound of each inverse_ entry
  double absDet_;                 // |det| of placement_'s 3x3 part
  Bounds3f objectBounds_;         // the shape's, in object space
  float farReach_ = kInfinity;    // kFarReach times the box's largest side (inf: unbounded, empty)
};

}  // namespace glint
