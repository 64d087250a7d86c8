// glint — PlacedShape: a shape under an affine transform, with the transformed ray origin's
// rounding error carried into t (pbrt-v4's Transform::ApplyInverse(Ray) idea).
#include "geometry/shape.h"

#include <algorithm>
#include <limits>

namespace glint {

PlacedShape::PlacedShape(const Shape* shape, const Transform& placement)
    : shape_(shape), placement_(placement), identity_(placement.isIdentity()) {
  objectBounds_ = shape_->bounds();
  if (!isUnbounded(objectBounds_) && !objectBounds_.empty()) {
    const Vec3f size = objectBounds_.upper - objectBounds_.lower;
    farReach_ = kFarReach * std::max({size.x, size.y, size.z});
  }
  if (identity_) {
    // Every member function takes the shortcut for an identity placement before it reads the
    // inverse; shapes placed by no transform are common (and placed once per hit).
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) inverse_[r][c] = r == c;
    inverseRelError_ = 0;
    absDet_ = 1;
    return;
  }
  const auto& m = placement_.matrix().m;
  translationOnly_ = true;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) translationOnly_ = translationOnly_ && m[r][c] == (r == c);
  if (translationOnly_) {
    // What the general case below computes for an identity 3x3 part (cofactors 1 and 0,
    // det 1), without computing it: shading places a shape once per hit.
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) inverse_[r][c] = r == c;
    inverseRelError_ = 0x1p-50 * 3;
    absDet_ = 1;
    return;
  }
  // The inverse of the float matrix as given (not its rounded float inverse), in double, once:
  // the adjugate's entries are exact products of floats, then one division each.
  double a[3][3], cof[3][3];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) a[r][c] = m[r][c];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      int r1 = (r + 1) % 3, r2 = (r + 2) % 3, c1 = (c + 1) % 3, c2 = (c + 2) % 3;
      cof[r][c] = a[r1][c1] * a[r2][c2] - a[r1][c2] * a[r2][c1];  // exact products of floats
    }
  double det = 0, absDet = 0;
  for (int c = 0; c < 3; ++c) det += a[0][c] * cof[0][c], absDet += std::abs(a[0][c] * cof[0][c]);
  // Relative error of each inverse entry (cofactor rounding, det's rounding and division).
  inverseRelError_ = 0x1p-50 * (2 + absDet / std::abs(det));
  absDet_ = std::abs(det);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) inverse_[r][c] = cof[c][r] / det;  // adjugate / det
}

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

bool PlacedShape::startsFar(const double o[3]) const {
  if (!(farReach_ < kInfinity)) return false;
  for (int i = 0; i < 3; ++i)
    if (objectBounds_.lower[i] - o[i] > farReach_ || o[i] - objectBounds_.upper[i] > farReach_)
      return true;
  return false;
}

Ray PlacedShape::toObject(const Ray& ray, float* shift, float* shiftError,
                          Vec3f* originError) const {
  const auto& m = placement_.matrix().m;
  if (translationOnly_) {
    // A translation (common for CSG leaves and placed objects), in float: the direction is
    // exact, and the origin x = o - translation rounds once (within u|x_i|, u the unit
    // roundoff). The move along d below rounds twice more (the product and the sum), so the
    // moved origin is within 2u|x_i| (1 + u) + (2u + u^2)|d_i dt| of x + d dt, exactly; dt is
    // under 2u (1 + u)|x|_2 / |d|, so |d_i dt| is under 2.1u sum|x| and e_i = 2u|x_i| +
    // 16u^2 sum|x| bounds it all. The shift covers e projected onto d, and 1 + gamma(8) the
    // roundings of its own sums and quotient. Degenerate directions, overflow and far origins
    // take the double solve below.
    constexpr float u = kMachineEpsilon;
    const Vec3f x{ray.o.x - m[0][3], ray.o.y - m[1][3], ray.o.z - m[2][3]};
    const double xd[3] = {x.x, x.y, x.z};
    const Vec3f ax = abs(x), ad = abs(ray.d);
    const float spread = 16 * u * u * (ax.x + ax.y + ax.z);
    const Vec3f e = ax * (2 * u) + Vec3f{spread, spread, spread};
    const float l2 = dot(ray.d, ray.d), along = dot(ad, e);
    if (l2 > 0x1p-100f && l2 < kInfinity && along < kInfinity && !startsFar(xd)) {
      const float dt = nextFloatUp(along / l2 * (1 + gamma(8)));
      *shift = *shiftError = dt;
      const Vec3f o = x + ray.d * dt;
      if (originError)
        for (int i = 0; i < 3; ++i) (*originError)[i] = nextFloatUp(e[i] * (1 + gamma(2)));
      return Ray{o, ray.d, ray.tMin, ray.tMax - dt, ray.time};
    }
  }
  // Solved in double from the float matrix as given (not its rounded inverse), origin taken
  // relative to the translation first: no cancellation against a large translation, and the
  // origin's error is essentially its final rounding to float.
  const double rel = inverseRelError_;
  double x[3], dw[3];
  for (int i = 0; i < 3; ++i) x[i] = double(ray.o[i]) - m[i][3], dw[i] = ray.d[i];
  double od[3], dd[3], err[3];
  // A translation or the identity: the inverse is exactly the identity, so the products below
  // are x and dw themselves; the same values without the nine multiply-adds.
  if (translationOnly_ || identity_) {
    for (int r = 0; r < 3; ++r)
      od[r] = x[r], dd[r] = dw[r], err[r] = std::abs(x[r]) * (rel + 0x1p-49);
  } else {
    for (int r = 0; r < 3; ++r) {
      od[r] = dd[r] = err[r] = 0;
      for (int c = 0; c < 3; ++c) {
        double inv = inverse_[r][c];
        od[r] += inv * x[c];
        dd[r] += inv * dw[c];
        err[r] += std::abs(inv * x[c]);
      }
      // Inverse entries, x's own rounding (o - translation) and the dot product's sums.
      err[r] *= rel + 0x1p-49;
    }
  }
  Vec3f d{float(dd[0]), float(dd[1]), float(dd[2])};
  const double l2 = dd[0] * dd[0] + dd[1] * dd[1] + dd[2] * dd[2];
  // From far away, first along the line to where it enters the shape's box (a float: t values
  // shift by it exactly), still in double: the moved origin is as exact as the solve, and its
  // rounding to float below is relative to coordinates of the shape's size. The t offset is
  // exact; the move's own rounding joins the origin's error.
  float entry = 0;
  if (l2 > 0 && startsFar(od)) {
    double tEntry = -std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; ++i) {
      if (dd[i] == 0) continue;
      const double t0 = (objectBounds_.lower[i] - od[i]) / dd[i];
      const double t1 = (objectBounds_.upper[i] - od[i]) / dd[i];
      tEntry = std::max(tEntry, std::min(t0, t1));
    }
    if (tEntry > 0 && tEntry < std::numeric_limits<float>::max()) {
      entry = float(tEntry);
      for (int i = 0; i < 3; ++i) {
        const double step = dd[i] * double(entry);  // exact: a product of two floats
        err[i] += 0x1p-52 * (std::abs(od[i]) + std::abs(step));
        od[i] += step;
      }
    }
  }
  float dt = 0;
  if (l2 > 0) {
    // Move the origin to the far end of its error box along d (the rounding to float
    // included): the object-space ray never starts behind the caller's origin; t values
    // shift by dt, and dt is also their uncertainty.
    double along = 0;
    for (int i = 0; i < 3; ++i)
      along += std::abs(dd[i]) * (err[i] + kMachineEpsilon * 1.0001 * std::abs(od[i]));
    double t = along / l2;
    dt = float(t);
    if (double(dt) < t) dt = nextFloatUp(dt);
    for (int i = 0; i < 3; ++i) od[i] += dd[i] * double(dt);
  }
  Vec3f o{float(od[0]), float(od[1]), float(od[2])};
  if (originError)  // the solve's error, then two roundings to float (before and after the move)
    for (int i = 0; i < 3; ++i)
      (*originError)[i] = nextFloatUp(float(err[i]) + 2.0001f * kMachineEpsilon * std::abs(o[i]));
  if (entry == 0) {
    *shift = *shiftError = dt;
    // tMin stays: a hit counts only when certainly past the (uncertain) origin.
    return Ray{o, d, ray.tMin, ray.tMax - dt, ray.time};
  }
  // The offsets' sum rounds once (within half an ulp); tMin moves back by the entry alone
  // (rounded up), so a hit still counts only when certainly past the caller's tMin.
  *shift = entry + dt;
  *shiftError = nextFloatUp(dt + gamma(1) * *shift);
  return Ray{o, d, nextFloatUp(ray.tMin - entry), ray.tMax - *shift, ray.time};
}

bool PlacedShape::intersect(const Ray& ray, ShapeHit* hit) const {
  if (identity_ && !startsFar(ray.o)) return shape_->intersect(ray, hit);
  float shift, shiftError;
  Ray r = toObject(ray, &shift, &shiftError);
  ShapeHit h;
  if (!shape_->intersect(r, &h)) return false;
  float t = h.t + shift;
  if (!(t <= ray.tMax)) return false;  // rounding of the shift past tMax
  hit->t = t;
  hit->part = h.part;
  return true;
}

bool PlacedShape::occluded(const Ray& ray) const {
  if (identity_ && !startsFar(ray.o)) return shape_->occluded(ray);
  ShapeHit hit;
  return intersect(ray, &hit);
}

ShapeSurface PlacedShape::surface(const Ray& ray, const ShapeHit& hit,
                                  SurfaceDetails details) const {
  if (identity_ && !startsFar(ray.o)) return shape_->surface(ray, hit, details);
  float shift, shiftError;
  Ray r = toObject(ray, &shift, &shiftError);
  ShapeHit local{hit.t - shift, hit.part};
  if (shift > shiftError) {
    // Moved from far away: the caller's t is the shape's t plus the shift, rounded at the
    // caller's scale (a float step of t at 1e4 is 1e-3, far more than the shape's own error
    // bound allows for, and a point placed by it could lie inside a thin wall). The shape's own
    // t comes from intersecting the same moved ray again: its first hit past tMin, which is
    // the one found before as long as it is the same part at the same t within that rounding.
    // Only rays from far away pay for this.
    ShapeHit again;
    Ray unbounded = r;
    unbounded.tMax = kInfinity;
    if (shape_->intersect(unbounded, &again) && again.part == hit.part &&
        std::abs(again.t - local.t) <= 2 * gamma(1) * std::abs(hit.t) + shiftError)
      local = again;
  }
  ShapeSurface s = shape_->surface(r, local, details);
  if (identity_) return s;
  ShapeSurface w;
  w.p = placement_.point(s.p, s.pError, &w.pError);
  // The inverse transpose keeps solids' normals outward even when handedness flips.
  w.n = normalize(placement_.normal(s.n));
  w.uv = s.uv;
  if (details.tangents) w.dpdu = placement_.vector(s.dpdu), w.dpdv = placement_.vector(s.dpdv);
  return w;
}

bool PlacedShape::span(const Ray& ray, const SurfaceTolerance& tolerance, Span* out) const {
  if (identity_ && !startsFar(ray.o)) return shape_->span(ray, tolerance, out);
  float shift, shiftError;
  Vec3f originError;
  Ray r = toObject(ray, &shift, &shiftError, &originError);
  // shiftError covers the origin's error along the ray; across it, the error moves a crossing by
  // the error along the surface's normal over |d . n|, like a surface tolerance: where crossings
  // tie (tolerance given), the origin's error joins the tolerance, and so does the direction's
  // rounding (half an ulp of each component, times |t|: at most half an ulp of |p - o|).
  SurfaceTolerance tol = tolerance;
  if (!tolerance.none())
    for (size_t k = 0; k < 3; ++k) {
      tol.m[k][3] += originError[int(k)] + kMachineEpsilon * std::abs(r.o[int(k)]);
      tol.m[k][k] += kMachineEpsilon;
    }
  Span s;
  // t is the caller's t, shifted: tie widths carry over unchanged.
  if (!shape_->span(r, tol, &s)) return false;
  for (Crossing* c : {&s.enter, &s.exit}) {
    if (std::isinf(c->t)) continue;
    // The shift's uncertainty is also the origin's along the ray; then the sum's own rounding.
    c->t += shift;
    c->tError = nextFloatUp(c->tError + shiftError + gamma(1) * std::abs(c->t));
    // The normal in the caller's space (through the inverse transpose, as surface() does).
    if (!translationOnly_ && (c->n.x != 0 || c->n.y != 0 || c->n.z != 0))
      c->n = normalize(placement_.normal(c->n));
  }
  *out = s;
  return true;
}

}  // namespace glint

// --- Sampling ---------------------------------------------------------------------------------

namespace glint {

namespace {
// M^T v for the 3x3 part M of t: the object-space direction of a destination normal v (up to
// length), since normals go through M^-T.
Vec3f transposeTimes(const Transform& t, Vec3f v) {
  const auto& m = t.matrix().m;
  return {m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z,
          m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z,
          m[0][2] * v.x + m[1][2] * v.y + m[2][2] * v.z};
}
}  // namespace

Vec3f PlacedShape::objectPoint(Vec3f p) const {
  if (identity_) return p;
  const auto& m = placement_.matrix().m;
  double x[3];
  for (int i = 0; i < 3; ++i) x[i] = double(p[i]) - m[i][3];
  Vec3f o;
  for (int r = 0; r < 3; ++r)
    o[r] = float(inverse_[r][0] * x[0] + inverse_[r][1] * x[1] + inverse_[r][2] * x[2]);
  return o;
}

ShapeSample PlacedShape::toDestination(const ShapeSample& s) const {
  if (identity_) return s;
  ShapeSample w = s;
  w.p = placement_.point(s.p, s.pError, &w.pError);
  const Vec3f n = placement_.normal(s.n);  // M^-T n: its length is the area Jacobian / |det|
  const float len = length(n);
  w.n = n / len;
  w.pdf = s.pdf / float(absDet_ * len);
  return w;
}

float PlacedShape::area() const {
  const float objectArea = shape_->area();
  if (identity_ || !(objectArea > 0)) return objectArea;
  // A_dest = A_obj E[J] over object-uniform points: a stratified grid, exact where J is
  // constant (similarities, each face of a box), within a fraction of a percent otherwise.
  constexpr int kGrid = 64;
  double sum = 0;
  for (int j = 0; j < kGrid; ++j)
    for (int i = 0; i < kGrid; ++i)
      if (auto s = shape_->sample({(float(i) + 0.5f) / kGrid, (float(j) + 0.5f) / kGrid}))
        sum += absDet_ * double(length(placement_.normal(s->n)));
  return float(objectArea * sum / (kGrid * kGrid));
}

std::optional<ShapeSample> PlacedShape::sample(Vec2f u) const {
  std::optional<ShapeSample> s = shape_->sample(u);
  if (s) *s = toDestination(*s);
  return s;
}

std::optional<ShapeSample> PlacedShape::sample(Vec3f ref, Vec2f u) const {
  std::optional<ShapeSample> s = shape_->sample(objectPoint(ref), u);
  if (s) *s = toDestination(*s);
  return s;
}

float PlacedShape::pdf(Vec3f ref, Vec3f p, Vec3f n) const {
  if (identity_) return shape_->pdf(ref, p);
  // The object normal is M^T n / |M^T n| and the Jacobian |det| / |M^T n| for unit n.
  const float objectPdf = shape_->pdf(objectPoint(ref), objectPoint(p));
  return objectPdf * length(transposeTimes(placement_, n)) / float(absDet_);
}

Vec3f PlacedShape::flatNormal() const {
  const Vec3f n = shape_->flatNormal();
  if (identity_ || lengthSquared(n) == 0) return n;
  return normalize(placement_.normal(n));
}

}  // namespace glint
