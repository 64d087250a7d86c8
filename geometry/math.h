// glint — small math value types: vectors, bounds, 4x4 transforms, float rounding helpers.
//
// One vector type (Vec3f) serves points, directions and normals, as in yocto-gl; what a
// value *is* is said by the transform call that consumes it: xf.point(p), xf.vector(v),
// xf.normal(n). We chose this over pbrt-v4's distinct Point3f/Normal3f types because the
// renderer is small enough that the extra type algebra costs more than it catches; the
// transform names keep the distinction where it matters (normals use the inverse transpose).
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace glint {

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.31830988618379067154f;
inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

// ---------------------------------------------------------------------------------------------
// Vectors
// ---------------------------------------------------------------------------------------------

struct Vec2f {
  float x = 0, y = 0;
  constexpr float operator[](int i) const { return i == 0 ? x : y; }
  constexpr float& operator[](int i) { return i == 0 ? x : y; }
};
constexpr Vec2f operator+(Vec2f a, Vec2f b) { return {a.x + b.x, a.y + b.y}; }
constexpr Vec2f operator-(Vec2f a, Vec2f b) { return {a.x - b.x, a.y - b.y}; }
constexpr Vec2f operator*(Vec2f a, float s) { return {a.x * s, a.y * s}; }
constexpr Vec2f operator*(float s, Vec2f a) { return {a.x * s, a.y * s}; }
constexpr bool operator==(Vec2f a, Vec2f b) { return a.x == b.x && a.y == b.y; }

struct Vec3f {
  float x = 0, y = 0, z = 0;
  constexpr float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
};
constexpr Vec3f operator+(Vec3f a, Vec3f b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
constexpr Vec3f operator-(Vec3f a, Vec3f b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
constexpr Vec3f operator-(Vec3f a) { return {-a.x, -a.y, -a.z}; }
constexpr Vec3f operator*(Vec3f a, Vec3f b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
constexpr Vec3f operator/(Vec3f a, Vec3f b) { return {a.x / b.x, a.y / b.y, a.z / b.z}; }
constexpr Vec3f operator*(Vec3f a, float s) { return {a.x * s, a.y * s, a.z * s}; }
constexpr Vec3f operator*(float s, Vec3f a) { return {a.x * s, a.y * s, a.z * s}; }
constexpr Vec3f operator/(Vec3f a, float s) { return {a.x / s, a.y / s, a.z / s}; }
constexpr Vec3f& operator+=(Vec3f& a, Vec3f b) { return a = a + b; }
constexpr Vec3f& operator-=(Vec3f& a, Vec3f b) { return a = a - b; }
constexpr Vec3f& operator*=(Vec3f& a, Vec3f b) { return a = a * b; }
constexpr Vec3f& operator*=(Vec3f& a, float s) { return a = a * s; }
constexpr bool operator==(Vec3f a, Vec3f b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

constexpr float dot(Vec3f a, Vec3f b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3f cross(Vec3f a, Vec3f b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(Vec3f a) { return std::sqrt(dot(a, a)); }
inline float lengthSquared(Vec3f a) { return dot(a, a); }
inline Vec3f normalize(Vec3f a) { return a / length(a); }
inline float distance(Vec3f a, Vec3f b) { return length(a - b); }
inline Vec3f abs(Vec3f a) { return {std::abs(a.x), std::abs(a.y), std::abs(a.z)}; }
constexpr Vec3f min(Vec3f a, Vec3f b) {
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
constexpr Vec3f max(Vec3f a, Vec3f b) {
  return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
constexpr float maxComponent(Vec3f a) { return std::max(a.x, std::max(a.y, a.z)); }
inline bool isFinite(Vec3f a) {
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}
// Flips n so that it lies in the hemisphere of v.
constexpr Vec3f faceForward(Vec3f n, Vec3f v) { return dot(n, v) < 0 ? -n : n; }
inline Vec3f lerp(float t, Vec3f a, Vec3f b) { return (1 - t) * a + t * b; }

// Linear RGB in the scene_linear space (Rec.709 primaries) shares the vector type.
using Rgb = Vec3f;
inline float luminance(Rgb c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

struct Vec4f {
  float x = 0, y = 0, z = 0, w = 0;
  constexpr float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : (i == 2 ? z : w)); }
};

// An orthonormal basis around a unit normal (Duff et al. 2017, "Building an Orthonormal
// Basis, Revisited"): no branch on a threshold, continuous except at n.z = -1 exactly.
struct Frame {
  Vec3f s, t, n;
  static Frame fromZ(Vec3f n) {
    float sign = std::copysign(1.0f, n.z);
    float a = -1.0f / (sign + n.z);
    float b = n.x * n.y * a;
    return {{1 + sign * n.x * n.x * a, sign * b, -sign * n.x}, {b, sign + n.y * n.y * a, -n.y}, n};
  }
  Vec3f toLocal(Vec3f v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
  Vec3f fromLocal(Vec3f v) const { return s * v.x + t * v.y + n * v.z; }
};

// A 64-bit hash finaliser (Stafford's Mix13 variant of MurmurHash3's fmix64), a strong
// bijective mix: the sampler, random colours and snow all hash with it.
inline uint64_t mixBits(uint64_t v) {
  v ^= v >> 31;
  v *= 0x7fb5d329728ea185ull;
  v ^= v >> 27;
  v *= 0x81dadef4bc2dd44dull;
  v ^= v >> 33;
  return v;
}

// ---------------------------------------------------------------------------------------------
// Bounds
// ---------------------------------------------------------------------------------------------

struct Bounds3f {
  Vec3f lower{kInfinity, kInfinity, kInfinity};
  Vec3f upper{-kInfinity, -kInfinity, -kInfinity};

  bool empty() const { return lower.x > upper.x || lower.y > upper.y || lower.z > upper.z; }
  void extend(Vec3f p) { lower = min(lower, p), upper = max(upper, p); }
  void extend(const Bounds3f& b) { lower = min(lower, b.lower), upper = max(upper, b.upper); }
  Vec3f center() const { return (lower + upper) * 0.5f; }
  Vec3f diagonal() const { return upper - lower; }
};

// ---------------------------------------------------------------------------------------------
// Floating-point rounding (for conservative error bounds, pbrt-v4 style)
// ---------------------------------------------------------------------------------------------

inline constexpr float kMachineEpsilon = std::numeric_limits<float>::epsilon() * 0.5f;
// Bound on the relative error of n floating-point operations.
constexpr float gamma(int n) { return (n * kMachineEpsilon) / (1 - n * kMachineEpsilon); }

inline float nextFloatUp(float v) {
  if (std::isinf(v) && v > 0) return v;
  if (v == -0.0f) v = 0.0f;
  uint32_t bits = std::bit_cast<uint32_t>(v);
  bits = v >= 0 ? bits + 1 : bits - 1;
  return std::bit_cast<float>(bits);
}
inline float nextFloatDown(float v) {
  if (std::isinf(v) && v < 0) return v;
  if (v == 0.0f) v = -0.0f;
  uint32_t bits = std::bit_cast<uint32_t>(v);
  bits = v > 0 ? bits - 1 : bits + 1;
  return std::bit_cast<float>(bits);
}

// ---------------------------------------------------------------------------------------------
// Transforms: a 4x4 matrix with its inverse, named destination-from-source.
// ---------------------------------------------------------------------------------------------

struct Mat4 {
  // Row-major: m[row][col]. Points are column vectors: p' = M p.
  std::array<std::array<float, 4>, 4> m{{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};

  static Mat4 identity() { return {}; }
  // From 16 numbers in glTF's column-major order.
  static Mat4 fromColumnMajor(const float* v) {
    Mat4 r;
    for (int c = 0; c < 4; ++c)
      for (int rr = 0; rr < 4; ++rr) r.m[rr][c] = v[c * 4 + rr];
    return r;
  }
  bool isIdentity() const { return *this == Mat4{}; }
  friend bool operator==(const Mat4& a, const Mat4& b) { return a.m == b.m; }
};

Mat4 operator*(const Mat4& a, const Mat4& b);
Mat4 transpose(const Mat4& a);
// Returns false (and leaves `out` untouched) when the matrix is singular or not finite.
bool invert(const Mat4& a, Mat4* out);

class Transform {
 public:
  Transform() = default;
  // `m` must be invertible; check with invert() first when it comes from user input.
  explicit Transform(const Mat4& m);
  Transform(const Mat4& m, const Mat4& inverse) : m_(m), inv_(inverse) {}

  static Transform translate(Vec3f t);
  static Transform scale(Vec3f s);
  // Rotation by a unit quaternion (x, y, z, w), as glTF stores it.
  static Transform rotateQuaternion(Vec4f q);
  static Transform rotate(float degrees, Vec3f axis);
  // Camera-to-world frame looking from `eye` at `target` along -Z with +Y up (glTF convention).
  static Transform lookAt(Vec3f eye, Vec3f target, Vec3f up);

  const Mat4& matrix() const { return m_; }
  const Mat4& inverseMatrix() const { return inv_; }
  Transform inverse() const { return Transform(inv_, m_); }
  bool isIdentity() const { return m_.isIdentity(); }

  Vec3f point(Vec3f p) const {
    const auto& m = m_.m;
    Vec3f r{m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
            m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
            m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
    float w = m[3][0] * p.x + m[3][1] * p.y + m[3][2] * p.z + m[3][3];
    return w == 1 ? r : r / w;
  }
  // Transforms an affine point and bounds the rounding error of the result
  // (pbrt-v4, Transform::operator()(Point3fi)): `error` receives |p' - exact|.
  Vec3f point(Vec3f p, Vec3f* error) const;
  // Same, for a point that already carries an absolute error `pError`.
  Vec3f point(Vec3f p, Vec3f pError, Vec3f* error) const;
  Vec3f vector(Vec3f v) const {
    const auto& m = m_.m;
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
            m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
  }
  // Normals go through the inverse transpose; the result is not normalized.
  Vec3f normal(Vec3f n) const {
    const auto& i = inv_.m;
    return {i[0][0] * n.x + i[1][0] * n.y + i[2][0] * n.z,
            i[0][1] * n.x + i[1][1] * n.y + i[2][1] * n.z,
            i[0][2] * n.x + i[1][2] * n.y + i[2][2] * n.z};
  }
  Bounds3f bounds(const Bounds3f& b) const;
  // True when the transform flips handedness (negative determinant of the 3x3 part).
  bool swapsHandedness() const;

  friend Transform operator*(const Transform& a, const Transform& b) {
    return Transform(a.m_ * b.m_, b.inv_ * a.inv_);
  }
  friend bool operator==(const Transform& a, const Transform& b) { return a.m_ == b.m_; }

 private:
  Mat4 m_, inv_;
};

// ---------------------------------------------------------------------------------------------
// How far a transform read from a file lies from the one its author meant
// ---------------------------------------------------------------------------------------------

// A number in a scene file that needs seven or more significant digits is taken to mean
// anything within this relative distance of itself: half a unit in its seventh digit (a third
// written 0.3333333, 1/0.7 as 1.428571). Shorter numbers (0.5, 10, 37.25) mean what they say.
inline constexpr float kWrittenPrecision = 5e-7f;
// The distance from `v` (a number as parsed) within which its author may have meant another:
// kWrittenPrecision |v| when v needs seven or more significant digits, else 0.
float writtenPrecision(float v);

// An entrywise bound on |M - M_meant| for a transform's 3x4 affine part (the last row
// [0, 0, 0, 1] is exact).
struct TransformError {
  std::array<std::array<float, 4>, 3> e{};  // zero: exact
};

// The transform a file's operations mean, composed beside the float Transform glint builds
// from them: the same operations composed in double from the numbers as parsed, so that
// |float matrix - exact| measures every rounding of sines, cosines, quaternions and products
// (not a bound: the difference itself), plus a bound on how far the written numbers may be
// from the ones their author meant (kWrittenPrecision; first order). Rotation angles and axes
// are taken as meant: 90 is 90, and a rotation undone by its negative is undone exactly.
// CSG trees use the result to tell faces that coincide as meant from faces that are apart.
class MeantTransform {
 public:
  MeantTransform();  // the identity, exact
  // An operation whose matrix entries are written numbers: translate, scale, shear, matrix.
  static MeantTransform written(const Mat4& m);
  // Transform::rotate(degrees, axis), exactly.
  static MeantTransform rotation(float degrees, Vec3f axis);
  // a applied after b, as Transform's operator*.
  friend MeantTransform operator*(const MeantTransform& a, const MeantTransform& b);
  // The bound on |m - meant| for the float matrix m composed from the same operations.
  TransformError errorOf(const Mat4& m) const;

 private:
  std::array<std::array<double, 4>, 3> exact_{};
  std::array<std::array<double, 4>, 3> written_{};  // entrywise bound
};

}  // namespace glint
