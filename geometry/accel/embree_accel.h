// glint — Intel Embree 3 backend of the Accelerator interface.
#pragma once

#include <embree3/rtcore.h>

#include <mutex>
#include <string>
#include <vector>

#include "geometry/accel/accelerator.h"
#include "geometry/accel/unbounded.h"

namespace glint {

// Owns an Embree device and scene. Analytic shapes (primitives, CSG trees) are Embree user
// geometry through one generic adaptor (embree_shapes.cpp); unbounded ones (infinite planes)
// are kept out of the BVH, whose bounds they would ruin, and tested directly before each query
// (see UnboundedShapes). Meshes placed exactly once with an identity transform (the
// scene builder bakes single placements into world space) are attached to the top-level scene
// directly; meshes placed several times are built once as their own scene and instanced, so
// their triangles are stored once. Embree's device errors are recorded by the error callback
// (which must not throw) and raised as std::runtime_error after the call that caused them.
class EmbreeAccelerator final : public Accelerator {
 public:
  // `highQuality` asks Embree for its high-quality BVH build (RTC_BUILD_QUALITY_HIGH: SAH with
  // spatial splits), slower to build and a little faster to trace; the renderer uses the
  // default (medium) quality, benchmarks compare build times against the high one.
  explicit EmbreeAccelerator(const GeometryScene& scene, bool highQuality = false);
  ~EmbreeAccelerator() override;
  EmbreeAccelerator(const EmbreeAccelerator&) = delete;
  EmbreeAccelerator& operator=(const EmbreeAccelerator&) = delete;

  std::string name() const override { return "embree"; }
  bool closestHit(const Ray& ray, Hit* hit) const override;
  bool anyHit(const Ray& ray) const override;
  // Packets of up to 16 (rtcIntersect16 with a coherent context), so the BVH nodes a pixel's
  // samples share are visited once per packet.
  void closestHits(const Ray* rays, Hit* hits, int count) const override;

  // The raw top-level scene, for benchmarks that measure Embree alone.
  RTCScene rtcScene() const { return scene_; }
  // The benchmarks' reference: a bare rtcIntersect1 loop over `count` rays (RTCRayHit set up
  // and nothing else: no glint code per ray). Returns how many hit. Thread-safe.
  static uint64_t bareIntersect1(RTCScene scene, const Ray* rays, size_t count);
  // Maps a top-level geometry ID (of a direct mesh or an instance) to the instance index.
  uint32_t instanceOfGeometry(unsigned geomID) const { return instanceOfGeom_[geomID]; }

 private:
  bool traceClosest(const Ray& ray, Hit* hit) const;  // Embree only, no unbounded shapes
  RTCGeometry makeTriangleGeometry(const TriangleMesh& mesh);
  RTCGeometry makeShapeGeometry(const PlacedShape* shape);
  void checkError(const char* what);

  bool highQuality_ = false;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  std::vector<RTCScene> meshScenes_;       // per mesh, only for instanced meshes
  std::vector<uint32_t> instanceOfGeom_;   // top-level geomID -> instance index
  std::vector<PlacedShape> placedShapes_;  // bounded shape instances: Embree's user data
  UnboundedShapes unbounded_;

  std::mutex errorMutex_;
  std::string firstError_;
  friend void embreeErrorCallback(void*, RTCError, const char*);
};

}  // namespace glint
