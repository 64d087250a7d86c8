// glint — rays, and spawning rays from surfaces without a fixed epsilon.
#pragma once

#include "geometry/math.h"

namespace glint {

// A ray o + t d for t in [tMin, tMax], at `time` in the shutter interval (0 when nothing
// moves; carried from day one so motion blur adds keys, not plumbing). `d` need not be unit
// length; t is measured in units of |d|.
struct Ray {
  Vec3f o;
  Vec3f d;
  float tMin = 0;
  float tMax = kInfinity;
  float time = 0;

  Vec3f at(float t) const { return o + d * t; }
};

// Moves `p` off its surface, to the side of the geometric normal `n` that `w` points to, by
// just enough to clear the point's rounding error `pError` (pbrt-v4's OffsetRayOrigin). The
// offset therefore scales with the hit point's magnitude and with how it was computed:
// there is no global epsilon that would be wrong for tiny or huge scenes.
inline Vec3f offsetRayOrigin(Vec3f p, Vec3f pError, Vec3f n, Vec3f w) {
  float d = dot(abs(n), pError);
  Vec3f offset = n * d;
  if (dot(w, n) < 0) offset = -offset;
  Vec3f po = p + offset;
  // Round away from p so the offset survives the addition's own rounding.
  for (int i = 0; i < 3; ++i) {
    if (offset[i] > 0)
      po[i] = nextFloatUp(po[i]);
    else if (offset[i] < 0)
      po[i] = nextFloatDown(po[i]);
  }
  return po;
}

// A ray leaving a surface point in direction `d`.
inline Ray spawnRay(Vec3f p, Vec3f pError, Vec3f n, Vec3f d, float time) {
  return Ray{offsetRayOrigin(p, pError, n, d), d, 0, kInfinity, time};
}

// Fraction of the segment length kept by shadow rays towards a point that has no error of its
// own (a point light): relative, so it stays meaningful at any scene scale.
inline constexpr float kShadowEpsilon = 1e-4f;

// A shadow ray from a surface point towards the point `target`; t in [0, 1) spans the segment.
inline Ray spawnRayTo(Vec3f p, Vec3f pError, Vec3f n, Vec3f target, float time) {
  Vec3f o = offsetRayOrigin(p, pError, n, target - p);
  return Ray{o, target - o, 0, 1 - kShadowEpsilon, time};
}

}  // namespace glint
