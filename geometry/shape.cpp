// glint — PlacedShape: a shape under an affine transform, with the transformed ray origin's
// rounding error carried into t (pbrt-v4's Transform::ApplyInverse(Ray) idea).
#include "geometry/shape.h"

namespace glint {

PlacedShape::PlacedShape(const Shape* shape, const Transform& placement)
    : shape_(shape), placement_(placement), identity_(placement.isIdentity()) {}

Bounds3f PlacedShape::bounds() const {
  Bounds3f b = shape_->bounds();
  if (isUnbounded(b))
    return {{-kInfinity, -kInfinity, -kInfinity}, {kInfinity, kInfinity, kInfinity}};
  if (identity_ || b.empty()) return b;
  // Corners padded by their transform rounding error so the box holds the exact image.
  Bounds3f r;
  for (int i = 0; i < 8; ++i) {
    Vec3f c{(i & 1) ? b.upper.x : b.lower.x, (i & 2) ? b.upper.y : b.lower.y,
            (i & 4) ? b.upper.z : b.lower.z};
    Vec3f err;
    Vec3f p = placement_.point(c, &err);
    Vec3f lo = p - err, hi = p + err;
    for (int a = 0; a < 3; ++a) lo[a] = nextFloatDown(lo[a]), hi[a] = nextFloatUp(hi[a]);
    r.extend(lo);
    r.extend(hi);
  }
  return r;
}

Ray PlacedShape::toObject(const Ray& ray, float* dt) const {
  Transform objectFromPlacement = placement_.inverse();
  Vec3f oError;
  Vec3f o = objectFromPlacement.point(ray.o, &oError);
  Vec3f d = objectFromPlacement.vector(ray.d);
  *dt = 0;
  float l2 = lengthSquared(d);
  if (l2 > 0) {
    // Move the origin to the far end of its error box along d: the object-space ray then
    // never starts behind the caller's origin, and t values shift by dt.
    *dt = dot(abs(d), oError) / l2;
    o += d * *dt;
  }
  // tMin stays: a hit counts only when it is certainly past the (uncertain) origin, which is
  // the caller's tMin shifted by dt and widened by the same dt of uncertainty.
  return Ray{o, d, ray.tMin, ray.tMax - *dt, ray.time};
}

bool PlacedShape::intersect(const Ray& ray, ShapeHit* hit) const {
  if (identity_) return shape_->intersect(ray, hit);
  float dt;
  Ray r = toObject(ray, &dt);
  ShapeHit h;
  if (!shape_->intersect(r, &h)) return false;
  float t = h.t + dt;
  if (!(t <= ray.tMax)) return false;  // rounding of the shift past tMax
  hit->t = t;
  hit->part = h.part;
  return true;
}

bool PlacedShape::occluded(const Ray& ray) const {
  if (identity_) return shape_->occluded(ray);
  ShapeHit hit;
  return intersect(ray, &hit);
}

ShapeSurface PlacedShape::surface(const Ray& ray, const ShapeHit& hit) const {
  if (identity_) return shape_->surface(ray, hit);
  float dt;
  Ray r = toObject(ray, &dt);
  ShapeSurface s = shape_->surface(r, ShapeHit{hit.t - dt, hit.part});
  ShapeSurface w;
  w.p = placement_.point(s.p, s.pError, &w.pError);
  // The inverse transpose keeps solids' normals outward even when handedness flips.
  w.n = normalize(placement_.normal(s.n));
  w.uv = s.uv;
  w.dpdu = placement_.vector(s.dpdu);
  w.dpdv = placement_.vector(s.dpdv);
  return w;
}

bool PlacedShape::span(const Ray& ray, Span* out) const {
  if (identity_) return shape_->span(ray, out);
  float dt;
  Ray r = toObject(ray, &dt);
  Span s;
  if (!shape_->span(r, &s)) return false;
  for (Crossing* c : {&s.enter, &s.exit}) {
    if (std::isinf(c->t)) continue;
    // dt is also the origin's uncertainty along the ray; then the sum's own rounding.
    c->t += dt;
    c->tError = nextFloatUp(c->tError + dt + gamma(1) * std::abs(c->t));
  }
  *out = s;
  return true;
}

}  // namespace glint
