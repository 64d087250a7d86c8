// Motion blur in geometry: AnimatedTransform (decomposition, keys, slerp, agreement with
// Embree's own interpolation), moving spheres, meshes and planes hit where they are at the
// ray's time in every backend, surface interactions at that time, conservative per-key bounds,
// and static scenes left exactly as they were.
#include "geometry/motion.h"

#include <embree3/rtcore.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/accel/accelerator.h"
#include "geometry/accel/embree_accel.h"
#include "geometry/accel/kdtree.h"
#include "geometry/interaction.h"
#include "geometry/shapes/box.h"
#include "geometry/shapes/plane.h"
#include "geometry/shapes/sphere.h"
#include "test_meshes.h"

namespace glint {
namespace {

// ---- helpers ---------------------------------------------------------------------------------

Transform shear(float xy, float xz, float yz) {
  Mat4 m;
  m.m[0][1] = xy, m.m[0][2] = xz, m.m[1][2] = yz;
  return Transform(m);
}

float maxDifference(const Transform& a, const Transform& b) {
  float d = 0;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) d = std::max(d, std::abs(a.matrix().m[r][c] - b.matrix().m[r][c]));
  return d;
}

Instance movingMesh(uint32_t mesh, std::vector<Transform> keys) {
  Instance inst;
  inst.mesh = mesh;
  inst.motion = AnimatedTransform(std::move(keys));
  inst.worldFromObject = inst.motion.key(0);
  return inst;
}

void addShape(GeometryScene* scene, std::unique_ptr<Shape> shape, std::vector<Transform> keys) {
  Instance inst;
  inst.shape = uint32_t(scene->shapes.size());
  inst.motion = AnimatedTransform(std::move(keys));
  inst.worldFromObject = inst.motion.key(0);
  scene->shapes.push_back(std::move(shape));
  scene->instances.push_back(inst);
}

// A square [-h, h]^2 in the z = 0 plane, facing +z (two triangles).
TriangleMesh square(float h) {
  TriangleMesh m;
  m.positions = {{-h, -h, 0}, {h, -h, 0}, {h, h, 0}, {-h, h, 0}};
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

// Keys of a translation through three points: (0,0,0) at t = 0, (2,0,0) at t = 0.5 (an
// interior key), (2,4,0) at t = 1. Between keys the motion is linear.
std::vector<Transform> threeKeyPath() {
  return {Transform::translate({0, 0, 0}), Transform::translate({2, 0, 0}),
          Transform::translate({2, 4, 0})};
}
Vec3f threeKeyPosition(float t) {
  return t <= 0.5f ? Vec3f{4 * t, 0, 0} : Vec3f{2, 8 * (t - 0.5f), 0};
}

const std::vector<std::string>& backends() {
  static const std::vector<std::string> names = acceleratorNames();
  return names;
}

// ---- AnimatedTransform -----------------------------------------------------------------------

TEST(AnimatedTransform, DecompositionRoundTripsShearAndReflection) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1, 1);
  for (int i = 0; i < 200; ++i) {
    const bool reflect = i % 2 == 1;
    Transform xf =
        Transform::translate(Vec3f{u(rng), u(rng), u(rng)} * 10) *
        Transform::rotate(180 * u(rng), {u(rng), u(rng), u(rng) + 2}) *
        shear(0.5f * u(rng), 0.5f * u(rng), 0.5f * u(rng)) *
        Transform::scale({1.5f + u(rng), 1.5f + u(rng), (reflect ? -1 : 1) * (1.5f + u(rng))});
    DecomposedTransform d = DecomposedTransform::fromTransform(xf);
    EXPECT_LT(maxDifference(d.toTransform(), xf), 2e-5f) << i;
    const Quaternion& q = d.rotation;
    EXPECT_NEAR(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w, 1, 1e-6f);
    // A reflection lives in U (negative sz); R stays a proper rotation.
    EXPECT_EQ(d.u[2][2] < 0, reflect) << i;
    EXPECT_GT(d.u[0][0], 0);
    EXPECT_GT(d.u[1][1], 0);
  }
}

TEST(AnimatedTransform, EndsAreTheFirstAndLastKeysExactly) {
  std::vector<Transform> keys = {Transform::rotate(10, {1, 2, 3}) * Transform::scale({1, 2, 3}),
                                 Transform::translate({1, 2, 3}) * Transform::rotate(70, {0, 1, 0}),
                                 Transform::translate({-4, 0, 1}) * shear(0.3f, 0, 0.1f)};
  AnimatedTransform motion(keys);
  ASSERT_TRUE(motion.isAnimated());
  EXPECT_EQ(motion.at(0), keys[0]);
  EXPECT_EQ(motion.at(1), keys[2]);
  // Outside the shutter the ends hold.
  EXPECT_EQ(motion.at(-0.5f), keys[0]);
  EXPECT_EQ(motion.at(1.5f), keys[2]);
}

TEST(AnimatedTransform, InteriorKeyTimesReturnThoseKeysExactly) {
  std::vector<Transform> keys;
  for (int k = 0; k < 5; ++k)
    keys.push_back(Transform::translate({float(k), float(k * k), 0}) *
                   Transform::rotate(40.0f * float(k), {1, 1, 0}));
  AnimatedTransform motion(keys);
  EXPECT_EQ(motion.at(0.25f), keys[1]);
  EXPECT_EQ(motion.at(0.5f), keys[2]);
  EXPECT_EQ(motion.at(0.75f), keys[3]);
  // In between it is neither neighbour.
  EXPECT_GT(maxDifference(motion.at(0.3f), keys[1]), 0.1f);
}

TEST(AnimatedTransform, SlerpMidpointOfAQuarterTurnKeepsUnitDistance) {
  AnimatedTransform motion({Transform(), Transform::rotate(90, {0, 0, 1})});
  const Vec3f p = motion.at(0.5f).point({1, 0, 0});
  EXPECT_NEAR(length(p), 1, 1e-6f);  // the blend of the two matrices would give 0.707
  EXPECT_NEAR(p.x, std::sqrt(0.5f), 1e-6f);
  EXPECT_NEAR(p.y, std::sqrt(0.5f), 1e-6f);
  // Uniform angular speed: a quarter of the way is 22.5 degrees.
  const Vec3f q = motion.at(0.25f).point({1, 0, 0});
  EXPECT_NEAR(std::atan2(q.y, q.x), kPi / 8, 2e-6f);
  EXPECT_NEAR(length(q), 1, 1e-6f);
}

TEST(AnimatedTransform, IdenticalKeysCollapseToStatic) {
  const Transform xf = Transform::translate({1, 2, 3}) * Transform::rotate(33, {1, 0, 1});
  AnimatedTransform motion({xf, xf, xf});
  EXPECT_FALSE(motion.isAnimated());
  EXPECT_EQ(motion.keyCount(), 1u);
  EXPECT_EQ(motion.at(0.4f), xf);
  EXPECT_FALSE(AnimatedTransform().isAnimated());
}

// Our transform at a time must be the one Embree intersected, to within the bound
// interpolationMismatch() states: Embree's slerp uses an approximate acos (error ~1e-6 rad),
// which a libm acos would miss by far more than rounding, and nearly parallel keys amplify
// rounding differences. 2000 random key sets, with 3 keys each.
TEST(AnimatedTransform, AgreesWithEmbreesInterpolation) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
  RTCDevice device = rtcNewDevice(nullptr);
  RTCScene empty = rtcNewScene(device);
  rtcCommitScene(empty);
  float worst = 0;
  for (int i = 0; i < 2000; ++i) {
    std::vector<Transform> keys;
    for (int k = 0; k < 3; ++k) {
      // One draw per statement or braced list: function arguments and the operands of * are
      // evaluated in an unspecified order (GCC and Clang differ), which would give each
      // compiler different keys.
      const Vec3f t = Vec3f{u(rng), u(rng), u(rng)} * 3;
      const float angle = 150 * u(rng);
      Vec3f axis{u(rng), u(rng), u(rng)};
      axis.z += 2;
      const Vec3f skew = Vec3f{u(rng), u(rng), u(rng)} * 0.3f;
      const Vec3f s = Vec3f{u(rng), u(rng), u(rng)} + Vec3f{1.5f, 1.5f, 1.5f};
      keys.push_back(Transform::translate(t) * Transform::rotate(angle, axis) *
                     shear(skew.x, skew.y, skew.z) * Transform::scale(s));
    }
    AnimatedTransform motion(keys);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(geom, empty);
    rtcSetGeometryTimeStepCount(geom, 3);
    for (unsigned k = 0; k < 3; ++k) {
      const DecomposedTransform& d = motion.decomposedKey(k);
      RTCQuaternionDecomposition qd;
      rtcInitQuaternionDecomposition(&qd);
      rtcQuaternionDecompositionSetScale(&qd, d.u[0][0], d.u[1][1], d.u[2][2]);
      rtcQuaternionDecompositionSetSkew(&qd, d.u[0][1], d.u[0][2], d.u[1][2]);
      rtcQuaternionDecompositionSetQuaternion(&qd, d.rotation.w, d.rotation.x, d.rotation.y,
                                              d.rotation.z);
      rtcQuaternionDecompositionSetTranslation(&qd, d.translation.x, d.translation.y,
                                               d.translation.z);
      rtcSetGeometryTransformQuaternion(geom, k, &qd);
    }
    rtcCommitGeometry(geom);
    for (int j = 0; j < 20; ++j) {
      const float time = u01(rng);
      float m[12];  // 3x4 column-major
      rtcGetGeometryTransform(geom, time, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m);
      const Transform ours = motion.at(time);
      // Relative to the largest linear entry (the scale at which the rotation was computed);
      // translations also relative to their own size.
      const auto& a = ours.matrix().m;
      float entry = 0;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) entry = std::max(entry, std::abs(a[r][c]));
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 3; ++r) {
          const float size = c == 3 ? entry + std::abs(a[r][3]) : entry;
          worst = std::max(
              worst, std::abs(m[c * 3 + r] - a[r][c]) / size / motion.interpolationMismatch(time));
        }
    }
    rtcReleaseGeometry(geom);
  }
  rtcReleaseScene(empty);
  rtcReleaseDevice(device);
  // The bound the spawn offsets of moving meshes rely on holds with a margin of 2 (measured:
  // about 3 over 20000 key sets, many of them between nearly parallel rotations).
  EXPECT_LT(worst, 0.5f);
}

// ---- per-key bounds --------------------------------------------------------------------------

TEST(MotionKeyBounds, BlendOfNeighbouringKeysContainsTheShapeAtEveryTime) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> u(-1, 1);
  const Bounds3f box{{-0.3f, -0.2f, -0.1f}, {0.4f, 0.2f, 0.3f}};
  for (int i = 0; i < 20; ++i) {
    std::vector<Transform> keys;
    const int n = 2 + i % 3;
    for (int k = 0; k < n; ++k)
      keys.push_back(Transform::translate(Vec3f{u(rng), u(rng), u(rng)} * 2) *
                     Transform::rotate(170 * u(rng), {u(rng), u(rng), 1}) *
                     Transform::translate({2, 0, 0}) *  // far from the pivot: a wide arc
                     Transform::scale({1 + 0.5f * u(rng), 1, 1 + 0.5f * u(rng)}));
    AnimatedTransform motion(keys);
    std::vector<Bounds3f> kb = motionKeyBounds(box, motion);
    ASSERT_EQ(kb.size(), motion.keyCount());
    const int segments = n - 1;
    for (int j = 0; j <= 2000; ++j) {
      const float time = float(j) / 2000;
      const float s = time * float(segments);
      const int k = std::min(int(s), segments - 1);
      const float f = s - float(k);
      const Bounds3f placed = motion.at(time).bounds(box);
      for (int a = 0; a < 3; ++a) {
        EXPECT_LE((1 - f) * kb[k].lower[a] + f * kb[k + 1].lower[a], placed.lower[a]);
        EXPECT_GE((1 - f) * kb[k].upper[a] + f * kb[k + 1].upper[a], placed.upper[a]);
      }
    }
  }
}

// ---- moving objects in every backend ---------------------------------------------------------

TEST(MotionBlur, MovingSphereIsHitWhereItIsAtTheRayTime) {
  GeometryScene scene;
  addShape(&scene, std::make_unique<Sphere>(Vec3f{0, 0, 0}, 1.0f), threeKeyPath());
  for (const std::string& name : backends()) {
    SCOPED_TRACE(name);
    auto accel = makeAccelerator(name, scene);
    for (float time : {0.0f, 0.25f, 0.5f, 0.75f, 0.9f, 1.0f}) {
      const Vec3f c = threeKeyPosition(time);
      // Straight down onto the top, and off-centre (hit at height 0.8, normal (0.6, 0, 0.8)).
      for (float dx : {0.0f, 0.6f}) {
        Ray ray{c + Vec3f{dx, 0, 10}, {0, 0, -1}, 0, kInfinity, time};
        Hit hit;
        ASSERT_TRUE(accel->closestHit(ray, &hit)) << "time " << time;
        const float z = std::sqrt(1 - dx * dx);
        EXPECT_NEAR(hit.t, 10 - z, 2e-5f) << "time " << time;
        EXPECT_TRUE(accel->anyHit(ray));
        SurfaceInteraction si = computeSurfaceInteraction(scene, ray, hit);
        EXPECT_NEAR(distance(si.p, c + Vec3f{dx, 0, z}), 0, 2e-5f) << "time " << time;
        EXPECT_NEAR(dot(si.ng, Vec3f{dx, 0, z}), 1, 1e-5f) << "time " << time;
        EXPECT_TRUE(si.frontFace);
      }
      // Where the sphere is at another time, this time's ray misses.
      const Vec3f elsewhere = threeKeyPosition(time < 0.5f ? 1.0f : 0.0f);
      Ray miss{elsewhere + Vec3f{0, 0, 10}, {0, 0, -1}, 0, kInfinity, time};
      Hit hit;
      EXPECT_FALSE(accel->closestHit(miss, &hit)) << "time " << time;
      EXPECT_FALSE(accel->anyHit(miss)) << "time " << time;
    }
  }
}

TEST(MotionBlur, MovingTriangleMeshIsHitWhereItIsAtTheRayTime) {
  GeometryScene scene;
  scene.meshes.push_back(square(0.5f));
  // Placed once, moving: not baked; worldFromObject is the first key.
  scene.instances.push_back(movingMesh(0, threeKeyPath()));
  for (const std::string& name : backends()) {
    SCOPED_TRACE(name);
    auto accel = makeAccelerator(name, scene);
    for (float time : {0.0f, 0.125f, 0.5f, 0.625f, 1.0f}) {
      const Vec3f c = threeKeyPosition(time);
      Ray ray{c + Vec3f{0.2f, 0.1f, 3}, {0, 0, -1}, 0, kInfinity, time};
      Hit hit;
      ASSERT_TRUE(accel->closestHit(ray, &hit)) << "time " << time;
      EXPECT_EQ(hit.instance, 0u);
      EXPECT_NEAR(hit.t, 3, 1e-5f);
      SurfaceInteraction si = computeSurfaceInteraction(scene, ray, hit);
      EXPECT_NEAR(distance(si.p, c + Vec3f{0.2f, 0.1f, 0}), 0, 1e-5f) << "time " << time;
      EXPECT_NEAR(si.ng.z, 1, 1e-6f);
      // The object-space point is the same at every time: barycentrics do not move.
      const Vec3f pObj =
          (1 - hit.u - hit.v) * scene.meshes[0].positions[scene.meshes[0].indices[3 * hit.prim]] +
          hit.u * scene.meshes[0].positions[scene.meshes[0].indices[3 * hit.prim + 1]] +
          hit.v * scene.meshes[0].positions[scene.meshes[0].indices[3 * hit.prim + 2]];
      EXPECT_NEAR(distance(pObj, Vec3f{0.2f, 0.1f, 0}), 0, 1e-5f);
      Ray miss{threeKeyPosition(time < 0.5f ? 1.0f : 0.0f) + Vec3f{0, 0, 3},
               {0, 0, -1},
               0,
               kInfinity,
               time};
      EXPECT_FALSE(accel->closestHit(miss, &hit)) << "time " << time;
      EXPECT_FALSE(accel->anyHit(miss));
    }
  }
}

// Half way through a quarter turn about z, an object 2 units from the pivot is at 45 degrees,
// 2 units out: where slerp puts it, not where the blend of the two matrices would (1.41 out).
TEST(MotionBlur, RotatingInstanceAtHalfShutterIsWhereSlerpPutsIt) {
  GeometryScene scene;
  TriangleMesh m = square(0.2f);
  for (Vec3f& p : m.positions) p.x += 2;
  scene.meshes.push_back(m);
  const std::vector<Transform> turn = {Transform(), Transform::rotate(90, {0, 0, 1})};
  scene.instances.push_back(movingMesh(0, turn));
  addShape(&scene, std::make_unique<Sphere>(Vec3f{0, 2, 0}, 0.2f), turn);  // 90 degrees ahead
  const float r = std::sqrt(2.0f);
  for (const std::string& name : backends()) {
    SCOPED_TRACE(name);
    auto accel = makeAccelerator(name, scene);
    Hit hit;
    Ray onMesh{{r, r, 5}, {0, 0, -1}, 0, kInfinity, 0.5f};
    ASSERT_TRUE(accel->closestHit(onMesh, &hit));
    EXPECT_EQ(hit.instance, 0u);
    EXPECT_NEAR(hit.t, 5, 1e-5f);
    Ray onSphere{{-r, r, 5}, {0, 0, -1}, 0, kInfinity, 0.5f};
    ASSERT_TRUE(accel->closestHit(onSphere, &hit));
    EXPECT_EQ(hit.instance, 1u);
    EXPECT_NEAR(hit.t, 4.8f, 1e-5f);
    SurfaceInteraction si = computeSurfaceInteraction(scene, onSphere, hit);
    EXPECT_NEAR(distance(si.p, Vec3f{-r, r, 0.2f}), 0, 1e-5f);
    // The shrunken positions of a matrix blend are empty.
    Ray lerped{{1, 1, 5}, {0, 0, -1}, 0, kInfinity, 0.5f};
    EXPECT_FALSE(accel->closestHit(lerped, &hit));
    Ray lerpedSphere{{-1, 1, 5}, {0, 0, -1}, 0, kInfinity, 0.5f};
    EXPECT_FALSE(accel->closestHit(lerpedSphere, &hit));
  }
}

// A square turning a quarter turn about y: at t = 0.5 its normal is tilted by 45 degrees, and
// the interaction's normal is that of the transform at the ray's time.
TEST(MotionBlur, NormalsFollowTheTransformAtTheRayTime) {
  GeometryScene scene;
  scene.meshes.push_back(square(1));
  scene.instances.push_back(
      movingMesh(0, {Transform::translate({0, 0, 0}), Transform::rotate(90, {0, 1, 0})}));
  auto accel = makeAccelerator("embree", scene);
  for (float time : {0.0f, 0.3f, 0.5f, 0.8f}) {
    const float angle = 0.5f * kPi * time;
    const Vec3f n{std::sin(angle), 0, std::cos(angle)};
    Ray ray{n * 5, -n, 0, kInfinity, time};
    Hit hit;
    ASSERT_TRUE(accel->closestHit(ray, &hit)) << time;
    EXPECT_NEAR(hit.t, 5, 1e-5f);
    SurfaceInteraction si = computeSurfaceInteraction(scene, ray, hit);
    EXPECT_NEAR(dot(si.ng, n), 1, 1e-6f) << time;
    EXPECT_NEAR(length(si.p), 0, 1e-5f) << time;
  }
}

// Random rays at random times against moving, turning, scaled spheres, boxes and meshes: the
// interaction lies on the surface as placed at the ray's time (object space: on the unit
// sphere), and rays spawned from it at that time never re-hit it.
TEST(MotionBlur, InteractionsLieOnTheSurfaceAtTheRayTimeAndSpawnedRaysLeaveIt) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
  std::normal_distribution<float> g;
  for (float scale : {1e-3f, 1.0f, 1e3f}) {
    SCOPED_TRACE(scale);
    GeometryScene scene;
    scene.meshes.push_back(test::unitOctahedron());
    std::vector<std::vector<Transform>> paths;
    for (int i = 0; i < 6; ++i) {
      std::vector<Transform> keys;
      for (int k = 0; k < 3; ++k)
        keys.push_back(Transform::scale(Vec3f{scale, scale, scale}) *
                       Transform::translate(Vec3f{u(rng), u(rng), u(rng)} * 4) *
                       Transform::rotate(120 * u(rng), {u(rng), u(rng), 1}) *
                       Transform::scale({1 + 0.3f * u(rng), 1 + 0.3f * u(rng), 1}));
      paths.push_back(keys);
    }
    for (int i = 0; i < 6; ++i) {
      if (i % 3 == 0) scene.instances.push_back(movingMesh(0, paths[i]));
      if (i % 3 == 1) addShape(&scene, std::make_unique<Sphere>(Vec3f{0, 0, 0}, 1.0f), paths[i]);
      if (i % 3 == 2)
        addShape(&scene, std::make_unique<Box>(Vec3f{-1, -1, -1}, Vec3f{1, 1, 1}), paths[i]);
    }
    auto accel = makeAccelerator("embree", scene);
    int hits = 0, reHits = 0;
    for (int j = 0; j < 3000; ++j) {
      const float time = u01(rng);
      const uint32_t target = uint32_t(j % scene.instances.size());
      const Transform xf = scene.instances[target].worldFromObjectAt(time);
      const Vec3f aim = xf.point(Vec3f{u(rng), u(rng), u(rng)} * 0.5f);
      const Vec3f dir = normalize(Vec3f{g(rng), g(rng), g(rng)});
      Ray ray{aim - dir * (20 * scale), dir, 0, kInfinity, time};
      Hit hit;
      if (!accel->closestHit(ray, &hit)) continue;
      ++hits;
      SurfaceInteraction si = computeSurfaceInteraction(scene, ray, hit);
      const Instance& inst = scene.instances[hit.instance];
      const Transform at = inst.worldFromObjectAt(time);
      EXPECT_NEAR(distance(si.p, ray.at(hit.t)), 0, 1e-4f * scale);
      const Vec3f pObj = at.inverse().point(si.p);
      if (inst.isShape() && dynamic_cast<const Sphere*>(scene.shapes[inst.shape].get())) {
        EXPECT_NEAR(length(pObj), 1, 1e-4f);
      }
      if (inst.isShape() && dynamic_cast<const Box*>(scene.shapes[inst.shape].get())) {
        EXPECT_NEAR(std::max({std::abs(pObj.x), std::abs(pObj.y), std::abs(pObj.z)}), 1, 1e-4f);
      }
      Vec3f w = normalize(Vec3f{g(rng), g(rng), g(rng)});
      if (dot(w, si.ng) < 0) w = -w;
      // Only the object itself could be re-hit from its outside: a convex solid.
      Hit again;
      if (accel->closestHit(si.spawnRay(w, time), &again) && again.instance == hit.instance)
        ++reHits;
    }
    EXPECT_GT(hits, 1500);
    EXPECT_EQ(reHits, 0);
  }
}

TEST(MotionBlur, MovingInfinitePlaneIsPlacedAtTheRayTime) {
  GeometryScene scene;
  addShape(&scene, std::make_unique<Plane>(Vec3f{0, 0, 0}, Vec3f{0, 1, 0}, 1.0f),
           {Transform::translate({0, 0, 0}), Transform::translate({0, 2, 0})});
  for (const std::string& name : backends()) {
    SCOPED_TRACE(name);
    auto accel = makeAccelerator(name, scene);
    for (float time : {0.0f, 0.5f, 1.0f}) {
      Ray ray{{0.3f, 10, 0.7f}, {0, -1, 0}, 0, kInfinity, time};
      Hit hit;
      ASSERT_TRUE(accel->closestHit(ray, &hit));
      EXPECT_NEAR(hit.t, 10 - 2 * time, 1e-5f);
      SurfaceInteraction si = computeSurfaceInteraction(scene, ray, hit);
      EXPECT_NEAR(si.p.y, 2 * time, 1e-5f);
      // A shadow ray that ends just above the plane at this time is not blocked.
      Ray shadow{{0.3f, 10, 0.7f}, {0, -1, 0}, 0, 10 - 2 * time - 0.01f, time};
      EXPECT_FALSE(accel->anyHit(shadow));
      shadow.tMax = 10 - 2 * time + 0.01f;
      EXPECT_TRUE(accel->anyHit(shadow));
    }
  }
}

// ---- backends agree --------------------------------------------------------------------------

GeometryScene randomMovingScene(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1, 1);
  GeometryScene scene;
  TriangleMesh soup;
  for (int i = 0; i < 60; ++i) {
    Vec3f c{u(rng), u(rng), u(rng)};
    for (int k = 0; k < 3; ++k) {
      soup.positions.push_back(c + Vec3f{u(rng), u(rng), u(rng)} * 0.3f);
      soup.indices.push_back(uint32_t(soup.positions.size() - 1));
    }
  }
  scene.meshes.push_back(soup);
  auto keys = [&](int n) {
    std::vector<Transform> k;
    for (int i = 0; i < n; ++i)
      k.push_back(Transform::translate(Vec3f{u(rng), u(rng), u(rng)} * 3) *
                  Transform::rotate(100 * u(rng), {u(rng), u(rng), 1}) *
                  Transform::scale({1 + 0.3f * u(rng), 1 + 0.3f * u(rng), 1 + 0.3f * u(rng)}));
    return k;
  };
  scene.instances.push_back({0, Transform::translate({0, 0, 2})});  // static
  scene.instances.push_back(movingMesh(0, keys(2)));
  scene.instances.push_back(movingMesh(0, keys(4)));
  for (int i = 0; i < 8; ++i) {
    if (i % 2)
      addShape(&scene, std::make_unique<Sphere>(Vec3f{0, 0, 0}, 0.5f), keys(2 + i % 3));
    else
      addShape(&scene, std::make_unique<Box>(Vec3f{-0.3f, -0.4f, -0.5f}, Vec3f{0.3f, 0.4f, 0.5f}),
               i % 4 == 0 ? std::vector<Transform>{Transform::translate({u(rng), u(rng), u(rng)})}
                          : keys(3));
  }
  addShape(&scene, std::make_unique<Plane>(Vec3f{0, -4, 0}, Vec3f{0, 1, 0}, 1.0f),
           {Transform(), Transform::rotate(15, {1, 0, 0})});
  return scene;
}

TEST(MotionBlur, KdTreesAgreeWithEmbreeOnMovingScenes) {
  std::mt19937 rng(99);
  std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
  GeometryScene scene = randomMovingScene(rng);
  auto embree = makeAccelerator("embree", scene);
  for (const char* name : {"kdtree", "kdtree-median"}) {
    SCOPED_TRACE(name);
    auto kd = makeAccelerator(name, scene);
    int hits = 0, mismatches = 0;
    for (int i = 0; i < 4000; ++i) {
      Vec3f o = Vec3f{u(rng), u(rng), u(rng)} * 8;
      Ray ray{o, normalize(Vec3f{u(rng), u(rng), u(rng)} * 3 - o), 0, kInfinity, u01(rng)};
      Hit a, b;
      const bool fa = embree->closestHit(ray, &a), fb = kd->closestHit(ray, &b);
      // A ray grazing an edge or a silhouette may be decided differently by the two
      // backends' rounding, and only that.
      if (fa != fb || embree->anyHit(ray) != kd->anyHit(ray)) {
        ++mismatches;
        continue;
      }
      if (!fa) continue;
      ++hits;
      // Ties between overlapping objects may go either way; the distance may not.
      EXPECT_NEAR(a.t, b.t, 1e-4f * a.t) << "ray " << i;
      if (a.instance != b.instance || a.prim != b.prim) {
        ++mismatches;
        continue;
      }
      EXPECT_NEAR(a.u, b.u, 1e-3f);
      EXPECT_NEAR(a.v, b.v, 1e-3f);
    }
    EXPECT_GT(hits, 2000);
    EXPECT_LT(mismatches, 5);
  }
}

TEST(MotionBlur, PacketsAgreeWithSingleRaysOnMovingScenes) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
  GeometryScene scene = randomMovingScene(rng);
  scene.instances.pop_back();  // without the plane, packets go through rtcIntersect16
  auto accel = makeAccelerator("embree", scene);
  int hits = 0;
  for (int p = 0; p < 200; ++p) {
    Ray rays[16];
    Hit packet[16];
    const Vec3f o = Vec3f{u(rng), u(rng), u(rng)} * 8;
    for (Ray& r : rays)
      r = {o, normalize(Vec3f{u(rng), u(rng), u(rng)} * 3 - o), 0, kInfinity, u01(rng)};
    accel->closestHits(rays, packet, 16);
    for (int i = 0; i < 16; ++i) {
      Hit single;
      const bool found = accel->closestHit(rays[i], &single);
      ASSERT_EQ(found, packet[i].instance != Hit::kInvalid);
      if (!found) continue;
      ++hits;
      EXPECT_EQ(single.instance, packet[i].instance);
      EXPECT_NEAR(single.t, packet[i].t, 1e-5f * single.t);
    }
  }
  EXPECT_GT(hits, 500);
}

// ---- static scenes stay as they were ---------------------------------------------------------

TEST(MotionBlur, StaticObjectsAreNotBuiltWithTimeSteps) {
  GeometryScene scene;
  scene.meshes.push_back(square(1));
  scene.instances.push_back({0, Transform()});                      // baked
  scene.instances.push_back({0, Transform::translate({3, 0, 0})});  // instanced
  addShape(&scene, std::make_unique<Sphere>(Vec3f{0, 0, 0}, 1.0f),
           {Transform::translate({0, 3, 0})});
  // Keys that are all the same are no motion either.
  addShape(&scene, std::make_unique<Sphere>(Vec3f{0, 0, 0}, 1.0f),
           {Transform::translate({0, 6, 0}), Transform::translate({0, 6, 0})});
  EXPECT_FALSE(scene.hasMotion());
  {
    EmbreeAccelerator accel(scene);
    EXPECT_EQ(accel.motionGeometryCount(), 0u);
  }
  // One moving sphere and one moving mesh placement: two geometries with time steps, no more.
  addShape(&scene, std::make_unique<Sphere>(Vec3f{0, 0, 0}, 1.0f), threeKeyPath());
  scene.instances.push_back(movingMesh(0, threeKeyPath()));
  EXPECT_TRUE(scene.hasMotion());
  EmbreeAccelerator accel(scene);
  EXPECT_EQ(accel.motionGeometryCount(), 2u);
}

// Without motion the ray time changes nothing, in every backend: the same hits bit for bit.
TEST(MotionBlur, StaticSceneGivesTheSameHitsAtEveryTime) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
  GeometryScene scene = randomMovingScene(rng);
  for (Instance& inst : scene.instances) inst.motion = AnimatedTransform(inst.worldFromObject);
  ASSERT_FALSE(scene.hasMotion());
  for (const std::string& name : backends()) {
    SCOPED_TRACE(name);
    auto accel = makeAccelerator(name, scene);
    for (int i = 0; i < 1000; ++i) {
      Vec3f o = Vec3f{u(rng), u(rng), u(rng)} * 8;
      Ray ray{o, normalize(Vec3f{u(rng), u(rng), u(rng)} * 3 - o)};
      Ray later = ray;
      later.time = u01(rng);
      Hit a, b;
      ASSERT_EQ(accel->closestHit(ray, &a), accel->closestHit(later, &b));
      EXPECT_EQ(a.t, b.t);
      EXPECT_EQ(a.instance, b.instance);
      EXPECT_EQ(a.prim, b.prim);
      EXPECT_EQ(a.u, b.u);
    }
  }
}

TEST(MotionBlur, SceneBoundsHoldTheWholeSweep) {
  GeometryScene scene;
  scene.meshes.push_back(square(0.5f));
  scene.instances.push_back(movingMesh(0, threeKeyPath()));
  addShape(&scene, std::make_unique<Sphere>(Vec3f{0, 0, 0}, 1.0f),
           {Transform::translate({0, 0, 0}), Transform::translate({0, 0, -5})});
  const Bounds3f b = scene.bounds();
  EXPECT_LE(b.lower.x, -0.5f);
  EXPECT_GE(b.upper.x, 2.5f);
  EXPECT_GE(b.upper.y, 4.5f);
  EXPECT_LE(b.lower.z, -6.0f);
  EXPECT_GE(b.upper.z, 1.0f);
}

}  // namespace
}  // namespace glint

namespace glint {
namespace {

// The interpolated transform's inverse is built from its factors (U^-1 R^T T^-1), not by a
// general inversion: it must still invert the matrix, shear, reflection and all.
TEST(AnimatedTransform, InterpolatedInverseInvertsTheMatrix) {
  Mat4 shear;
  shear.m[0][1] = 0.7f, shear.m[1][2] = -0.4f, shear.m[0][2] = 0.25f;
  Transform a = Transform::translate({1, -2, 3}) * Transform::rotate(30, {1, 2, 3}) *
                Transform(shear) * Transform::scale({2, 0.5f, -1.5f});
  Transform b = Transform::translate({-4, 0, 1}) * Transform::rotate(130, {0, 1, 1}) *
                Transform::scale({0.25f, 3, 1});
  AnimatedTransform motion({a, b});
  for (float t : {0.1f, 0.37f, 0.5f, 0.9f}) {
    Transform xf = motion.at(t);
    Mat4 product = xf.matrix() * xf.inverseMatrix();
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c)
        EXPECT_NEAR(product.m[r][c], r == c ? 1.0f : 0.0f, 2e-5f)
            << "t " << t << " [" << r << "][" << c << "]";
  }
}

}  // namespace
}  // namespace glint
