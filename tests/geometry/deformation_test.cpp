// Deformation blur in geometry: a mesh whose vertices have time steps
// (TriangleMesh::positionSteps) is hit where the blend of its steps puts it at the ray's time,
// in every backend and composed with a moving placement; surface interactions lie on that
// surface and rays spawned from them leave it; the kd-trees agree with Embree; bounds hold
// every step; and only deforming meshes are built with time steps.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/accel/accelerator.h"
#include "geometry/accel/embree_accel.h"
#include "geometry/interaction.h"
#include "test_meshes.h"

namespace glint {
namespace {

const std::vector<std::string>& backends() {
  static const std::vector<std::string> names = acceleratorNames();
  return names;
}

// A square [-h, h]^2 in the z = 0 plane, facing +z, carried through three steps: its centre at
// (0,0,0), (2,0,0) and (2,4,0), as a deformation (the vertices move, not a placement).
TriangleMesh deformingSquare(float h) {
  TriangleMesh m;
  const std::vector<Vec3f> base = {{-h, -h, 0}, {h, -h, 0}, {h, h, 0}, {-h, h, 0}};
  m.indices = {0, 1, 2, 0, 2, 3};
  for (Vec3f c : {Vec3f{0, 0, 0}, Vec3f{2, 0, 0}, Vec3f{2, 4, 0}}) {
    std::vector<Vec3f> step;
    for (Vec3f p : base) step.push_back(p + c);
    m.positionSteps.push_back(step);
  }
  m.positions = m.positionSteps[1];
  return m;
}
Vec3f squareCentre(float t) { return t <= 0.5f ? Vec3f{4 * t, 0, 0} : Vec3f{2, 8 * (t - 0.5f), 0}; }

TEST(DeformationBlur, StepAtMapsTimeAsEmbreeDoes) {
  TriangleMesh m = deformingSquare(1);
  EXPECT_EQ(m.stepAt(0).k, 0u);
  EXPECT_EQ(m.stepAt(0).f, 0.0f);
  EXPECT_EQ(m.stepAt(0.25f).k, 0u);
  EXPECT_EQ(m.stepAt(0.25f).f, 0.5f);
  EXPECT_EQ(m.stepAt(0.5f).k, 1u);
  EXPECT_EQ(m.stepAt(0.5f).f, 0.0f);
  // The end of the shutter is the end of the last segment, not a segment of its own.
  EXPECT_EQ(m.stepAt(1).k, 1u);
  EXPECT_EQ(m.stepAt(1).f, 1.0f);
  EXPECT_EQ(m.positionAt(0, m.stepAt(1)), m.positionSteps[2][0]);
}

TEST(DeformationBlur, DeformingMeshIsHitWhereItIsAtTheRayTime) {
  GeometryScene scene;
  scene.meshes.push_back(deformingSquare(0.5f));
  scene.instances.push_back({0, Transform()});
  ASSERT_TRUE(scene.hasMotion());
  for (const std::string& name : backends()) {
    SCOPED_TRACE(name);
    auto accel = makeAccelerator(name, scene);
    for (float time : {0.0f, 0.125f, 0.375f, 0.5f, 0.625f, 1.0f}) {
      const Vec3f c = squareCentre(time);
      Ray ray{c + Vec3f{0.2f, 0.1f, 3}, {0, 0, -1}, 0, kInfinity, time};
      Hit hit;
      ASSERT_TRUE(accel->closestHit(ray, &hit)) << "time " << time;
      EXPECT_NEAR(hit.t, 3, 1e-5f);
      const SurfaceInteraction si = computeSurfaceInteraction(scene, ray, hit);
      EXPECT_NEAR(distance(si.p, c + Vec3f{0.2f, 0.1f, 0}), 0, 1e-5f) << "time " << time;
      EXPECT_NEAR(si.ng.z, 1, 1e-6f);
      // Where the square is at another time, this ray's time sees nothing.
      Ray miss{
          squareCentre(time < 0.5f ? 1.0f : 0.0f) + Vec3f{0, 0, 3}, {0, 0, -1}, 0, kInfinity, time};
      EXPECT_FALSE(accel->closestHit(miss, &hit)) << "time " << time;
      EXPECT_FALSE(accel->anyHit(miss)) << "time " << time;
      EXPECT_TRUE(accel->anyHit(ray));
    }
  }
}

TEST(DeformationBlur, NormalsAreBlendedAtTheRayTime) {
  GeometryScene scene;
  TriangleMesh m = deformingSquare(0.5f);
  // The shading normal tips from +z to +x over the first half of the shutter.
  m.normalSteps = {std::vector<Vec3f>(4, {0, 0, 1}), std::vector<Vec3f>(4, {1, 0, 0}),
                   std::vector<Vec3f>(4, {1, 0, 0})};
  m.normals = m.normalSteps[1];
  scene.meshes.push_back(m);
  scene.instances.push_back({0, Transform()});
  auto accel = makeAccelerator("embree", scene);
  const float time = 0.25f;  // half way: (0.5, 0, 0.5) normalised
  Ray ray{squareCentre(time) + Vec3f{0.1f, 0.1f, 3}, {0, 0, -1}, 0, kInfinity, time};
  Hit hit;
  ASSERT_TRUE(accel->closestHit(ray, &hit));
  const SurfaceInteraction si = computeSurfaceInteraction(scene, ray, hit);
  const float h = std::sqrt(0.5f);
  EXPECT_NEAR(si.ns.x, h, 1e-5f);
  EXPECT_NEAR(si.ns.z, h, 1e-5f);
}

// A deforming mesh placed by a moving instance: the instance's motion applies to the blended
// vertices, both at the ray's time.
TEST(DeformationBlur, ComposesWithAMovingPlacement) {
  GeometryScene scene;
  scene.meshes.push_back(deformingSquare(0.5f));
  Instance inst;
  inst.mesh = 0;
  inst.motion =
      AnimatedTransform({Transform::translate({0, 0, 0}), Transform::translate({0, 0, -2})});
  inst.worldFromObject = inst.motion.key(0);
  scene.instances.push_back(inst);
  for (const std::string& name : backends()) {
    SCOPED_TRACE(name);
    auto accel = makeAccelerator(name, scene);
    for (float time : {0.1f, 0.4f, 0.8f}) {
      const Vec3f c = squareCentre(time) + Vec3f{0, 0, -2 * time};
      Ray ray{Vec3f{c.x - 0.2f, c.y + 0.3f, 5}, {0, 0, -1}, 0, kInfinity, time};
      Hit hit;
      ASSERT_TRUE(accel->closestHit(ray, &hit)) << "time " << time;
      EXPECT_NEAR(hit.t, 5 - c.z, 1e-4f);
      const SurfaceInteraction si = computeSurfaceInteraction(scene, ray, hit);
      EXPECT_NEAR(distance(si.p, Vec3f{c.x - 0.2f, c.y + 0.3f, c.z}), 0, 1e-4f);
    }
  }
}

// An octahedron whose every step is a different affine image of the unit one: every blend of
// two steps is affine too, so the mesh stays convex at every time and a ray spawned outward
// from a hit must not hit it again.
TriangleMesh deformingOctahedron(std::mt19937& rng, float scale, int steps) {
  std::uniform_real_distribution<float> u(-1, 1);
  TriangleMesh m = test::unitOctahedron();
  const std::vector<Vec3f> base = m.positions;
  for (int k = 0; k < steps; ++k) {
    const Transform xf = Transform::scale(Vec3f{scale, scale, scale}) *
                         Transform::translate(Vec3f{u(rng), u(rng), u(rng)} * 3) *
                         Transform::rotate(60 * u(rng), {u(rng), u(rng), 1}) *
                         Transform::scale({1 + 0.4f * u(rng), 1 + 0.4f * u(rng), 1});
    std::vector<Vec3f> step;
    for (Vec3f p : base) step.push_back(xf.point(p));
    m.positionSteps.push_back(step);
  }
  m.positions = m.positionSteps[size_t(steps) / 2];
  return m;
}

TEST(DeformationBlur, InteractionsLieOnTheSurfaceAtTheRayTimeAndSpawnedRaysLeaveIt) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
  std::normal_distribution<float> g;
  for (float scale : {1e-3f, 1.0f, 1e3f}) {
    SCOPED_TRACE(scale);
    GeometryScene scene;
    scene.meshes.push_back(deformingOctahedron(rng, scale, 5));
    scene.instances.push_back({0, Transform()});
    for (const std::string& name : backends()) {
      SCOPED_TRACE(name);
      auto accel = makeAccelerator(name, scene);
      const TriangleMesh& m = scene.meshes[0];
      int hits = 0, reHits = 0;
      for (int j = 0; j < 1500; ++j) {
        const float time = u01(rng);
        const TriangleMesh::StepBlend s = m.stepAt(time);
        Vec3f centre{0, 0, 0};
        for (uint32_t v = 0; v < 6; ++v) centre += m.positionAt(v, s) / 6.0f;
        const Vec3f dir = normalize(Vec3f{g(rng), g(rng), g(rng)});
        const Vec3f aim = centre + Vec3f{u(rng), u(rng), u(rng)} * (0.2f * scale);
        Ray ray{aim - dir * (20 * scale), dir, 0, kInfinity, time};
        Hit hit;
        if (!accel->closestHit(ray, &hit)) continue;
        ++hits;
        const SurfaceInteraction si = computeSurfaceInteraction(scene, ray, hit);
        EXPECT_NEAR(distance(si.p, ray.at(hit.t)), 0, 1e-4f * scale);
        // On the plane of the blended triangle.
        const Vec3f p0 = m.positionAt(m.indices[3 * hit.prim], s);
        EXPECT_NEAR(dot(si.p - p0, si.ng), 0, 1e-5f * scale);
        Vec3f w = normalize(Vec3f{g(rng), g(rng), g(rng)});
        if (dot(w, si.ng) < 0) w = -w;
        Hit again;
        if (accel->closestHit(si.spawnRay(w, time), &again)) ++reHits;
      }
      EXPECT_GT(hits, 1000);
      EXPECT_EQ(reHits, 0);
    }
  }
}

TEST(DeformationBlur, KdTreesAgreeWithEmbree) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
  GeometryScene scene;
  // A soup of triangles, each wandering through 5 steps, single-sided; plus a static copy of
  // it placed elsewhere, which stays in the main tree.
  TriangleMesh soup;
  soup.positionSteps.resize(5);
  for (int i = 0; i < 80; ++i) {
    const Vec3f c{u(rng), u(rng), u(rng)};
    for (int k = 0; k < 3; ++k) {
      const Vec3f corner = c + Vec3f{u(rng), u(rng), u(rng)} * 0.3f;
      for (size_t s = 0; s < 5; ++s)
        soup.positionSteps[s].push_back(corner + Vec3f{u(rng), u(rng), u(rng)} * 0.4f);
      soup.indices.push_back(uint32_t(soup.positionSteps[0].size() - 1));
    }
  }
  soup.positions = soup.positionSteps[2];
  soup.singleSided = true;
  TriangleMesh still = soup;
  still.positionSteps.clear();
  scene.meshes = {soup, still};
  scene.instances.push_back({0, Transform()});
  scene.instances.push_back({1, Transform::translate({0, 0, 3})});
  auto embree = makeAccelerator("embree", scene);
  for (const char* name : {"kdtree", "kdtree-median"}) {
    SCOPED_TRACE(name);
    auto kd = makeAccelerator(name, scene);
    int hits = 0, deformingHits = 0, mismatches = 0;
    for (int i = 0; i < 4000; ++i) {
      const Vec3f o = Vec3f{u(rng), u(rng), u(rng)} * 8;
      Ray ray{o, normalize(Vec3f{u(rng), u(rng), u(rng)} * 2 + Vec3f{0, 0, 1.5f * u01(rng)} - o), 0,
              kInfinity, u01(rng)};
      Hit a, b;
      const bool fa = embree->closestHit(ray, &a), fb = kd->closestHit(ray, &b);
      if (fa != fb || embree->anyHit(ray) != kd->anyHit(ray)) {
        ++mismatches;  // an edge decided differently by the two backends' rounding
        continue;
      }
      if (!fa) continue;
      ++hits;
      deformingHits += a.instance == 0;
      EXPECT_NEAR(a.t, b.t, 1e-4f * a.t) << "ray " << i;
      if (a.instance != b.instance || a.prim != b.prim) {
        ++mismatches;
        continue;
      }
      EXPECT_NEAR(a.u, b.u, 1e-3f);
      EXPECT_NEAR(a.v, b.v, 1e-3f);
    }
    EXPECT_GT(deformingHits, 300);  // single-sided: about half the rays see a back face
    EXPECT_GT(hits, 600);
    EXPECT_LT(mismatches, 5);
  }
}

TEST(DeformationBlur, OnlyDeformingMeshesGetTimeStepsAndBoundsHoldEveryStep) {
  GeometryScene scene;
  scene.meshes.push_back(deformingSquare(0.5f));
  TriangleMesh still = deformingSquare(0.5f);
  still.positionSteps.clear();
  scene.meshes.push_back(still);
  scene.instances.push_back({0, Transform()});
  scene.instances.push_back({1, Transform::translate({0, 0, 5})});
  EmbreeAccelerator accel(scene);
  EXPECT_EQ(accel.motionGeometryCount(), 1u);
  const Bounds3f b = scene.bounds();
  EXPECT_LE(b.lower.x, -0.5f);
  EXPECT_GE(b.upper.x, 2.5f);
  EXPECT_GE(b.upper.y, 4.5f);
  // The middle step alone would not reach y = 4.5.
  EXPECT_LT(scene.meshes[0].positions[2].y, 1);
}

}  // namespace
}  // namespace glint
