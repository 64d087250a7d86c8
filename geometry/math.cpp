// glint — 4x4 matrix algebra and transform construction.
#include "geometry/math.h"

#include <cstdio>
#include <cstdlib>

namespace glint {

Mat4 operator*(const Mat4& a, const Mat4& b) {
  Mat4 r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += double(a.m[i][k]) * double(b.m[k][j]);
      r.m[i][j] = float(s);
    }
  return r;
}

Mat4 transpose(const Mat4& a) {
  Mat4 r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r.m[i][j] = a.m[j][i];
  return r;
}

bool invert(const Mat4& a, Mat4* out) {
  // Gauss-Jordan elimination with partial pivoting, in double precision.
  double m[4][8];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      if (!std::isfinite(a.m[i][j])) return false;
      m[i][j] = a.m[i][j];
      m[i][j + 4] = i == j ? 1.0 : 0.0;
    }
  for (int c = 0; c < 4; ++c) {
    int pivot = c;
    for (int r = c + 1; r < 4; ++r)
      if (std::abs(m[r][c]) > std::abs(m[pivot][c])) pivot = r;
    if (m[pivot][c] == 0.0) return false;
    if (pivot != c)
      for (int j = 0; j < 8; ++j) std::swap(m[c][j], m[pivot][j]);
    double inv = 1.0 / m[c][c];
    for (int j = 0; j < 8; ++j) m[c][j] *= inv;
    for (int r = 0; r < 4; ++r) {
      if (r == c) continue;
      double f = m[r][c];
      if (f == 0.0) continue;
      for (int j = 0; j < 8; ++j) m[r][j] -= f * m[c][j];
    }
  }
  Mat4 r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      r.m[i][j] = float(m[i][j + 4]);
      if (!std::isfinite(r.m[i][j])) return false;
    }
  *out = r;
  return true;
}

Transform::Transform(const Mat4& m) : m_(m) {
  bool ok = invert(m, &inv_);
  (void)ok;  // callers validate user matrices with invert() first
}

Transform Transform::translate(Vec3f t) {
  Mat4 m, inv;
  m.m[0][3] = t.x, m.m[1][3] = t.y, m.m[2][3] = t.z;
  inv.m[0][3] = -t.x, inv.m[1][3] = -t.y, inv.m[2][3] = -t.z;
  return Transform(m, inv);
}

Transform Transform::scale(Vec3f s) {
  Mat4 m, inv;
  m.m[0][0] = s.x, m.m[1][1] = s.y, m.m[2][2] = s.z;
  inv.m[0][0] = 1 / s.x, inv.m[1][1] = 1 / s.y, inv.m[2][2] = 1 / s.z;
  return Transform(m, inv);
}

Transform Transform::rotateQuaternion(Vec4f q) {
  float x = q.x, y = q.y, z = q.z, w = q.w;
  float n = std::sqrt(x * x + y * y + z * z + w * w);
  if (n > 0) x /= n, y /= n, z /= n, w /= n;
  Mat4 m;
  m.m[0][0] = 1 - 2 * (y * y + z * z);
  m.m[0][1] = 2 * (x * y - z * w);
  m.m[0][2] = 2 * (x * z + y * w);
  m.m[1][0] = 2 * (x * y + z * w);
  m.m[1][1] = 1 - 2 * (x * x + z * z);
  m.m[1][2] = 2 * (y * z - x * w);
  m.m[2][0] = 2 * (x * z - y * w);
  m.m[2][1] = 2 * (y * z + x * w);
  m.m[2][2] = 1 - 2 * (x * x + y * y);
  return Transform(m, transpose(m));  // rotations are orthogonal
}

Transform Transform::rotate(float degrees, Vec3f axis) {
  Vec3f a = normalize(axis);
  float half = degrees * kPi / 360.0f;
  float s = std::sin(half);
  return rotateQuaternion({a.x * s, a.y * s, a.z * s, std::cos(half)});
}

Transform Transform::lookAt(Vec3f eye, Vec3f target, Vec3f up) {
  Vec3f back = normalize(eye - target);  // camera looks down -Z
  Vec3f right = cross(up, back);
  if (lengthSquared(right) == 0) right = Frame::fromZ(back).s;  // up parallel to view
  right = normalize(right);
  Vec3f newUp = cross(back, right);
  Mat4 m;
  for (int r = 0; r < 3; ++r) {
    m.m[r][0] = right[r];
    m.m[r][1] = newUp[r];
    m.m[r][2] = back[r];
    m.m[r][3] = eye[r];
  }
  return Transform(m);
}

Vec3f Transform::point(Vec3f p, Vec3f* error) const {
  // Affine part only, each row summed in double and rounded once to float; that rounding is
  // measured, not bounded. The linear terms keep pbrt-v4's float bound, gamma(3) of their
  // magnitudes (spawned rays off sheared, unevenly scaled shapes rely on that margin,
  // Shapes.SpawnedRaysNeverReHitUnderWildTransforms), but the translation's magnitude no longer
  // enters it: far from the origin the bound was gamma(3) |t|, 0.18 at 1e6 (three float steps
  // there) whatever the point, and shadow rays started that far above the surface.
  const auto& m = m_.m;
  if (m[3][0] != 0 || m[3][1] != 0 || m[3][2] != 0 || m[3][3] != 1) {  // projective
    Vec3f absSum;
    for (int i = 0; i < 3; ++i)
      absSum[i] = std::abs(m[i][0] * p.x) + std::abs(m[i][1] * p.y) + std::abs(m[i][2] * p.z) +
                  std::abs(m[i][3]);
    *error = gamma(3) * absSum;
    return point(p);
  }
  Vec3f r;
  for (int i = 0; i < 3; ++i) {
    const double sum =
        double(m[i][0]) * p.x + double(m[i][1]) * p.y + double(m[i][2]) * p.z + double(m[i][3]);
    const float linear =
        std::abs(m[i][0] * p.x) + std::abs(m[i][1] * p.y) + std::abs(m[i][2] * p.z);
    r[i] = float(sum);
    const double rounding = std::abs(double(r[i]) - sum) + std::abs(double(m[i][3])) * 0x1p-50;
    (*error)[i] = nextFloatUp(float(rounding) + gamma(4) * linear);
  }
  return r;
}

Vec3f Transform::point(Vec3f p, Vec3f pError, Vec3f* error) const {
  const auto& m = m_.m;
  Vec3f own;
  Vec3f r = point(p, &own);
  Vec3f propagated{
      std::abs(m[0][0]) * pError.x + std::abs(m[0][1]) * pError.y + std::abs(m[0][2]) * pError.z,
      std::abs(m[1][0]) * pError.x + std::abs(m[1][1]) * pError.y + std::abs(m[1][2]) * pError.z,
      std::abs(m[2][0]) * pError.x + std::abs(m[2][1]) * pError.y + std::abs(m[2][2]) * pError.z};
  *error = own + (1 + gamma(3)) * propagated;
  return r;
}

Bounds3f Transform::bounds(const Bounds3f& b) const {
  Bounds3f r;
  if (b.empty()) return r;
  for (int i = 0; i < 8; ++i)
    r.extend(point({(i & 1) ? b.upper.x : b.lower.x, (i & 2) ? b.upper.y : b.lower.y,
                    (i & 4) ? b.upper.z : b.lower.z}));
  return r;
}

bool Transform::swapsHandedness() const {
  const auto& m = m_.m;
  float det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
              m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
              m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  return det < 0;
}

MeantTransform::MeantTransform() {
  for (int i = 0; i < 3; ++i) exact_[i][i] = 1;
}

float writtenPrecision(float v) {
  if (v == 0 || !std::isfinite(v)) return 0;
  char text[32];
  for (int digits = 1; digits <= 6; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, double(v));
    if (std::strtof(text, nullptr) == v) return 0;  // as short as written: meant exactly
  }
  return kWrittenPrecision * std::abs(v);
}

MeantTransform MeantTransform::written(const Mat4& m) {
  MeantTransform r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) {
      r.exact_[i][j] = m.m[i][j];
      r.written_[i][j] = writtenPrecision(m.m[i][j]);
    }
  return r;
}

MeantTransform MeantTransform::rotation(float degrees, Vec3f axis) {
  // Rodrigues' formula in double: R = c I + s [k]x + (1 - c) k k^T.
  const double len =
      std::sqrt(double(axis.x) * axis.x + double(axis.y) * axis.y + double(axis.z) * axis.z);
  const double k[3] = {axis.x / len, axis.y / len, axis.z / len};
  const double a = double(degrees) * 3.14159265358979323846 / 180;
  const double c = std::cos(a), sn = std::sin(a);
  const double cross[3][3] = {{0, -k[2], k[1]}, {k[2], 0, -k[0]}, {-k[1], k[0], 0}};
  MeantTransform r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r.exact_[i][j] = (i == j ? c : 0) + sn * cross[i][j] + (1 - c) * k[i] * k[j];
  return r;
}

MeantTransform operator*(const MeantTransform& a, const MeantTransform& b) {
  // Affine 3x4 products (last rows [0 0 0 1]); the written bounds to first order:
  // |a| W_b + W_a |b|.
  MeantTransform r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) {
      double e = 0, w = 0;
      for (int k = 0; k < 3; ++k) {
        e += a.exact_[i][k] * b.exact_[k][j];
        w += std::abs(a.exact_[i][k]) * b.written_[k][j] +
             a.written_[i][k] * std::abs(b.exact_[k][j]);
      }
      if (j == 3) e += a.exact_[i][3], w += a.written_[i][3];
      r.exact_[i][j] = e;
      r.written_[i][j] = w;
    }
  return r;
}

TransformError MeantTransform::errorOf(const Mat4& m) const {
  TransformError r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) {
      // The double products' own rounding is far below a float ulp: 2^-40 of the row's
      // magnitude covers it generously.
      double magnitude = std::abs(exact_[i][3]);
      for (int k = 0; k < 3; ++k) magnitude += std::abs(exact_[i][k]);
      const double bound =
          std::abs(double(m.m[i][j]) - exact_[i][j]) + written_[i][j] + 0x1p-40 * magnitude;
      r.e[i][j] = float(bound);
      if (double(r.e[i][j]) < bound) r.e[i][j] = nextFloatUp(r.e[i][j]);
    }
  return r;
}

}  // namespace glint
