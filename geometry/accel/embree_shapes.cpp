// glint — the generic Embree user-geometry adaptor: one RTCGeometry per placed analytic shape,
// whose callbacks forward to PlacedShape. Written once for every shape and CSG tree.
//
// The callbacks honour what Embree hands them: the `valid` mask of the N rays, each ray's
// [tnear, tfar] and time, the instance-ID stack of the context (so shapes may later live in
// instanced scenes), and the intersection/occlusion filter, which is called for every
// candidate hit before it is committed. Nothing here throws: the shapes do not.
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "geometry/accel/embree_accel.h"

namespace glint {

namespace {

Ray rayFromEmbree(RTCRayN* ray, unsigned N, unsigned i) {
  Ray r;
  r.o = {RTCRayN_org_x(ray, N, i), RTCRayN_org_y(ray, N, i), RTCRayN_org_z(ray, N, i)};
  r.d = {RTCRayN_dir_x(ray, N, i), RTCRayN_dir_y(ray, N, i), RTCRayN_dir_z(ray, N, i)};
  r.tMin = RTCRayN_tnear(ray, N, i);
  r.tMax = RTCRayN_tfar(ray, N, i);
  r.time = RTCRayN_time(ray, N, i);
  return r;
}

void boundsCallback(const RTCBoundsFunctionArguments* args) {
  const auto* shape = static_cast<const PlacedShape*>(args->geometryUserPtr);
  Bounds3f b = shape->bounds();
  RTCBounds* out = args->bounds_o;
  out->lower_x = b.lower.x, out->lower_y = b.lower.y, out->lower_z = b.lower.z;
  out->upper_x = b.upper.x, out->upper_y = b.upper.y, out->upper_z = b.upper.z;
}

void movingBoundsCallback(const RTCBoundsFunctionArguments* args) {
  const auto* shape = static_cast<const EmbreeAccelerator::MovingShape*>(args->geometryUserPtr);
  const Bounds3f& b = shape->keyBounds[args->timeStep];
  RTCBounds* out = args->bounds_o;
  out->lower_x = b.lower.x, out->lower_y = b.lower.y, out->lower_z = b.lower.z;
  out->upper_x = b.upper.x, out->upper_y = b.upper.y, out->upper_z = b.upper.z;
}

// The shape as the callbacks see it at ray time `time`: a static one as placed, a moving one
// placed where it is at that time.
const PlacedShape& placedAt(const PlacedShape* shape, float) { return *shape; }
PlacedShape placedAt(const EmbreeAccelerator::MovingShape* shape, float time) {
  return shape->at(time);
}

// Room for a hit packet of up to 16 rays (Embree's widest), in its SoA layout.
struct alignas(64) HitPacket {
  RTCHit16 storage;
  RTCHitN* get() { return reinterpret_cast<RTCHitN*>(&storage); }
};

// Writes lane i of a hit packet for a shape hit: glint computes normals and uvs later
// (two-phase hits), so only the ids and the instance stack matter.
void writeHit(RTCHitN* hits, unsigned N, unsigned i, const ShapeHit& sh, unsigned geomID,
              const RTCIntersectContext* context) {
  RTCHitN_Ng_x(hits, N, i) = 0;
  RTCHitN_Ng_y(hits, N, i) = 0;
  RTCHitN_Ng_z(hits, N, i) = 0;
  RTCHitN_u(hits, N, i) = 0;
  RTCHitN_v(hits, N, i) = 0;
  RTCHitN_primID(hits, N, i) = sh.part;
  RTCHitN_geomID(hits, N, i) = geomID;
  for (unsigned l = 0; l < RTC_MAX_INSTANCE_LEVEL_COUNT; ++l)
    RTCHitN_instID(hits, N, i, l) = context->instID[l];
}

// Runs the candidate hit of lane i through the filters (intersection or occlusion, per
// `Args`): as a hit packet with only that lane valid, with the ray's tfar set to the candidate
// distance (Embree's contract for filters). Returns true when the hit is accepted; on
// rejection the ray's tfar is restored, so it keeps its previous closest hit.
template <class Args>
bool acceptedByFilters(const Args* args, RTCRayN* rays, unsigned i, const ShapeHit& sh) {
  const unsigned N = args->N;
  HitPacket packet;
  writeHit(packet.get(), N, i, sh, args->geomID, args->context);
  int mask[16] = {};
  mask[i] = -1;
  const float oldTfar = RTCRayN_tfar(rays, N, i);
  RTCRayN_tfar(rays, N, i) = sh.t;
  RTCFilterFunctionNArguments filter;
  filter.valid = mask;
  filter.geometryUserPtr = args->geometryUserPtr;
  filter.context = args->context;
  filter.ray = rays;
  filter.hit = packet.get();
  filter.N = N;
  if constexpr (std::is_same_v<Args, RTCIntersectFunctionNArguments>)
    rtcFilterIntersection(args, &filter);
  else
    rtcFilterOcclusion(args, &filter);
  if (mask[i] != 0) return true;
  RTCRayN_tfar(rays, N, i) = oldTfar;
  return false;
}

template <class UserShape>
void intersectCallback(const RTCIntersectFunctionNArguments* args) {
  const auto* user = static_cast<const UserShape*>(args->geometryUserPtr);
  const unsigned N = args->N;
  RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, N);
  RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, N);
  for (unsigned i = 0; i < N; ++i) {
    if (args->valid[i] == 0) continue;
    // A filter may reject a hit (an alpha test, say): then the shape's next crossing along the
    // ray is offered, and so on (t - tError > tMin never returns the rejected one again).
    Ray ray = rayFromEmbree(rays, N, i);
    const auto& shape = placedAt(user, ray.time);
    ShapeHit sh;
    while (shape.intersect(ray, &sh)) {
      if (acceptedByFilters(args, rays, i, sh)) {
        writeHit(hits, N, i, sh, args->geomID, args->context);
        break;
      }
      ray.tMin = sh.t;
    }
  }
}

template <class UserShape>
void occludedCallback(const RTCOccludedFunctionNArguments* args) {
  const auto* user = static_cast<const UserShape*>(args->geometryUserPtr);
  const unsigned N = args->N;
  RTCRayN* rays = args->ray;
  for (unsigned i = 0; i < N; ++i) {
    if (args->valid[i] == 0) continue;
    // Crossings in order until the filters accept one, as for closest hits.
    Ray ray = rayFromEmbree(rays, N, i);
    const auto& shape = placedAt(user, ray.time);
    ShapeHit sh;
    while (shape.intersect(ray, &sh)) {
      if (acceptedByFilters(args, rays, i, sh)) {
        RTCRayN_tfar(rays, N, i) = -std::numeric_limits<float>::infinity();  // "occluded"
        break;
      }
      ray.tMin = sh.t;
    }
  }
}

}  // namespace

RTCGeometry EmbreeAccelerator::makeShapeGeometry(const PlacedShape* shape) {
  RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(geom, 1);
  rtcSetGeometryUserData(geom, const_cast<PlacedShape*>(shape));
  rtcSetGeometryBoundsFunction(geom, boundsCallback, nullptr);
  rtcSetGeometryIntersectFunction(geom, intersectCallback<PlacedShape>);
  rtcSetGeometryOccludedFunction(geom, occludedCallback<PlacedShape>);
  rtcCommitGeometry(geom);
  return geom;
}

RTCGeometry EmbreeAccelerator::makeMovingShapeGeometry(const MovingShape* shape) {
  RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(geom, 1);
  rtcSetGeometryTimeStepCount(geom, unsigned(shape->keyBounds.size()));
  rtcSetGeometryUserData(geom, const_cast<MovingShape*>(shape));
  rtcSetGeometryBoundsFunction(geom, movingBoundsCallback, nullptr);
  rtcSetGeometryIntersectFunction(geom, intersectCallback<MovingShape>);
  rtcSetGeometryOccludedFunction(geom, occludedCallback<MovingShape>);
  rtcCommitGeometry(geom);
  ++motionGeometryCount_;
  return geom;
}

// ---- conservative bounds of a moving shape per time step -------------------------------------

std::vector<Bounds3f> motionKeyBounds(const Bounds3f& objectBounds,
                                      const AnimatedTransform& motion) {
  const size_t segments = motion.keyCount() - 1;
  if (motion.keyCount() < 2 || objectBounds.empty())
    return std::vector<Bounds3f>(motion.keyCount(), objectBounds);
  // Samples per key interval; the padding below shrinks as 1/kSamples.
  constexpr int kSamples = 16;
  Vec3f corners[8];
  for (int c = 0; c < 8; ++c)
    corners[c] = {(c & 1) ? objectBounds.upper.x : objectBounds.lower.x,
                  (c & 2) ? objectBounds.upper.y : objectBounds.lower.y,
                  (c & 4) ? objectBounds.upper.z : objectBounds.lower.z};
  std::vector<Bounds3f> sweep(segments);
  for (size_t k = 0; k < segments; ++k) {
    const DecomposedTransform& d0 = motion.decomposedKey(k);
    const DecomposedTransform& d1 = motion.decomposedKey(k + 1);
    // A point x of the box moves as p(f) = T(f) + R(f) U(f) x over the interval's parameter
    // f in [0, 1], so |dp/df| <= |T1 - T0| + angle * max|U x| + max|(U1 - U0) x| (|U(f) x| is
    // at most its larger end value: U is blended linearly and the norm is convex).
    double reach = 0, stretch = 0;
    for (const Vec3f& c : corners) {
      for (const DecomposedTransform* d : {&d0, &d1}) {
        double n2 = 0;
        for (int r = 0; r < 3; ++r) {
          double ux = 0;
          for (int col = r; col < 3; ++col) ux += double(d->u[r][col]) * c[col];
          n2 += ux * ux;
        }
        reach = std::max(reach, std::sqrt(n2));
      }
      double n2 = 0;
      for (int r = 0; r < 3; ++r) {
        double dx = 0;
        for (int col = r; col < 3; ++col) dx += double(d1.u[r][col] - d0.u[r][col]) * c[col];
        n2 += dx * dx;
      }
      stretch = std::max(stretch, std::sqrt(n2));
    }
    const double cosHalf = std::min(1.0, std::abs(double(dot(d0.rotation, d1.rotation))));
    const double angle = 2 * std::acos(cosHalf);
    const double speed = length(d1.translation - d0.translation) + angle * reach + stretch;
    Bounds3f b;
    for (int j = 0; j <= kSamples; ++j) {
      const Transform xf = motion.at((float(k) + float(j) / kSamples) / float(segments));
      Vec3f err;
      for (const Vec3f& c : corners) {
        // Corner images padded by their rounding, as PlacedShape::bounds pads them.
        const Vec3f p = xf.point(c, &err);
        b.extend(p - err);
        b.extend(p + err);
      }
    }
    // Any time lies within half a sample step of a sample: a point is at most speed * step / 2
    // from where it was sampled. 1% and a relative 1e-5 of the extent cover the rounding of
    // the transform evaluation and Embree's approximate slerp near the keys.
    float magnitude = 0;
    for (int a = 0; a < 3; ++a)
      magnitude = std::max({magnitude, std::abs(b.lower[a]), std::abs(b.upper[a])});
    const float pad = float(1.01 * speed / (2 * kSamples)) + 1e-5f * magnitude;
    for (int a = 0; a < 3; ++a) b.lower[a] -= pad, b.upper[a] += pad;
    sweep[k] = b;
  }
  std::vector<Bounds3f> keys(motion.keyCount());
  for (size_t k = 0; k < keys.size(); ++k) {
    if (k > 0) keys[k].extend(sweep[k - 1]);
    if (k < segments) keys[k].extend(sweep[k]);
  }
  return keys;
}

}  // namespace glint
