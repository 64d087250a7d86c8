// Analytic shapes inside Embree (the user-geometry adaptor): agreement with direct
// intersection of every placed shape, packets, shadow queries, infinite planes kept out of the
// BVH, shapes mixed with triangle meshes, and surface interactions of shape hits.
#include <embree3/rtcore.h>
#include <gtest/gtest.h>

#include <random>

#include "geometry/accel/accelerator.h"
#include "geometry/accel/embree_accel.h"
#include "geometry/csg.h"
#include "geometry/interaction.h"
#include "geometry/shapes/box.h"
#include "geometry/shapes/cone.h"
#include "geometry/shapes/cylinder.h"
#include "geometry/shapes/disk.h"
#include "geometry/shapes/plane.h"
#include "geometry/shapes/quad.h"
#include "geometry/shapes/sphere.h"

namespace glint {
namespace {

void addShape(GeometryScene* scene, std::unique_ptr<Shape> shape, const Transform& xf) {
  Instance inst;
  inst.shape = uint32_t(scene->shapes.size());
  inst.worldFromObject = xf;
  scene->shapes.push_back(std::move(shape));
  scene->instances.push_back(inst);
}

// A field of every primitive kind under random rotations, scales and shears.
GeometryScene randomShapes(std::mt19937& rng, int count, bool withPlane) {
  std::uniform_real_distribution<float> u(-1, 1);
  GeometryScene scene;
  for (int i = 0; i < count; ++i) {
    std::unique_ptr<Shape> s;
    switch (i % 6) {
      case 0:
        s = std::make_unique<Sphere>(Vec3f{0, 0, 0}, 0.3f);
        break;
      case 1:
        s = std::make_unique<Box>(Vec3f{-0.2f, -0.3f, -0.1f}, Vec3f{0.2f, 0.3f, 0.2f});
        break;
      case 2:
        s = std::make_unique<Cylinder>(0.2f, 0.5f, i % 12 < 6);
        break;
      case 3:
        s = std::make_unique<Cone>(0.3f, 0.5f, i % 12 < 6);
        break;
      case 4:
        s = std::make_unique<Disk>(0.3f);
        break;
      default:
        s = std::make_unique<Quad>(Vec3f{-0.2f, 0, -0.2f}, Vec3f{0.4f, 0, 0}, Vec3f{0, 0.1f, 0.4f});
    }
    Mat4 shear;
    shear.m[0][1] = 0.3f * u(rng);
    shear.m[1][2] = 0.3f * u(rng);
    Mat4 shearInv;
    EXPECT_TRUE(invert(shear, &shearInv));
    Transform xf = Transform::translate(Vec3f{u(rng), u(rng), u(rng)} * 3.0f) *
                   Transform::rotate(180 * u(rng), Vec3f{u(rng), u(rng), 1}) *
                   Transform(shear, shearInv) *
                   Transform::scale({1 + 0.5f * u(rng), 1 + 0.5f * u(rng), 1 + 0.5f * u(rng)});
    addShape(&scene, std::move(s), xf);
  }
  if (withPlane)
    addShape(&scene, std::make_unique<Plane>(Vec3f{0, -3.5f, 0}, Vec3f{0, 1, 0}, 1.0f),
             Transform::rotate(10, {1, 0, 0}));
  return scene;
}

// The nearest hit by testing every placed shape directly.
bool bruteForce(const GeometryScene& scene, const Ray& ray, Hit* hit) {
  bool found = false;
  Ray r = ray;
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    ShapeHit sh;
    if (!scene.placedShape(i).intersect(r, &sh)) continue;
    r.tMax = sh.t;
    *hit = Hit{sh.t, i, sh.part, 0, 0};
    found = true;
  }
  return found;
}

Ray randomRay(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1, 1);
  Vec3f o{u(rng) * 6, u(rng) * 6, u(rng) * 6};
  Vec3f target{u(rng) * 3, u(rng) * 3, u(rng) * 3};
  return Ray{o, normalize(target - o)};
}

TEST(EmbreeShapes, ClosestHitMatchesDirectIntersection) {
  std::mt19937 rng(11);
  for (bool plane : {false, true}) {
    GeometryScene scene = randomShapes(rng, 120, plane);
    auto accel = makeAccelerator("embree", scene);
    int hits = 0;
    for (int i = 0; i < 4000; ++i) {
      Ray ray = randomRay(rng);
      Hit expected, got;
      bool e = bruteForce(scene, ray, &expected);
      bool g = accel->closestHit(ray, &got);
      ASSERT_EQ(e, g) << "ray " << i;
      if (!e) continue;
      ++hits;
      EXPECT_EQ(got.instance, expected.instance);
      EXPECT_EQ(got.prim, expected.prim);
      EXPECT_FLOAT_EQ(got.t, expected.t);
      EXPECT_EQ(accel->anyHit(ray), true);
    }
    EXPECT_GT(hits, 1000);
  }
}

TEST(EmbreeShapes, PacketsAgreeWithSingleRays) {
  std::mt19937 rng(12);
  GeometryScene scene = randomShapes(rng, 60, false);
  auto accel = makeAccelerator("embree", scene);
  for (int batch = 0; batch < 200; ++batch) {
    Ray rays[16];
    Hit packet[16];
    int n = 1 + batch % 16;
    for (int i = 0; i < n; ++i) rays[i] = randomRay(rng);
    accel->closestHits(rays, packet, n);
    for (int i = 0; i < n; ++i) {
      Hit single;
      bool found = accel->closestHit(rays[i], &single);
      ASSERT_EQ(found, packet[i].instance != Hit::kInvalid);
      if (found) {
        EXPECT_EQ(packet[i].instance, single.instance);
        EXPECT_EQ(packet[i].t, single.t);
      }
    }
  }
}

// A camera's pixel is traced as one packet of its samples. Embree's coherent (frustum)
// traversal lost such packets far from the origin: a 2 x 2 card 4.19 units in front of the
// camera, both moved by 1e4, missed a third of them (0.6% at 1e3, a few already at 10 with
// mixed direction signs), so distant scenes rendered half black. Packets must find exactly
// what single rays find, baked or instanced, near and far.
TEST(EmbreeShapes, PixelPacketsFarFromTheOriginFindWhatSingleRaysFind) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> u(-1, 1);
  for (float offset : {0.0f, 10.0f, 1e3f, 1e4f, 1e6f}) {
    for (bool instanced : {false, true}) {
      SCOPED_TRACE(::testing::Message()
                   << "offset " << offset << (instanced ? " instanced" : " baked"));
      // Five cards one behind the other (a top-level tree with inner nodes: one alone never
      // lost a packet), as TextureCoordinateTest's five meshes.
      GeometryScene scene;
      for (uint32_t k = 0; k < 5; ++k) {
        const Vec3f at{offset, offset, -offset + 0.05f * float(k)};
        TriangleMesh card;
        for (Vec3f p : {Vec3f{-1, -1, 0}, Vec3f{1, -1, 0}, Vec3f{1, 1, 0}, Vec3f{-1, 1, 0}})
          card.positions.push_back(instanced ? p : p + at);
        card.indices = {0, 1, 2, 0, 2, 3};
        scene.meshes.push_back(std::move(card));
        scene.instances.push_back({k, instanced ? Transform::translate(at) : Transform()});
      }
      const Vec3f at{offset, offset, -offset};
      auto accel = makeAccelerator("embree", scene);
      const Vec3f eye = at + Vec3f{0, 0, -4.19f};
      int lost = 0, found = 0;
      for (int pixel = 0; pixel < 1000; ++pixel) {
        // A pixel's direction, straddling the axes for one in five, and its samples' spread.
        const float spread = 3e-4f;
        const Vec2f c = pixel % 5 == 0 ? Vec2f{u(rng) * spread, u(rng) * spread}
                                       : Vec2f{u(rng) * 0.2f, u(rng) * 0.2f};
        Ray rays[16];
        Hit packet[16];
        const int n = 4 + pixel % 13;
        for (int i = 0; i < n; ++i) {
          const Vec3f d{c.x + u(rng) * spread, c.y + u(rng) * spread, 1};
          rays[i] = Ray{eye, normalize(d)};
        }
        accel->closestHits(rays, packet, n);
        for (int i = 0; i < n; ++i) {
          Hit single;
          const bool hit = accel->closestHit(rays[i], &single);
          found += hit;
          lost += hit && packet[i].instance == Hit::kInvalid;
        }
      }
      EXPECT_EQ(lost, 0) << "of " << found;
      EXPECT_GT(found, 9000);  // every ray is aimed at the card
    }
  }
}

TEST(EmbreeShapes, ShadowRaysRespectTheSegment) {
  GeometryScene scene;
  addShape(&scene, std::make_unique<Sphere>(Vec3f{0, 0, 0}, 1.0f), Transform());
  auto accel = makeAccelerator("embree", scene);
  Ray ray{{-5, 0, 0}, {1, 0, 0}};
  ray.tMax = 3.9f;  // stops short of the sphere at t = 4
  EXPECT_FALSE(accel->anyHit(ray));
  ray.tMax = 4.1f;
  EXPECT_TRUE(accel->anyHit(ray));
  ray.tMin = 6.1f;  // starts beyond the far side at t = 6
  ray.tMax = kInfinity;
  EXPECT_FALSE(accel->anyHit(ray));
}

TEST(EmbreeShapes, InfinitePlaneStaysOutOfTheHierarchy) {
  GeometryScene scene;
  addShape(&scene, std::make_unique<Plane>(Vec3f{0, 0, 0}, Vec3f{0, 1, 0}, 1.0f), Transform());
  addShape(&scene, std::make_unique<Sphere>(Vec3f{0, 1, 0}, 1.0f), Transform());
  // Bounds ignore the plane: the scene's box is the sphere's.
  Bounds3f b = scene.bounds();
  EXPECT_FALSE(isUnbounded(b));
  EXPECT_NEAR(b.upper.y, 2.0f, 1e-5f);
  auto accel = makeAccelerator("embree", scene);
  Hit hit;
  // Far away on the plane, a million units out: only the plane can be hit.
  Ray far{{1e6f, 10, 3e5f}, normalize(Vec3f{0.3f, -1, 0.1f})};
  ASSERT_TRUE(accel->closestHit(far, &hit));
  EXPECT_EQ(hit.instance, 0u);
  // Straight down onto the sphere: the sphere is nearer than the plane below it.
  Ray down{{0, 5, 0}, {0, -1, 0}};
  ASSERT_TRUE(accel->closestHit(down, &hit));
  EXPECT_EQ(hit.instance, 1u);
  EXPECT_NEAR(hit.t, 3.0f, 1e-5f);
  // Parallel to the plane, above it: a miss unless the sphere is in the way.
  Ray parallel{{-10, 0.5f, 5}, {1, 0, 0}};
  EXPECT_FALSE(accel->closestHit(parallel, &hit));
  EXPECT_TRUE(accel->anyHit(down));
}

TEST(EmbreeShapes, ShapesAndMeshesShareOneScene) {
  GeometryScene scene;
  TriangleMesh tri;
  tri.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
  tri.indices = {0, 1, 2};
  scene.meshes.push_back(tri);
  scene.instances.push_back({0, Transform()});
  addShape(&scene, std::make_unique<Sphere>(Vec3f{0, 0, 2}, 0.5f), Transform());
  auto accel = makeAccelerator("embree", scene);
  Hit hit;
  ASSERT_TRUE(accel->closestHit(Ray{{0, 0, 5}, {0, 0, -1}}, &hit));
  EXPECT_EQ(hit.instance, 1u);  // the sphere, in front of the triangle
  EXPECT_NEAR(hit.t, 2.5f, 1e-5f);
  ASSERT_TRUE(accel->closestHit(Ray{{0.9f, -0.8f, 5}, {0, 0, -1}}, &hit));
  EXPECT_EQ(hit.instance, 0u);  // beside the sphere: the triangle
  EXPECT_EQ(scene.shapeInstanceCount(), 1u);
  EXPECT_EQ(scene.instancedTriangleCount(), 1u);
}

TEST(EmbreeShapes, SurfaceInteractionOfAShapeHit) {
  GeometryScene scene;
  // A sphere stretched along x and moved: the normal must come through the inverse transpose.
  Transform xf = Transform::translate({1, 2, 3}) * Transform::scale({2, 1, 1});
  addShape(&scene, std::make_unique<Sphere>(Vec3f{0, 0, 0}, 1.0f), xf);
  auto accel = makeAccelerator("embree", scene);
  Vec3f target{1 + 2 * std::sqrt(0.5f), 2 + std::sqrt(0.5f), 3};  // on the ellipsoid
  Ray ray{target + Vec3f{3, 3, 0}, normalize(Vec3f{-3, -3, 0})};
  Hit hit;
  ASSERT_TRUE(accel->closestHit(ray, &hit));
  SurfaceNeeds needs;
  needs.tangents = true;
  SurfaceInteraction si = computeSurfaceInteraction(scene, ray, hit, needs);
  EXPECT_LT(distance(si.p, target), 1e-4f);
  // Gradient of (x/2)^2 + y^2 + z^2 at the object point (sqrt .5, sqrt .5, 0) -> (x/4, y, z).
  Vec3f expected = normalize(Vec3f{std::sqrt(0.5f) / 2, std::sqrt(0.5f), 0});
  EXPECT_NEAR(dot(si.ng, expected), 1.0f, 1e-5f);
  EXPECT_EQ(si.mesh, Instance::kNone);
  EXPECT_EQ(si.materialSlot, 0u);
  EXPECT_GT(lengthSquared(si.dpdu), 0.0f);
}

// A material without textures or bump maps asks for no uv and no dp/du: the shapes skip them
// (a sphere's uv is an acos and an atan2), and what they do give must not change.
TEST(EmbreeShapes, SurfaceDetailsNotAskedForAreZeroAndChangeNothingElse) {
  std::mt19937 rng(11);
  GeometryScene scene = randomShapes(rng, 24, true);
  auto csg = std::make_unique<CsgShape>();
  const uint32_t box =
      csg->addLeaf(std::make_unique<Box>(Vec3f{-1, -1, -1}, Vec3f{1, 1, 1}), Transform());
  const uint32_t ball = csg->addLeaf(std::make_unique<Sphere>(Vec3f{0, 0, 1}, 0.6f),
                                     Transform::rotate(30, {1, 1, 0}));
  csg->finish(csg->addOperation(CsgOperation::Difference, {box, ball}));
  addShape(&scene, std::move(csg),
           Transform::translate({0, 1, 0}) * Transform::rotate(20, {0, 1, 1}));
  auto accel = makeAccelerator("embree", scene);
  SurfaceNeeds full, uvOnly, lean;
  full.tangents = uvOnly.uvs = true;
  lean.uvs = lean.tangents = uvOnly.tangents = false;
  int hits = 0, withTangents = 0;
  for (int i = 0; i < 4000; ++i) {
    const Ray ray = randomRay(rng);
    Hit hit;
    if (!accel->closestHit(ray, &hit)) continue;
    ++hits;
    const SurfaceInteraction a = computeSurfaceInteraction(scene, ray, hit, full);
    const SurfaceInteraction b = computeSurfaceInteraction(scene, ray, hit, uvOnly);
    const SurfaceInteraction c = computeSurfaceInteraction(scene, ray, hit, lean);
    for (const SurfaceInteraction* x : {&b, &c}) {
      EXPECT_EQ(x->p, a.p);
      EXPECT_EQ(x->pError, a.pError);
      EXPECT_EQ(x->ng, a.ng);
      EXPECT_EQ(x->ns, a.ns);
      EXPECT_EQ(x->frontFace, a.frontFace);
      EXPECT_EQ(x->materialSlot, a.materialSlot);
      EXPECT_EQ(x->dpdu, Vec3f{});
      EXPECT_EQ(x->dpdv, Vec3f{});
    }
    EXPECT_EQ(b.uv.x, a.uv.x);
    EXPECT_EQ(b.uv.y, a.uv.y);
    EXPECT_EQ(c.uv.x, 0.0f);
    EXPECT_EQ(c.uv.y, 0.0f);
    withTangents += lengthSquared(cross(a.dpdu, a.dpdv)) > 0;
  }
  EXPECT_GT(hits, 1000);
  EXPECT_EQ(withTangents, hits);  // asked for, every shape gives its frame
}

TEST(EmbreeShapes, CsgMaterialSlotsReachTheInteraction) {
  GeometryScene scene;
  auto csg = std::make_unique<CsgShape>();
  uint32_t a = csg->addLeaf(std::make_unique<Box>(Vec3f{-1, -1, -1}, Vec3f{1, 1, 1}), Transform());
  uint32_t b = csg->addLeaf(std::make_unique<Sphere>(Vec3f{0, 0, 1}, 0.5f), Transform());
  csg->finish(csg->addOperation(CsgOperation::Difference, {a, b}));
  addShape(&scene, std::move(csg), Transform());
  auto accel = makeAccelerator("embree", scene);
  Hit hit;
  Ray centre{{0, 0, 5}, {0, 0, -1}};  // into the dimple the sphere leaves
  ASSERT_TRUE(accel->closestHit(centre, &hit));
  EXPECT_NEAR(hit.t, 4.5f, 1e-5f);
  EXPECT_EQ(computeSurfaceInteraction(scene, centre, hit).materialSlot, 1u);
  Ray edge{{0.8f, 0.8f, 5}, {0, 0, -1}};  // beside it: the box's face
  ASSERT_TRUE(accel->closestHit(edge, &hit));
  EXPECT_EQ(computeSurfaceInteraction(scene, edge, hit).materialSlot, 0u);
}

// Rejects every candidate: the adaptor must consult it and keep looking.
void rejectAll(const RTCFilterFunctionNArguments* args) {
  for (unsigned i = 0; i < args->N; ++i) args->valid[i] = 0;
}

// Rejects candidates nearer than t = 5 (an alpha test, say).
void rejectNearerThanFive(const RTCFilterFunctionNArguments* args) {
  for (unsigned i = 0; i < args->N; ++i)
    if (args->valid[i] != 0 && RTCRayN_tfar(args->ray, args->N, i) < 5) args->valid[i] = 0;
}

TEST(EmbreeShapes, ARejectedCrossingOffersTheNextOne) {
  GeometryScene scene;
  addShape(&scene, std::make_unique<Sphere>(Vec3f{0, 0, 0}, 1.0f), Transform());
  auto accel = makeAccelerator("embree", scene);
  auto& embree = static_cast<EmbreeAccelerator&>(*accel);
  RTCGeometry geom = rtcGetGeometry(embree.rtcScene(), 0);
  rtcSetGeometryIntersectFilterFunction(geom, rejectNearerThanFive);
  rtcSetGeometryOccludedFilterFunction(geom, rejectNearerThanFive);
  rtcCommitGeometry(geom);
  rtcCommitScene(embree.rtcScene());
  Ray ray{{0, 0, 5}, {0, 0, -1}};  // enters at t = 4 (rejected), leaves at t = 6
  Hit hit;
  ASSERT_TRUE(accel->closestHit(ray, &hit));
  EXPECT_NEAR(hit.t, 6.0f, 1e-5f);
  ray.tMax = 5.5f;
  EXPECT_FALSE(accel->anyHit(ray));
  ray.tMax = 6.5f;
  EXPECT_TRUE(accel->anyHit(ray));
}

TEST(EmbreeShapes, TheAdaptorCallsTheGeometryFilters) {
  GeometryScene scene;
  addShape(&scene, std::make_unique<Sphere>(Vec3f{0, 0, 0}, 1.0f), Transform());   // near
  addShape(&scene, std::make_unique<Sphere>(Vec3f{0, 0, -5}, 1.0f), Transform());  // far
  auto accel = makeAccelerator("embree", scene);
  auto& embree = static_cast<EmbreeAccelerator&>(*accel);
  Ray ray{{0, 0, 5}, {0, 0, -1}};
  Hit hit;
  ASSERT_TRUE(accel->closestHit(ray, &hit));
  EXPECT_EQ(hit.instance, 0u);
  // A filter on the near sphere that rejects everything: the far sphere must be found.
  RTCGeometry near = rtcGetGeometry(embree.rtcScene(), 0);
  rtcSetGeometryIntersectFilterFunction(near, rejectAll);
  rtcSetGeometryOccludedFilterFunction(near, rejectAll);
  rtcCommitGeometry(near);
  rtcCommitScene(embree.rtcScene());
  ASSERT_TRUE(accel->closestHit(ray, &hit));
  EXPECT_EQ(hit.instance, 1u);
  EXPECT_NEAR(hit.t, 9.0f, 1e-5f);
  Ray rays[4] = {ray, ray, ray, ray};
  Hit hits[4];
  accel->closestHits(rays, hits, 4);  // the packet path (rtcIntersect16 with N = 16 lanes)
  for (const Hit& h : hits) EXPECT_EQ(h.instance, 1u);
  Ray shadow = ray;
  shadow.tMax = 7;  // reaches only the (filtered) near sphere
  EXPECT_FALSE(accel->anyHit(shadow));
  shadow.tMax = 9.5f;
  EXPECT_TRUE(accel->anyHit(shadow));
}

}  // namespace
}  // namespace glint
