// glint — rays, and spawning rays from surfaces without a fixed epsilon.
#pragma once

#include <algorithm>

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

// Shadow rays are parametrised by distance: unit direction, t in metres (scene units) from the
// offset origin. Their end depends on what is at the far end.
//
// Towards a point that has no surface of its own (a point or spot light, a point in a medium):
// the ray reaches it exactly (tMax is the whole distance). An occluder anywhere before the
// light is found, however close to it: a lamp 1 mm under a ceiling lights nothing above it
// from any distance.
inline Ray spawnRayTo(Vec3f p, Vec3f pError, Vec3f n, Vec3f target, float time) {
  const Vec3f o = offsetRayOrigin(p, pError, n, target - p);
  const Vec3f d = target - o;
  const float distance = length(d);
  if (!(distance > 0)) return Ray{o, n, 0, 0, time};  // nothing to cross
  return Ray{o, d / distance, 0, distance, time};
}

// Towards a point `q` on a surface that must not be reported (an area light's sample, a VPL),
// with error bound `qError` and geometric normal `nq` (zero: no surface, as above). Both ends
// leave their surfaces by their own error bounds (offsetRayOrigin), and the ray stops short
// of the offset end by the rounding a hit's distance can carry there, a few ulps of the two
// ends' coordinates (gamma(4) of them; a hit's t comes from differences of such coordinates),
// plus 16 times the length of q's error bound: q may lie that far outside a neighbouring face
// of its own surface (a box light's edge), which a ray reaching q at a slant crosses within a
// few error lengths of the end. The margin comes from the points' magnitudes and errors, not
// from a fraction of the segment, so an occluder near a light near the origin is found from
// far away (1e-3 in front of it from 1,000 units, where a fixed 1e-4 of the segment lost 0.1).
inline Ray spawnRayToSurface(Vec3f p, Vec3f pError, Vec3f n, Vec3f q, Vec3f qError, Vec3f nq,
                             float time) {
  if (nq.x == 0 && nq.y == 0 && nq.z == 0) return spawnRayTo(p, pError, n, q, time);
  const Vec3f o = offsetRayOrigin(p, pError, n, q - p);
  const Vec3f end = offsetRayOrigin(q, qError, nq, o - q);
  const Vec3f d = end - o;
  const float distance = length(d);
  if (!(distance > 0)) return Ray{o, n, 0, 0, time};
  const float rounding =
      gamma(4) * (maxComponent(abs(o)) + maxComponent(abs(end))) + 16 * length(qError);
  return Ray{o, d / distance, 0, std::max(0.0f, distance - rounding), time};
}

}  // namespace glint
