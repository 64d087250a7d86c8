// glint — the reference for ray throughput: Embree alone, no glint code per ray.
// Header-only so that `glint bench-accel` (apps/) and pipeline_bench share the very same loop
// without the product's accelerator class carrying it. Here, in the accelerators' folder,
// because `glint bench-accel` is product code, and product code includes no benchmark.
#pragma once

#include <embree3/rtcore.h>

#include <cstddef>
#include <cstdint>

#include "geometry/ray.h"

namespace glint::bench {

// A bare rtcIntersect1 loop over `count` rays (RTCRayHit set up and nothing else). Returns how
// many hit. Thread-safe.
inline uint64_t bareIntersect1(RTCScene scene, const Ray* rays, size_t count) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  uint64_t hits = 0;
  for (size_t i = 0; i < count; ++i) {
    const Ray& ray = rays[i];
    RTCRayHit rh;
    rh.ray.org_x = ray.o.x, rh.ray.org_y = ray.o.y, rh.ray.org_z = ray.o.z;
    rh.ray.dir_x = ray.d.x, rh.ray.dir_y = ray.d.y, rh.ray.dir_z = ray.d.z;
    rh.ray.tnear = ray.tMin, rh.ray.tfar = ray.tMax, rh.ray.time = ray.time;
    rh.ray.mask = ~0u, rh.ray.id = 0, rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &context, &rh);
    hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  }
  return hits;
}

}  // namespace glint::bench
