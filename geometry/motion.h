// glint — transforms that change during the shutter.
//
// Motion is stored as keys at uniform times over the normalised shutter time [0, 1] (ray time
// 0 = shutter open, 1 = shutter close), which is how Embree's time steps work. Each key is kept
// decomposed as Embree's RTCQuaternionDecomposition is: M = T · R · U, with U upper triangular
// (scale and shear), R a rotation held as a unit quaternion and T a translation. Between keys U
// and T are interpolated linearly and R by slerp, exactly as Embree interpolates motion
// instances, so a turning wheel stays round instead of shrinking through the linear blend of
// two rotation matrices, and the surface details glint computes at a hit use the same
// transform Embree intersected.
#pragma once

#include <vector>

#include "geometry/math.h"

namespace glint {

// A unit quaternion x i + y j + z k + w (glTF's order).
struct Quaternion {
  float x = 0, y = 0, z = 0, w = 1;
};

Quaternion normalize(const Quaternion& q);
float dot(const Quaternion& a, const Quaternion& b);
// Spherical linear interpolation along the shorter arc; nlerp when the two are nearly equal.
// Computed as Embree computes it (its approximate acos included), so a moving surface is where
// Embree intersected it to within float rounding.
Quaternion slerp(const Quaternion& a, const Quaternion& b, float t);
// The rotation matrix of a unit quaternion (and its transpose as the inverse).
Transform toTransform(const Quaternion& q);
// The quaternion of a rotation matrix (the 3x3 part of `m`, assumed orthonormal, det +1).
Quaternion quaternionFromRotation(const Mat4& m);

// One key: M = T · R · U.
struct DecomposedTransform {
  // Upper-triangular scale/shear: u[0] = (sx, sxy, sxz), u[1] = (0, sy, syz), u[2] = (0,0,sz).
  float u[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Quaternion rotation;
  Vec3f translation{0, 0, 0};

  // QR decomposition of the affine part of `xf` (Gram–Schmidt in double precision). A
  // reflection goes into U as a negative sz, so R is always a proper rotation.
  static DecomposedTransform fromTransform(const Transform& xf);
  Transform toTransform() const;
  static DecomposedTransform lerp(const DecomposedTransform& a, const DecomposedTransform& b,
                                  float t);
};

// The most keys a motion may have: Embree 3's RTC_MAX_TIME_STEP_COUNT.
inline constexpr size_t kMaxMotionKeys = 129;

class AnimatedTransform {
 public:
  // The identity, not moving. A static transform lives in `first_` alone, so the many
  // instances that never move carry no heap allocation for their motion.
  AnimatedTransform() = default;
  explicit AnimatedTransform(const Transform& xf) : first_(xf) {}
  // Keys at times i / (n - 1) of the shutter, 1 <= n <= kMaxMotionKeys. Consecutive rotations are
  // put in the same hemisphere so slerp takes the short way between them; callers sample densely
  // enough that no step turns by more than 180 degrees. All keys equal collapses to one (no
  // motion).
  explicit AnimatedTransform(std::vector<Transform> keys);

  bool isAnimated() const { return !keys_.empty(); }
  size_t keyCount() const { return isAnimated() ? keys_.size() : 1; }
  const Transform& key(size_t i) const { return isAnimated() ? keys_[i] : first_; }
  // The decomposition of key i (animated transforms only): what Embree is given.
  const DecomposedTransform& decomposedKey(size_t i) const { return decomposed_[i]; }
  // The transform at normalised shutter time `time` (clamped to [0, 1]). Exactly key i at time
  // i / (n - 1); the first key when not animated.
  Transform at(float time) const;
  // A bound on how far Embree's own interpolation of these keys at `time` (the transform it
  // intersected a moving mesh with) may differ from at(time), relative to the matrix's scale:
  // entry by entry, |M_embree - M| <= bound * (largest linear entry [+ |translation|]). Both
  // slerp the same way but round differently; between nearly parallel rotations the
  // difference is amplified by 1 / sin(angle). Zero when not animated.
  float interpolationMismatch(float time) const;
  // Bounds of `b` swept over the shutter, sampled at the keys and `steps` times between
  // consecutive keys. For framing and statistics only: traversal bounds are Embree's own.
  Bounds3f motionBounds(const Bounds3f& b, int steps = 8) const;

 private:
  Transform first_;                              // key 0
  std::vector<Transform> keys_;                  // every key, or empty when not animated
  std::vector<DecomposedTransform> decomposed_;  // empty unless animated
};

}  // namespace glint
