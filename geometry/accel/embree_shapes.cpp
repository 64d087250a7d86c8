// glint — the generic Embree user-geometry adaptor: one RTCGeometry per placed analytic shape,
// whose callbacks forward to PlacedShape. Written once for every shape and CSG tree.
//
// The callbacks honour what Embree hands them: the `valid` mask of the N rays, each ray's
// [tnear, tfar] and time, the instance-ID stack of the context (so shapes may later live in
// instanced scenes), and the intersection/occlusion filter, which is called for every
// candidate hit before it is committed. Nothing here throws: the shapes do not.
#include <embree3/rtcore.h>

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

void intersectCallback(const RTCIntersectFunctionNArguments* args) {
  const auto* shape = static_cast<const PlacedShape*>(args->geometryUserPtr);
  const unsigned N = args->N;
  RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, N);
  RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, N);
  for (unsigned i = 0; i < N; ++i) {
    if (args->valid[i] == 0) continue;
    // A filter may reject a hit (an alpha test, say): then the shape's next crossing along the
    // ray is offered, and so on (t - tError > tMin never returns the rejected one again).
    Ray ray = rayFromEmbree(rays, N, i);
    ShapeHit sh;
    while (shape->intersect(ray, &sh)) {
      if (acceptedByFilters(args, rays, i, sh)) {
        writeHit(hits, N, i, sh, args->geomID, args->context);
        break;
      }
      ray.tMin = sh.t;
    }
  }
}

void occludedCallback(const RTCOccludedFunctionNArguments* args) {
  const auto* shape = static_cast<const PlacedShape*>(args->geometryUserPtr);
  const unsigned N = args->N;
  RTCRayN* rays = args->ray;
  for (unsigned i = 0; i < N; ++i) {
    if (args->valid[i] == 0) continue;
    // Crossings in order until the filters accept one, as for closest hits.
    Ray ray = rayFromEmbree(rays, N, i);
    ShapeHit sh;
    while (shape->intersect(ray, &sh)) {
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
  rtcSetGeometryIntersectFunction(geom, intersectCallback);
  rtcSetGeometryOccludedFunction(geom, occludedCallback);
  rtcCommitGeometry(geom);
  return geom;
}

}  // namespace glint
