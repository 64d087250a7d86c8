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
//
// Motion blur (Instance::motion animated; rays carry their normalised shutter time). Only what
// moves is built with time steps, so a static scene has exactly the layout and cost it had
// without motion:
// - a moving mesh is always instanced (never baked), by an instance geometry with one time
//   step per key, each given as Embree's quaternion decomposition (decomposedKey), so Embree
//   interpolates T and U linearly and R by slerp, as AnimatedTransform::at does;
// - a moving analytic shape is user geometry with one time step per key: the callbacks place
//   the shape at the ray's time (PlacedShape at motion.at(time)) and intersect the world ray,
//   and the per-step bounds (motionKeyBounds) are conservative for that nonlinear motion.
//   Chosen over hosting the shape in its own scene behind a motion instance because then
//   traversal and surface details use the very same transform and PlacedShape's robust
//   world-to-object ray transform (rays spawned from a hit never re-hit it) is kept; a motion
//   instance would hand the shape Embree's float-transformed ray instead, with an origin error
//   nothing accounts for. It costs one transform evaluation per candidate hit, moving shapes
//   only;
// - moving unbounded shapes (infinite planes) stay in UnboundedShapes, placed at the ray time;
// - a deforming mesh (TriangleMesh::positionSteps) is a triangle geometry with one vertex
//   buffer per time step, which Embree blends linearly at the ray's time; placed by a moving
//   instance, the two motions compose (Embree passes the ray's time into the instance).
//
// Single-sided meshes (TriangleMesh::singleSided) get intersection and occlusion filter
// functions that reject back-face hits, so one mechanism serves every query and packet size.
// Embree hands a filter an instanced mesh's ray and geometric normal in object space, where
// the front is the winding's side whatever the placement: a back face is dot(Ng, d) > 0.
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
  // Maps a top-level geometry ID (of a direct mesh or an instance) to the instance index.
  uint32_t instanceOfGeometry(unsigned geomID) const { return instanceOfGeom_[geomID]; }
  // How many geometries were built with time steps (moving instances and shapes, deforming
  // meshes): 0 for a static scene.
  uint32_t motionGeometryCount() const { return motionGeometryCount_; }

  // A moving analytic shape as Embree's user data: placed at each ray's time.
  struct MovingShape {
    const Shape* shape;
    const AnimatedTransform* motion;
    std::vector<Bounds3f> keyBounds;  // per time step, see motionKeyBounds
    PlacedShape at(float time) const { return PlacedShape(shape, motion->at(time)); }
  };

 private:
  bool traceClosest(const Ray& ray, Hit* hit) const;         // Embree only, no unbounded shapes
  bool closestHitUnrefined(const Ray& ray, Hit* hit) const;  // without refineFarHit
  RTCGeometry makeTriangleGeometry(const TriangleMesh& mesh);
  RTCGeometry makeShapeGeometry(const PlacedShape* shape);
  RTCGeometry makeMovingShapeGeometry(const MovingShape* shape);
  void checkError(const char* what);

  bool highQuality_ = false;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  std::vector<RTCScene> meshScenes_;       // per mesh, only for instanced meshes
  std::vector<uint32_t> instanceOfGeom_;   // top-level geomID -> instance index
  std::vector<PlacedShape> placedShapes_;  // bounded shape instances: Embree's user data
  std::vector<MovingShape> movingShapes_;  // bounded moving shape instances: the same
  uint32_t motionGeometryCount_ = 0;
  UnboundedShapes unbounded_;

  std::mutex errorMutex_;
  std::string firstError_;  // Embree's first error, "Embree error CODE: message"
  RTCError firstErrorCode_ = RTC_ERROR_NONE;
  friend void embreeErrorCallback(void*, RTCError, const char*);
};

// Bounds of `objectBounds` (in object space) for each key of `motion` (animated), such that
// for every time in the shutter the linear blend of the two keys' bounds around it contains
// the placed box at that time, rounding included: what Embree assumes of the per-time-step
// bounds of user geometry. Each key's box holds the whole sweep over its neighbouring key
// intervals (a blend of two boxes that both contain a set contains it); the sweep is sampled
// and padded by the farthest any point can travel between samples.
std::vector<Bounds3f> motionKeyBounds(const Bounds3f& objectBounds,
                                      const AnimatedTransform& motion);

}  // namespace glint
