// glint — Intel Embree 3 backend.
#include "geometry/accel/embree_accel.h"

#include <algorithm>
#include <cassert>
#include <cstring>
#include <stdexcept>

#include "geometry/error.h"

namespace glint {

void embreeErrorCallback(void* user, RTCError code, const char* message) {
  // Runs inside Embree: record, never throw.
  auto* self = static_cast<EmbreeAccelerator*>(user);
  std::lock_guard<std::mutex> lock(self->errorMutex_);
  if (self->firstError_.empty()) {
    self->firstError_ =
        "Embree error " + std::to_string(int(code)) + ": " + (message ? message : "(no message)");
    self->firstErrorCode_ = code;
  }
}

namespace {

// The filter of single-sided meshes (intersect and occluded alike): rejects hits on back faces.
// Ray and normal are in the mesh's object space (Embree transforms the ray into an instance).
void cullBackFaces(const RTCFilterFunctionNArguments* args) {
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const float side = RTCHitN_Ng_x(args->hit, args->N, i) * RTCRayN_dir_x(args->ray, args->N, i) +
                       RTCHitN_Ng_y(args->hit, args->N, i) * RTCRayN_dir_y(args->ray, args->N, i) +
                       RTCHitN_Ng_z(args->hit, args->N, i) * RTCRayN_dir_z(args->ray, args->N, i);
    if (side > 0) args->valid[i] = 0;
  }
}

// One time step per key, each as Embree's quaternion decomposition M = T R U (no shift): Embree
// then blends T and U linearly and R by slerp, as AnimatedTransform::at does.
void setMotionTransform(RTCGeometry geom, const AnimatedTransform& motion) {
  assert(motion.keyCount() <= kMaxMotionKeys);
  rtcSetGeometryTimeStepCount(geom, unsigned(motion.keyCount()));
  for (size_t k = 0; k < motion.keyCount(); ++k) {
    const DecomposedTransform& d = motion.decomposedKey(k);
    RTCQuaternionDecomposition qd;
    rtcInitQuaternionDecomposition(&qd);
    rtcQuaternionDecompositionSetScale(&qd, d.u[0][0], d.u[1][1], d.u[2][2]);
    rtcQuaternionDecompositionSetSkew(&qd, d.u[0][1], d.u[0][2], d.u[1][2]);
    rtcQuaternionDecompositionSetShift(&qd, 0, 0, 0);
    // Embree's quaternion is r + i i + j j + k k: r is glint's w.
    rtcQuaternionDecompositionSetQuaternion(&qd, d.rotation.w, d.rotation.x, d.rotation.y,
                                            d.rotation.z);
    rtcQuaternionDecompositionSetTranslation(&qd, d.translation.x, d.translation.y,
                                             d.translation.z);
    rtcSetGeometryTransformQuaternion(geom, unsigned(k), &qd);
  }
}

}  // namespace

EmbreeAccelerator::EmbreeAccelerator(const GeometryScene& geometry, bool highQuality)
    : highQuality_(highQuality) {
  device_ = rtcNewDevice(nullptr);
  // Not the scene's fault: the CPU or the memory (exit code 1).
  if (!device_)
    throw FailureError("cannot create an Embree device (Embree error " +
                       std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
  rtcSetDeviceErrorFunction(device_, embreeErrorCallback, this);

  // How often each mesh is placed decides direct attachment versus instancing.
  std::vector<uint32_t> uses(geometry.meshes.size(), 0);
  size_t movingShapeCount = 0;
  for (const Instance& inst : geometry.instances) {
    if (!inst.isShape()) ++uses[inst.mesh];
    movingShapeCount += inst.isShape() && inst.moves();
  }
  meshScenes_.assign(geometry.meshes.size(), nullptr);
  unbounded_.build(geometry);
  // Embree keeps pointers to the placed shapes: the vectors must not reallocate.
  placedShapes_.reserve(geometry.shapeInstanceCount() - movingShapeCount);
  movingShapes_.reserve(movingShapeCount);

  scene_ = rtcNewScene(device_);
  if (highQuality_) rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
  for (uint32_t i = 0; i < geometry.instances.size(); ++i) {
    const Instance& inst = geometry.instances[i];
    RTCGeometry geom;
    if (inst.isShape()) {
      if (unbounded_.contains(i)) continue;
      if (inst.moves()) {
        const Shape* shape = geometry.shapes[inst.shape].get();
        movingShapes_.push_back(
            {shape, &inst.motion, motionKeyBounds(shape->bounds(), inst.motion)});
        geom = makeMovingShapeGeometry(&movingShapes_.back());
      } else {
        placedShapes_.push_back(geometry.placedShape(i));
        geom = makeShapeGeometry(&placedShapes_.back());
      }
    } else {
      const TriangleMesh& mesh = geometry.meshes[inst.mesh];
      if (mesh.triangleCount() == 0) continue;
      if (uses[inst.mesh] == 1 && !inst.moves() && inst.worldFromObject.isIdentity()) {
        geom = makeTriangleGeometry(mesh);
      } else {
        RTCScene& meshScene = meshScenes_[inst.mesh];
        if (!meshScene) {
          meshScene = rtcNewScene(device_);
          if (highQuality_) rtcSetSceneBuildQuality(meshScene, RTC_BUILD_QUALITY_HIGH);
          RTCGeometry tri = makeTriangleGeometry(mesh);
          rtcAttachGeometry(meshScene, tri);
          rtcReleaseGeometry(tri);
          rtcCommitScene(meshScene);
        }
        geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(geom, meshScene);
        if (inst.moves()) {
          setMotionTransform(geom, inst.motion);
          ++motionGeometryCount_;
        } else {
          float m[12];  // 3x4 column-major
          const auto& a = inst.worldFromObject.matrix().m;
          for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 3; ++r) m[c * 3 + r] = a[r][c];
          rtcSetGeometryTransform(geom, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m);
        }
        rtcCommitGeometry(geom);
      }
    }
    unsigned id = rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);
    if (instanceOfGeom_.size() <= id) instanceOfGeom_.resize(id + 1, Hit::kInvalid);
    instanceOfGeom_[id] = i;
  }
  rtcCommitScene(scene_);
  checkError("building the Embree scene");
}

EmbreeAccelerator::~EmbreeAccelerator() {
  if (scene_) rtcReleaseScene(scene_);
  for (RTCScene s : meshScenes_)
    if (s) rtcReleaseScene(s);
  if (device_) rtcReleaseDevice(device_);
}

RTCGeometry EmbreeAccelerator::makeTriangleGeometry(const TriangleMesh& mesh) {
  RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  if (highQuality_) rtcSetGeometryBuildQuality(geom, RTC_BUILD_QUALITY_HIGH);
  // Copied into Embree-owned buffers: Embree needs padding after the last vertex that our
  // tightly packed vectors do not have. A deforming mesh gets one vertex buffer per time step.
  const size_t steps = mesh.deforms() ? mesh.positionSteps.size() : 1;
  if (mesh.deforms()) {
    rtcSetGeometryTimeStepCount(geom, unsigned(steps));
    ++motionGeometryCount_;
  }
  bool allocated = true;
  for (size_t k = 0; k < steps; ++k) {
    const std::vector<Vec3f>& p = mesh.deforms() ? mesh.positionSteps[k] : mesh.positions;
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, unsigned(k), RTC_FORMAT_FLOAT3, sizeof(Vec3f), p.size()));
    if (v) std::memcpy(v, p.data(), p.size() * sizeof(Vec3f));
    allocated = allocated && v;
  }
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0,
                                                             RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                                             mesh.triangleCount()));
  if (!allocated || !idx) {
    rtcReleaseGeometry(geom);
    checkError("allocating Embree buffers");
    throw FailureError("cannot allocate Embree buffers for a mesh of " +
                       std::to_string(mesh.triangleCount()) + " triangles");
  }
  std::memcpy(idx, mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t));
  if (mesh.singleSided) {
    rtcSetGeometryIntersectFilterFunction(geom, cullBackFaces);
    rtcSetGeometryOccludedFilterFunction(geom, cullBackFaces);
  }
  rtcCommitGeometry(geom);
  return geom;
}

void EmbreeAccelerator::checkError(const char* what) {
  std::lock_guard<std::mutex> lock(errorMutex_);
  if (firstError_.empty()) return;
  const std::string message = std::string(what) + ": " + firstError_;
  // An argument or call Embree rejects is glint's mistake (main: "internal error"); the rest
  // (out of memory, an unsupported CPU, a cancelled build) is work that could not be done.
  if (firstErrorCode_ == RTC_ERROR_INVALID_ARGUMENT ||
      firstErrorCode_ == RTC_ERROR_INVALID_OPERATION)
    throw std::logic_error(message);
  throw FailureError(message);
}

bool EmbreeAccelerator::closestHit(const Ray& ray, Hit* hit) const {
  if (!closestHitUnrefined(ray, hit)) return false;
  refineFarHit(ray, hit, [this](const Ray& r, Hit* h) { return closestHitUnrefined(r, h); });
  return true;
}

bool EmbreeAccelerator::closestHitUnrefined(const Ray& ray, Hit* hit) const {
  if (!unbounded_.empty()) {
    // The nearest plane shortens the ray Embree traces.
    Hit plane;
    if (!unbounded_.closestHit(ray, &plane)) return traceClosest(ray, hit);
    Ray shorter = ray;
    shorter.tMax = plane.t;
    if (traceClosest(shorter, hit) && hit->t < plane.t) return true;
    *hit = plane;
    return true;
  }
  return traceClosest(ray, hit);
}

bool EmbreeAccelerator::traceClosest(const Ray& ray, Hit* hit) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray.org_x = ray.o.x, rh.ray.org_y = ray.o.y, rh.ray.org_z = ray.o.z;
  rh.ray.dir_x = ray.d.x, rh.ray.dir_y = ray.d.y, rh.ray.dir_z = ray.d.z;
  rh.ray.tnear = ray.tMin;
  rh.ray.tfar = ray.tMax;
  rh.ray.time = ray.time;
  rh.ray.mask = ~0u;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  unsigned top = rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID ? rh.hit.instID[0] : rh.hit.geomID;
  hit->t = rh.ray.tfar;
  hit->instance = instanceOfGeom_[top];
  hit->prim = rh.hit.primID;
  hit->u = rh.hit.u;
  hit->v = rh.hit.v;
  return true;
}

void EmbreeAccelerator::closestHits(const Ray* rays, Hit* hits, int count) const {
  constexpr int kPacket = 16;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  // Not RTC_INTERSECT_CONTEXT_FLAG_COHERENT: Embree 3.13's coherent (frustum) traversal of
  // instances loses rays far from the origin (a pixel's packet 1e4 units out missed a card in
  // front of it for a third of its rays, 0.3% at 1e3; test
  // EmbreeShapes.PixelPacketsFarFromTheOriginFindWhatSingleRaysFind). The default context
  // still traces the 16 rays as a packet.
  if (!unbounded_.empty()) {  // rare: keep the plane logic in one place
    for (int i = 0; i < count; ++i)
      if (!closestHit(rays[i], &hits[i])) hits[i] = Hit{};
    return;
  }
  for (int first = 0; first < count; first += kPacket) {
    const int n = std::min(kPacket, count - first);
    if (n == 1) {  // a packet of one is slower than the single-ray kernel
      if (!closestHit(rays[first], &hits[first])) hits[first] = Hit{};
      continue;
    }
    alignas(64) int valid[kPacket];
    alignas(64) RTCRayHit16 rh;
    for (int i = 0; i < kPacket; ++i) {
      valid[i] = i < n ? -1 : 0;
      const Ray& ray = rays[first + std::min(i, n - 1)];
      rh.ray.org_x[i] = ray.o.x, rh.ray.org_y[i] = ray.o.y, rh.ray.org_z[i] = ray.o.z;
      rh.ray.dir_x[i] = ray.d.x, rh.ray.dir_y[i] = ray.d.y, rh.ray.dir_z[i] = ray.d.z;
      rh.ray.tnear[i] = ray.tMin;
      rh.ray.tfar[i] = ray.tMax;
      rh.ray.time[i] = ray.time;
      rh.ray.mask[i] = ~0u;
      rh.ray.id[i] = unsigned(i);
      rh.ray.flags[i] = 0;
      rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect16(valid, scene_, &context, &rh);
    for (int i = 0; i < n; ++i) {
      Hit& hit = hits[first + i];
      if (rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) {
        hit = Hit{};
        continue;
      }
      unsigned inst = rh.hit.instID[0][i];
      hit.t = rh.ray.tfar[i];
      hit.instance = instanceOfGeom_[inst != RTC_INVALID_GEOMETRY_ID ? inst : rh.hit.geomID[i]];
      hit.prim = rh.hit.primID[i];
      hit.u = rh.hit.u[i];
      hit.v = rh.hit.v[i];
      refineFarHit(rays[first + i], &hit,
                   [this](const Ray& r, Hit* h) { return traceClosest(r, h); });
    }
  }
}

bool EmbreeAccelerator::anyHit(const Ray& ray) const {
  if (!unbounded_.empty() && unbounded_.anyHit(ray)) return true;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay r;
  r.org_x = ray.o.x, r.org_y = ray.o.y, r.org_z = ray.o.z;
  r.dir_x = ray.d.x, r.dir_y = ray.d.y, r.dir_z = ray.d.z;
  r.tnear = ray.tMin;
  r.tfar = ray.tMax;
  r.time = ray.time;
  r.mask = ~0u;
  r.id = 0;
  r.flags = 0;
  rtcOccluded1(scene_, &context, &r);
  return r.tfar < 0;  // Embree sets tfar to -inf on a hit
}

}  // namespace glint
