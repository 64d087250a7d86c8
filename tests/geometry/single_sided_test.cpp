// Single-sided meshes (TriangleMesh::singleSided, glTF doubleSided false): every backend hides
// back faces from every query (closest hit, any hit, packets), for meshes attached directly,
// instanced under rotations and mirrors, and moving; and the front is the object-space
// winding's side carried by the placement, so a mirror keeps the outside outside.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "geometry/accel/accelerator.h"
#include "geometry/mesh.h"

namespace glint {
namespace {

const char* const kBackends[] = {"embree", "kdtree", "kdtree-median"};

// A unit square in the object's z = 0 plane, wound counter-clockwise seen from +z: its front
// faces +z.
TriangleMesh square(bool singleSided) {
  TriangleMesh m;
  m.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  m.indices = {0, 1, 2, 0, 2, 3};
  m.singleSided = singleSided;
  return m;
}

// The placements tried; the object's +z (its front) goes where frontOf says.
struct Placement {
  std::string name;
  Transform xf;
};

std::vector<Placement> placements() {
  const Transform rot = Transform::rotate(90, {0, 1, 0});  // +z -> +x
  const Transform mirrorX = Transform::scale({-1, 1, 1});
  return {
      {"identity", Transform()},
      {"rotated", rot},
      // A mirror in the square's own plane: the world-space winding turns over, the front
      // (the normal carried as a normal) does not.
      {"mirrored then rotated", rot * mirrorX},
      // A mirror across the square's plane: the front turns with it.
      {"mirrored across", Transform::scale({1, 1, -1})},
      {"scaled, mirrored, rotated, moved", Transform::translate({0.25f, -0.5f, 0.125f}) *
                                               Transform::rotate(30, {0, 0, 1}) * rot *
                                               Transform::scale({2, 0.5f, -3})},
  };
}

// The front of placement p: the object normal +z carried by the inverse transpose.
Vec3f frontOf(const Placement& p) { return normalize(p.xf.normal({0, 0, 1})); }

// Rays at the square's centre from both sides; `count` copies of the mesh placed (1: attached
// directly by Embree; 2: instanced).
struct Case {
  GeometryScene scene;
  Vec3f centre, front;
};

Case makeCase(const Placement& p, bool singleSided, int copies, bool moving) {
  Case c;
  c.scene.meshes.push_back(square(singleSided));
  for (int i = 0; i < copies; ++i) {
    // Copies after the first sit far away: the rays only ever reach the first.
    const Transform xf = i == 0 ? p.xf : Transform::translate({100.0f * float(i), 0, 0}) * p.xf;
    Instance inst{0, xf};
    if (moving && i == 0)  // a motion that keeps the square where it is, with two keys
      inst.motion = AnimatedTransform({xf, xf * Transform::rotate(0.001f, {0, 0, 1})});
    c.scene.instances.push_back(inst);
  }
  c.centre = p.xf.point({0, 0, 0});
  c.front = frontOf(p);
  return c;
}

Ray rayTowards(Vec3f centre, Vec3f from) {
  // Slightly oblique, so no backend sees an axis-aligned special case only.
  Vec3f o = centre + 4.0f * from + Vec3f{0.01f, 0.02f, 0.015f};
  return Ray{o, normalize(centre - o), 0, kInfinity, 0.5f};
}

TEST(SingleSided, BackFacesAreInvisibleToEveryQueryOfEveryBackend) {
  for (const Placement& p : placements()) {
    for (int copies : {1, 2}) {
      for (bool moving : {false, true}) {
        for (bool singleSided : {false, true}) {
          Case c = makeCase(p, singleSided, copies, moving);
          for (const char* backend : kBackends) {
            SCOPED_TRACE(p.name + ", " + std::to_string(copies) + " copies, " +
                         (moving ? "moving, " : "static, ") +
                         (singleSided ? "single-sided, " : "double-sided, ") + backend);
            auto accel = makeAccelerator(backend, c.scene);
            const Ray fromFront = rayTowards(c.centre, c.front);
            const Ray fromBack = rayTowards(c.centre, -c.front);
            Hit h;
            EXPECT_TRUE(accel->closestHit(fromFront, &h));
            EXPECT_EQ(h.instance, 0u);
            EXPECT_TRUE(accel->anyHit(fromFront));
            EXPECT_EQ(accel->closestHit(fromBack, &h), !singleSided);
            EXPECT_EQ(accel->anyHit(fromBack), !singleSided);
            // A packet of both kinds, interleaved.
            std::vector<Ray> rays;
            for (int i = 0; i < 16; ++i) rays.push_back(i % 2 ? fromBack : fromFront);
            std::vector<Hit> hits(rays.size());
            accel->closestHits(rays.data(), hits.data(), int(rays.size()));
            for (size_t i = 0; i < rays.size(); ++i)
              EXPECT_EQ(hits[i].instance != Hit::kInvalid, i % 2 == 0 || !singleSided) << i;
          }
        }
      }
    }
  }
}

TEST(SingleSided, ABackFaceLetsTheRayReachWhatIsBehindIt) {
  // A single-sided square facing +z at z = 0 above a double-sided one at z = -1.
  GeometryScene scene;
  scene.meshes.push_back(square(true));
  scene.meshes.push_back(square(false));  // double-sided, behind (z = -1)
  scene.instances.push_back(Instance{0, Transform()});
  scene.instances.push_back(Instance{1, Transform::translate({0, 0, -1})});
  for (const char* backend : kBackends) {
    SCOPED_TRACE(backend);
    auto accel = makeAccelerator(backend, scene);
    Hit h;
    // From below, through the double-sided square first (it stops the ray).
    ASSERT_TRUE(accel->closestHit(Ray{{0.1f, 0.2f, -5}, {0, 0, 1}, 0, kInfinity, 0}, &h));
    EXPECT_EQ(h.instance, 1u);
    // From below, starting between them: the single-sided one's back is not there.
    EXPECT_FALSE(accel->closestHit(Ray{{0.1f, 0.2f, -0.5f}, {0, 0, 1}, 0, kInfinity, 0}, &h));
    // From above: the single-sided square's front.
    ASSERT_TRUE(accel->closestHit(Ray{{0.1f, 0.2f, 5}, {0, 0, -1}, 0, kInfinity, 0}, &h));
    EXPECT_EQ(h.instance, 0u);
    EXPECT_NEAR(h.t, 5, 1e-5);
  }
}

TEST(SingleSided, BakingAMirrorKeepsTheFrontWhereThePlacementPutsIt) {
  for (const Placement& p : placements()) {
    SCOPED_TRACE(p.name);
    TriangleMesh baked = square(true);
    placeVertices(p.xf, &baked.positions, &baked.indices);
    const Vec3f front = frontOf(p);
    for (size_t t = 0; t < baked.triangleCount(); ++t) {
      const Vec3f a = baked.positions[baked.indices[3 * t]];
      const Vec3f b = baked.positions[baked.indices[3 * t + 1]];
      const Vec3f c = baked.positions[baked.indices[3 * t + 2]];
      EXPECT_GT(dot(cross(b - a, c - a), front), 0) << t;
    }
    // And the baked mesh, attached as it is, is culled from the same side as the instanced one.
    GeometryScene scene;
    scene.meshes.push_back(baked);
    scene.instances.push_back(Instance{0, Transform()});
    for (const char* backend : kBackends) {
      auto accel = makeAccelerator(backend, scene);
      const Vec3f centre = p.xf.point({0, 0, 0});
      EXPECT_TRUE(accel->anyHit(rayTowards(centre, front))) << backend;
      EXPECT_FALSE(accel->anyHit(rayTowards(centre, -front))) << backend;
    }
  }
}

}  // namespace
}  // namespace glint
