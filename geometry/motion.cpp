// glint — keyed transforms interpolated as Embree interpolates motion instances.
#include "geometry/motion.h"

#include <algorithm>
#include <cmath>

namespace glint {

Quaternion normalize(const Quaternion& q) {
  float n = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  if (!(n > 0)) return {};
  return {q.x / n, q.y / n, q.z / n, q.w / n};
}

float dot(const Quaternion& a, const Quaternion& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w;
}

namespace {

// acos on [0, 1] by the same single-precision polynomial Embree's slerp uses (its
// fastapprox::acos, a sollya minimax fit of asin, absolute error about 1.3e-6 rad). That error
// is twenty float ulps of a rotated point's position: with std::acos our transform at a ray
// time would put a moving surface off the one Embree intersected by more than a hit point's
// error bound, and rays spawned from it could re-hit it. Evaluated in Embree's order.
float embreeAcos(float x) {
  float v = 1.57079517841339111328125f +
            x * (-0.21450997889041900634765625f +
                 x * (8.78556668758392333984375e-2f +
                      x * (-4.489909112453460693359375e-2f +
                           x * (1.928029954433441162109375e-2f +
                                x * (-4.3095736764371395111083984375e-3f)))));
  v *= -std::sqrt(1.0f - x);
  v = v + 1.57079637050628662109375f;  // asin(x)
  if (v < 0) v = 0;
  return 1.57079637050628662109375f - v;
}

}  // namespace

Quaternion slerp(const Quaternion& a, const Quaternion& b0, float t) {
  Quaternion b = b0;
  float c = dot(a, b);
  if (c < 0) b = {-b.x, -b.y, -b.z, -b.w}, c = -c;
  if (c > 0.9995f) {
    // Nearly parallel: sin(theta) would divide by ~0; the chord is indistinguishable from the arc.
    return normalize({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), a.z + t * (b.z - a.z),
                      a.w + t * (b.w - a.w)});
  }
  // Embree's formulation: turn by phi from a towards the unit part of b orthogonal to a.
  const float phi = t * embreeAcos(c);
  const float sinPhi = std::sin(phi), cosPhi = std::cos(phi);
  const Quaternion perp = normalize({b.x - c * a.x, b.y - c * a.y, b.z - c * a.z, b.w - c * a.w});
  return {cosPhi * a.x + sinPhi * perp.x, cosPhi * a.y + sinPhi * perp.y,
          cosPhi * a.z + sinPhi * perp.z, cosPhi * a.w + sinPhi * perp.w};
}

Transform toTransform(const Quaternion& q) {
  return Transform::rotateQuaternion({q.x, q.y, q.z, q.w});
}

Quaternion quaternionFromRotation(const Mat4& mat) {
  // Shepperd's method: pick the largest of w, x, y, z to divide by, for accuracy.
  const auto& m = mat.m;
  double trace = double(m[0][0]) + m[1][1] + m[2][2];
  double x, y, z, w;
  if (trace > 0) {
    double s = std::sqrt(trace + 1.0) * 2;
    w = 0.25 * s;
    x = (m[2][1] - m[1][2]) / s;
    y = (m[0][2] - m[2][0]) / s;
    z = (m[1][0] - m[0][1]) / s;
  } else if (m[0][0] > m[1][1] && m[0][0] > m[2][2]) {
    double s = std::sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]) * 2;
    w = (m[2][1] - m[1][2]) / s;
    x = 0.25 * s;
    y = (m[0][1] + m[1][0]) / s;
    z = (m[0][2] + m[2][0]) / s;
  } else if (m[1][1] > m[2][2]) {
    double s = std::sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]) * 2;
    w = (m[0][2] - m[2][0]) / s;
    x = (m[0][1] + m[1][0]) / s;
    y = 0.25 * s;
    z = (m[1][2] + m[2][1]) / s;
  } else {
    double s = std::sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]) * 2;
    w = (m[1][0] - m[0][1]) / s;
    x = (m[0][2] + m[2][0]) / s;
    y = (m[1][2] + m[2][1]) / s;
    z = 0.25 * s;
  }
  return normalize({float(x), float(y), float(z), float(w)});
}

// ---- decomposition ---------------------------------------------------------------------------

namespace {

struct Vec3d {
  double x = 0, y = 0, z = 0;
};
Vec3d operator-(Vec3d a, Vec3d b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec3d operator*(Vec3d a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dotd(Vec3d a, Vec3d b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3d crossd(Vec3d a, Vec3d b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double lengthd(Vec3d a) { return std::sqrt(dotd(a, a)); }

// Any unit vector perpendicular to `a` (unit), for degenerate (zero-scale) columns.
Vec3d perpendicular(Vec3d a) {
  Vec3d axis = std::abs(a.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
  Vec3d p = crossd(a, axis);
  return p * (1 / lengthd(p));
}

}  // namespace

DecomposedTransform DecomposedTransform::fromTransform(const Transform& xf) {
  const auto& m = xf.matrix().m;
  Vec3d a[3];
  for (int c = 0; c < 3; ++c) a[c] = {m[0][c], m[1][c], m[2][c]};
  // Gram–Schmidt: A = Q U, column by column.
  Vec3d q[3];
  double u[3][3] = {};
  u[0][0] = lengthd(a[0]);
  q[0] = u[0][0] > 0 ? a[0] * (1 / u[0][0]) : Vec3d{1, 0, 0};
  u[0][1] = dotd(q[0], a[1]);
  Vec3d r1 = a[1] - q[0] * u[0][1];
  u[1][1] = lengthd(r1);
  q[1] = u[1][1] > 1e-12 * (1 + lengthd(a[1])) ? r1 * (1 / u[1][1]) : perpendicular(q[0]);
  u[0][2] = dotd(q[0], a[2]);
  u[1][2] = dotd(q[1], a[2]);
  Vec3d r2 = a[2] - q[0] * u[0][2] - q[1] * u[1][2];
  // q2 completes a right-handed frame; a reflection shows up as a negative u22.
  q[2] = crossd(q[0], q[1]);
  u[2][2] = dotd(q[2], r2);

  DecomposedTransform d;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) d.u[r][c] = float(u[r][c]);
  Mat4 rot;
  for (int c = 0; c < 3; ++c) {
    rot.m[0][c] = float(q[c].x);
    rot.m[1][c] = float(q[c].y);
    rot.m[2][c] = float(q[c].z);
  }
  d.rotation = quaternionFromRotation(rot);
  d.translation = {m[0][3], m[1][3], m[2][3]};
  return d;
}

Transform DecomposedTransform::toTransform() const {
  // M = T R U and M^-1 = U^-1 R^T T^-1: the inverse comes from the factors (U is upper
  // triangular, R orthogonal) at a fraction of a general 4x4 inversion. This runs for every
  // candidate hit on a moving shape.
  const Mat4 r = glint::toTransform(rotation).matrix();
  Mat4 m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      m.m[i][j] = r.m[i][0] * u[0][j] + r.m[i][1] * u[1][j] + r.m[i][2] * u[2][j];
  m.m[0][3] = translation.x, m.m[1][3] = translation.y, m.m[2][3] = translation.z;
  const float a = u[0][0], b = u[0][1], c = u[0][2], d = u[1][1], e = u[1][2], f = u[2][2];
  if (a == 0 || d == 0 || f == 0 || !std::isfinite(a * d * f))
    return Transform(m, Mat4{});  // a zero scale: nothing can be hit, keep it finite
  const float ui[3][3] = {{1 / a, -b / (a * d), (b * e - c * d) / (a * d * f)},
                          {0, 1 / d, -e / (d * f)},
                          {0, 0, 1 / f}};
  Mat4 inv;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)  // (U^-1 R^T)[i][j] = sum_k ui[i][k] r[j][k]
      inv.m[i][j] = ui[i][0] * r.m[j][0] + ui[i][1] * r.m[j][1] + ui[i][2] * r.m[j][2];
  for (int i = 0; i < 3; ++i)
    inv.m[i][3] =
        -(inv.m[i][0] * translation.x + inv.m[i][1] * translation.y + inv.m[i][2] * translation.z);
  return Transform(m, inv);
}

DecomposedTransform DecomposedTransform::lerp(const DecomposedTransform& a,
                                              const DecomposedTransform& b, float t) {
  DecomposedTransform d;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) d.u[r][c] = (1 - t) * a.u[r][c] + t * b.u[r][c];
  d.rotation = slerp(a.rotation, b.rotation, t);
  d.translation = a.translation * (1 - t) + b.translation * t;
  return d;
}

// ---- AnimatedTransform -----------------------------------------------------------------------

AnimatedTransform::AnimatedTransform(std::vector<Transform> keys) {
  if (keys.empty()) return;
  first_ = keys.front();
  bool moves = false;
  for (const Transform& k : keys) moves = moves || !(k == keys.front());
  if (!moves) return;
  keys_ = std::move(keys);
  decomposed_.reserve(keys_.size());
  for (size_t i = 0; i < keys_.size(); ++i) {
    DecomposedTransform d = DecomposedTransform::fromTransform(keys_[i]);
    if (i > 0 && dot(d.rotation, decomposed_.back().rotation) < 0)
      d.rotation = {-d.rotation.x, -d.rotation.y, -d.rotation.z, -d.rotation.w};
    decomposed_.push_back(d);
  }
}

Transform AnimatedTransform::at(float time) const {
  if (!isAnimated()) return first_;
  const size_t segments = keys_.size() - 1;
  float s = std::clamp(time, 0.0f, 1.0f) * float(segments);
  size_t i = std::min(size_t(s), segments - 1);
  float f = s - float(i);
  // On a key the key itself is returned, bit for bit (its decomposition would round).
  if (f == 0) return keys_[i];
  if (f == 1) return keys_[i + 1];
  return DecomposedTransform::lerp(decomposed_[i], decomposed_[i + 1], f).toTransform();
}

float AnimatedTransform::interpolationMismatch(float time) const {
  if (!isAnimated()) return 0;
  // Measured against rtcGetGeometryTransform (tests/geometry/motion_test.cpp): about 1e-6
  // from the approximate acos and the matrix build wherever the rotation turns far enough,
  // and up to 4.5 float epsilons / sin(angle) between nearly parallel keys, where the rounding
  // of cos(angle) and of b - cos(angle) a is amplified. Each term is kept with a margin of 3
  // or more.
  constexpr float kBase = 4e-6f;
  constexpr float kAmplified = 16 * kMachineEpsilon;
  const size_t segments = keys_.size() - 1;
  const size_t i = std::min(size_t(std::clamp(time, 0.0f, 1.0f) * float(segments)), segments - 1);
  const float c =
      std::min(std::abs(dot(decomposed_[i].rotation, decomposed_[i + 1].rotation)), 1.0f);
  // Above Embree's lerp threshold nothing is amplified (slerp() here uses the same branch).
  if (c > 0.9995f) return kBase;
  return kBase + kAmplified / std::sqrt(1 - c * c);
}

Bounds3f AnimatedTransform::motionBounds(const Bounds3f& b, int steps) const {
  if (!isAnimated()) return first_.bounds(b);
  Bounds3f out;
  const int n = int(keys_.size() - 1) * std::max(steps, 1);
  for (int i = 0; i <= n; ++i) out.extend(at(float(i) / float(n)).bounds(b));
  return out;
}

}  // namespace glint
