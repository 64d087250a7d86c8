// Tests for the kd-tree backends ("kdtree", SAH; "kdtree-median"): agreement with a
// double-precision brute force and with Embree on random and adversarial scenes, structure
// statistics, and the node format.
#include "geometry/accel/kdtree.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>
#include <sstream>

#include "geometry/accel/accelerator.h"
#include "geometry/shapes/box.h"
#include "geometry/shapes/plane.h"
#include "geometry/shapes/sphere.h"
#include "scenes/load.h"
#include "test_support.h"

namespace glint {
namespace {

const char* const kBackends[] = {"kdtree", "kdtree-median", "embree"};

// ---------------------------------------------------------------------------------------------
// The reference: every primitive, in double precision
// ---------------------------------------------------------------------------------------------

struct WorldTriangle {
  Vec3f p[3];
  uint32_t instance, prim;
};

struct Reference {
  bool found = false;
  double t = kInfinity;
  uint32_t instance = Hit::kInvalid, prim = Hit::kInvalid;
  double u = 0, v = 0;
  double tTol = 0;   // how far a float backend's t may be from t (see closest())
  double uvTol = 0;  // and its barycentrics from u, v
  // The answer is within rounding of changing: a candidate at or near the nearest t lies
  // within rounding of a triangle's edge or in its plane, or a hit lies at the ends of
  // [tMin, tMax]. Float backends may then decide either way.
  bool ambiguous = false;
};

class BruteForce {
 public:
  explicit BruteForce(const GeometryScene& scene) : scene_(scene) {
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
      const Instance& inst = scene.instances[i];
      if (inst.isShape()) {
        shapes_.push_back(scene.placedShape(i));
        shapeInstance_.push_back(i);
        continue;
      }
      const TriangleMesh& m = scene.meshes[inst.mesh];
      for (uint32_t t = 0; t < m.triangleCount(); ++t) {
        WorldTriangle w{{}, i, t};
        for (int k = 0; k < 3; ++k)  // placed as the kd-tree places them
          w.p[k] = inst.worldFromObject.point(m.positions[m.indices[3 * t + k]]);
        tris_.push_back(w);
      }
    }
  }

  // Double-precision Moller-Trumbore over every triangle, and every shape. Float backends
  // see the hit point with an error of a few ulps of the coordinates' magnitude, magnified by
  // 1 / sin(angle between ray and plane): t and the barycentrics get tolerances to match.
  Reference closest(const Ray& ray) const {
    constexpr double kUlps = 1e-6;  // about 8 float ulps
    Reference best;
    std::vector<double> edgeTs;  // t of candidates whose inside/outside is within rounding
    const double d[3] = {ray.d.x, ray.d.y, ray.d.z};
    const double dl = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const double oScale = std::max({std::abs(ray.o.x), std::abs(ray.o.y), std::abs(ray.o.z)});
    for (const WorldTriangle& w : tris_) {
      double e1[3] = {}, e2[3] = {}, s[3] = {}, scale = oScale, longest = 0;
      for (int k = 0; k < 3; ++k) {
        e1[k] = double(w.p[1][k]) - w.p[0][k];
        e2[k] = double(w.p[2][k]) - w.p[0][k];
        s[k] = double(ray.o[k]) - w.p[0][k];
        for (int j = 0; j < 3; ++j) scale = std::max(scale, double(std::abs(w.p[j][k])));
      }
      double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                     e1[0] * e2[1] - e1[1] * e2[0]};
      double nl = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (nl == 0) continue;  // zero area: never hit
      for (int j = 0; j < 3; ++j)
        longest = std::max(longest, double(length(w.p[(j + 1) % 3] - w.p[j])));
      double p[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2],
                     d[0] * e2[1] - d[1] * e2[0]};
      double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
      double sinAngle = std::abs(det) / (nl * dl);
      if (sinAngle < 1e-9) {
        // In the triangle's plane: an edge-on "hit" is possible only through rounding.
        double off = std::abs(n[0] * s[0] + n[1] * s[1] + n[2] * s[2]) / nl;
        if (off <= kUlps * scale) edgeTs.push_back(ray.tMin);
        continue;
      }
      double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
      double q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2],
                     s[0] * e1[1] - s[1] * e1[0]};
      double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
      double t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
      double margin = std::min({u, v, 1 - u - v});
      double height = nl / longest;
      double mTol = 1e-6 + kUlps * scale / (height * sinAngle);
      double tTol = 1e-6 * std::abs(t) + kUlps * scale / (sinAngle * dl);
      if (margin < -mTol || t < ray.tMin - tTol || t > double(ray.tMax) + tTol) continue;
      if (margin < mTol || std::abs(t - ray.tMin) <= tTol || std::abs(t - ray.tMax) <= tTol)
        edgeTs.push_back(t - tTol);
      if (margin >= 0 && t > ray.tMin && t <= ray.tMax && t < best.t)
        best = {true, t, w.instance, w.prim, u, v, tTol, 1e-4 + 2 * mTol, false};
    }
    for (size_t k = 0; k < shapes_.size(); ++k) {
      Ray r = ray;
      r.tMax = float(std::min<double>(best.t, ray.tMax));
      ShapeHit sh;
      if (shapes_[k].intersect(r, &sh) && sh.t < best.t)
        best = {true, sh.t, shapeInstance_[k], sh.part, 0, 0, 1e-6 * sh.t, 0, false};
    }
    for (double t : edgeTs)
      if (t <= best.t + best.tTol) best.ambiguous = true;
    return best;
  }

  // The scene's bounds, for aiming rays.
  Bounds3f bounds() const { return scene_.bounds(); }
  const std::vector<WorldTriangle>& triangles() const { return tris_; }

 private:
  const GeometryScene& scene_;
  std::vector<WorldTriangle> tris_;
  std::vector<PlacedShape> shapes_;
  std::vector<uint32_t> shapeInstance_;
};

// Counts disagreements and keeps the first few for the failure message.
struct Tally {
  int rays = 0, ambiguous = 0, hits = 0, failures = 0;
  std::ostringstream log;

  void fail(const std::string& backend, int ray, const std::string& what) {
    if (++failures <= 8) log << backend << " ray " << ray << ": " << what << "\n";
  }
};

// Equal distances: within the reference's rounding tolerance, or a relative 1e-5.
bool sameT(double t, const Reference& ref) {
  return std::abs(t - ref.t) <= std::max(2 * ref.tTol, 1e-5 * ref.t);
}

// Checks every backend against the reference for one ray.
void check(const std::vector<std::unique_ptr<Accelerator>>& accels, const Ray& ray,
           const Reference& ref, int index, Tally* tally) {
  ++tally->rays;
  if (ref.ambiguous) {
    ++tally->ambiguous;
    return;
  }
  tally->hits += ref.found;
  for (const auto& accel : accels) {
    Hit hit;
    bool found = accel->closestHit(ray, &hit);
    bool any = accel->anyHit(ray);
    std::ostringstream what;
    if (found != ref.found) {
      what << "closestHit " << found << " expected " << ref.found << " (t " << ref.t << ")";
    } else if (any != ref.found) {
      what << "anyHit " << any << " expected " << ref.found;
    } else if (found && !sameT(hit.t, ref)) {
      what << "t " << hit.t << " expected " << ref.t << " (prim " << hit.prim << " vs " << ref.prim
           << ")";
    } else if (found && hit.instance == ref.instance && hit.prim == ref.prim &&
               (std::abs(hit.u - ref.u) > ref.uvTol || std::abs(hit.v - ref.v) > ref.uvTol)) {
      what << "uv " << hit.u << "," << hit.v << " expected " << ref.u << "," << ref.v;
    } else {
      continue;
    }
    tally->fail(accel->name(), index, what.str());
  }
}

std::vector<std::unique_ptr<Accelerator>> allBackends(const GeometryScene& scene) {
  std::vector<std::unique_ptr<Accelerator>> accels;
  for (const char* name : kBackends) accels.push_back(makeAccelerator(name, scene));
  return accels;
}

// ---------------------------------------------------------------------------------------------
// Rays
// ---------------------------------------------------------------------------------------------

Vec3f randomDirection(std::mt19937& rng) {
  std::normal_distribution<float> g;
  for (;;) {
    Vec3f d{g(rng), g(rng), g(rng)};
    if (length(d) > 1e-3f) return normalize(d);
  }
}

Vec3f randomIn(std::mt19937& rng, const Bounds3f& b) {
  std::uniform_real_distribution<float> u(0, 1);
  return {b.lower.x + u(rng) * (b.upper.x - b.lower.x),
          b.lower.y + u(rng) * (b.upper.y - b.lower.y),
          b.lower.z + u(rng) * (b.upper.z - b.lower.z)};
}

// Ray kinds: 0 inside the bounds, 1 from outside towards a point inside, 2 axis-parallel with
// the origin on a vertex's coordinate plane (where split planes lie), 3 grazing a triangle
// (nearly in its plane, through a point of it).
Ray randomRay(std::mt19937& rng, const Bounds3f& b, const std::vector<WorldTriangle>& tris,
              int kind) {
  std::uniform_real_distribution<float> u(0, 1);
  const float size = length(b.diagonal());
  switch (kind) {
    case 0:
      return Ray{randomIn(rng, b), randomDirection(rng)};
    case 1: {
      Vec3f o = b.center() + randomDirection(rng) * size * 1.5f;
      return Ray{o, normalize(randomIn(rng, b) - o)};
    }
    case 2: {
      const WorldTriangle& w = tris[rng() % tris.size()];
      Vec3f o = randomIn(rng, b);
      int onAxis = int(rng() % 3), along = (onAxis + 1 + int(rng() % 2)) % 3;
      o[onAxis] = w.p[rng() % 3][onAxis];  // in a plane a split may use
      Vec3f d;
      d[along] = rng() % 2 ? 1.0f : -1.0f;
      o[along] = d[along] > 0 ? b.lower[along] - 0.1f * size : b.upper[along] + 0.1f * size;
      return Ray{o, d};
    }
    default: {
      const WorldTriangle& w = tris[rng() % tris.size()];
      float b1 = u(rng), b2 = u(rng);
      if (b1 + b2 > 1) b1 = 1 - b1, b2 = 1 - b2;
      Vec3f p = w.p[0] * (1 - b1 - b2) + w.p[1] * b1 + w.p[2] * b2;
      Vec3f n = cross(w.p[1] - w.p[0], w.p[2] - w.p[0]);
      if (length(n) == 0) return Ray{p, randomDirection(rng)};
      Vec3f d = normalize(normalize(w.p[1] - w.p[0]) + normalize(n) * (u(rng) - 0.5f) * 0.02f);
      return Ray{p - d * size * 0.5f, d};
    }
  }
}

// Checks `count` rays of each kind against brute force on every backend.
Tally checkRandomRays(const GeometryScene& scene, uint32_t seed, int count) {
  BruteForce brute(scene);
  auto accels = allBackends(scene);
  std::mt19937 rng(seed);
  Tally tally;
  Bounds3f b = brute.bounds();
  int index = 0;
  for (int kind = 0; kind < 4; ++kind)
    for (int i = 0; i < count; ++i, ++index) {
      Ray ray = randomRay(rng, b, brute.triangles(), kind);
      check(accels, ray, brute.closest(ray), index, &tally);
    }
  return tally;
}

TriangleMesh randomSoup(std::mt19937& rng, int count, float spread = 1, float size = 0.2f) {
  std::uniform_real_distribution<float> u(-1, 1);
  TriangleMesh m;
  for (int i = 0; i < count; ++i) {
    Vec3f c = Vec3f{u(rng), u(rng), u(rng)} * spread;
    for (int k = 0; k < 3; ++k) {
      m.positions.push_back(c + Vec3f{u(rng), u(rng), u(rng)} * size);
      m.indices.push_back(uint32_t(m.positions.size() - 1));
    }
  }
  return m;
}

GeometryScene oneMeshScene(TriangleMesh mesh) {
  GeometryScene scene;
  scene.meshes.push_back(std::move(mesh));
  scene.instances.push_back({0, Transform()});
  return scene;
}

void expectClean(const Tally& tally, int minHits) {
  EXPECT_EQ(tally.failures, 0) << tally.log.str();
  EXPECT_GE(tally.hits, minHits);
  // Ambiguous rays are skipped: they must stay a small minority or the test means little.
  EXPECT_LE(tally.ambiguous, tally.rays / 5) << tally.ambiguous << " of " << tally.rays;
}

// ---------------------------------------------------------------------------------------------
// Random scenes
// ---------------------------------------------------------------------------------------------

TEST(KdTree, MatchesBruteForceOnRandomSoups) {
  for (uint32_t seed : {1u, 2u, 3u}) {
    std::mt19937 rng(seed);
    GeometryScene scene = oneMeshScene(randomSoup(rng, 2000));
    Tally tally = checkRandomRays(scene, seed * 17, 8000);
    SCOPED_TRACE(seed);
    expectClean(tally, 7000);
  }
}

TEST(KdTree, MatchesBruteForceOnInstancedSoups) {
  std::mt19937 rng(9);
  GeometryScene scene;
  scene.meshes.push_back(randomSoup(rng, 600));
  scene.meshes.push_back(randomSoup(rng, 300, 0.5f, 0.05f));
  scene.instances.push_back({0, Transform()});
  scene.instances.push_back(
      {0, Transform::translate({1.5f, 0, 0}) * Transform::rotate(40, {1, 2, 3})});
  scene.instances.push_back({1, Transform::scale({0.5f, 2, 1})});
  Tally tally = checkRandomRays(scene, 99, 5000);
  expectClean(tally, 5000);
}

// The Stanford bunny, loaded from the shared assets (never skipped: a missing file fails).
GeometryScene loadBunny() {
  std::string path = test::assetsDir() + "/stanford/bun_zipper.glb";
  if (!std::filesystem::exists(path))
    throw std::runtime_error("missing " + path + " (run benchmarks/get_assets.sh)");
  SceneDescription desc = loadScene(path);
  GeometryScene scene;
  for (const MeshDesc& m : desc.meshes) {
    TriangleMesh mesh;
    mesh.positions = m.positions;
    mesh.indices = m.indices;
    scene.meshes.push_back(std::move(mesh));
  }
  for (const InstanceDesc& inst : desc.instances)
    scene.instances.push_back({uint32_t(inst.mesh), inst.worldFromObject});
  return scene;
}

TEST(KdTree, MatchesBruteForceOnStanfordBunny) {
  GeometryScene scene = loadBunny();
  ASSERT_EQ(scene.instancedTriangleCount(), 69451u);
  Tally tally = checkRandomRays(scene, 2024, 500);
  expectClean(tally, 700);
}

// Many rays on the bunny: the kd-trees must agree with Embree; where they do not, brute force
// decides, and the ray must be one whose answer is within rounding of changing.
TEST(KdTree, AgreesWithEmbreeOnManyBunnyRays) {
  GeometryScene scene = loadBunny();
  BruteForce brute(scene);
  auto accels = allBackends(scene);
  const Accelerator& embree = *accels[2];
  std::mt19937 rng(77);
  Bounds3f b = brute.bounds();
  Tally tally;
  int disagreements = 0;
  constexpr int kPerKind = 250000;  // a million rays: inside, outside, grazing, axis-parallel
  for (int kind = 0; kind < 4; ++kind)
    for (int i = 0; i < kPerKind; ++i) {
      Ray ray = randomRay(rng, b, brute.triangles(), kind);
      Hit e;
      bool fe = embree.closestHit(ray, &e);
      bool agree = true;
      for (int k = 0; k < 2; ++k) {
        Hit h;
        bool f = accels[k]->closestHit(ray, &h);
        if (f != fe || (f && std::abs(h.t - e.t) > 1e-4f * e.t) || accels[k]->anyHit(ray) != fe)
          agree = false;
      }
      tally.hits += fe;
      if (agree) continue;
      ++disagreements;
      check(accels, ray, brute.closest(ray), kind * kPerKind + i, &tally);
    }
  EXPECT_EQ(tally.failures, 0) << tally.log.str();
  EXPECT_LE(disagreements, 4 * kPerKind / 100);
  EXPECT_GT(tally.hits, kPerKind);
}

// ---------------------------------------------------------------------------------------------
// Hard scenes
// ---------------------------------------------------------------------------------------------

TEST(KdTree, CoplanarTrianglesAndRaysInAndThroughTheirPlane) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1, 1);
  TriangleMesh m;
  for (int i = 0; i < 800; ++i) {
    Vec3f c{u(rng), u(rng), 0.5f};
    for (int k = 0; k < 3; ++k) {
      m.positions.push_back(c + Vec3f{u(rng), u(rng), 0} * 0.2f);
      m.indices.push_back(uint32_t(m.positions.size() - 1));
    }
  }
  GeometryScene scene = oneMeshScene(m);
  BruteForce brute(scene);
  auto accels = allBackends(scene);
  Tally tally;
  int index = 0;
  for (int i = 0; i < 4000; ++i, ++index) {  // through the plane
    Ray ray{Vec3f{u(rng), u(rng), 0.5f + u(rng)}, randomDirection(rng)};
    check(accels, ray, brute.closest(ray), index, &tally);
  }
  for (int i = 0; i < 4000; ++i, ++index) {  // straight down: t is exact
    Vec3f o{u(rng), u(rng), 2};
    Ray ray{o, {0, 0, -1}};
    Reference ref = brute.closest(ray);
    check(accels, ray, ref, index, &tally);
    for (const auto& accel : accels) {
      Hit hit;
      if (accel->closestHit(ray, &hit) && !ref.ambiguous && accel->name() != "embree") {
        EXPECT_EQ(hit.t, 1.5f) << accel->name();  // exact (Embree's is within an ulp)
      }
    }
  }
  for (int i = 0; i < 4000; ++i, ++index) {  // in the plane, and leaving it
    Vec3f d = randomDirection(rng);
    Ray inPlane{Vec3f{u(rng) * 1.5f, u(rng) * 1.5f, 0.5f}, normalize(Vec3f{d.x, d.y, 0})};
    Ray leaving{inPlane.o, d};
    for (const auto& accel : accels) {
      Hit hit;
      EXPECT_FALSE(accel->closestHit(inPlane, &hit)) << accel->name();
      EXPECT_FALSE(accel->anyHit(inPlane)) << accel->name();
      EXPECT_FALSE(accel->closestHit(leaving, &hit)) << accel->name();
    }
  }
  expectClean(tally, 3000);
}

TEST(KdTree, DuplicatedTrianglesBuildAndHit) {
  std::mt19937 rng(6);
  TriangleMesh m = randomSoup(rng, 200);
  const Vec3f a{-0.3f, -0.3f, 0}, b{0.4f, -0.2f, 0.1f}, c{0, 0.5f, -0.1f};
  for (int i = 0; i < 2000; ++i) {
    for (const Vec3f& p : {a, b, c}) m.positions.push_back(p);
    for (int k = 3; k > 0; --k) m.indices.push_back(uint32_t(m.positions.size() - k));
  }
  GeometryScene scene = oneMeshScene(m);
  for (const char* name : {"kdtree", "kdtree-median"}) {
    auto accel = makeAccelerator(name, scene);
    EXPECT_LT(accel->stats().nodes, 100000u) << name;  // no blow-up into copies of copies
  }
  Tally tally = checkRandomRays(scene, 66, 1500);
  expectClean(tally, 1500);
}

// Steps of width 1/4 and height 1/8 rising along +x, each a tread (horizontal quad) and a
// riser (vertical quad at x = k/4), all exactly representable: hit distances are exact.
TEST(KdTree, StaircaseHitByRaysParallelToRisersAndTreads) {
  constexpr int kSteps = 16;
  constexpr float kW = 0.25f, kH = 0.125f;
  TriangleMesh m;
  auto quad = [&m](Vec3f p0, Vec3f p1, Vec3f p2, Vec3f p3) {
    uint32_t base = uint32_t(m.positions.size());
    for (const Vec3f& p : {p0, p1, p2, p3}) m.positions.push_back(p);
    for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) m.indices.push_back(base + i);
  };
  for (int k = 0; k < kSteps; ++k) {
    float x0 = k * kW, x1 = (k + 1) * kW, y = (k + 1) * kH;
    quad({x0, y - kH, 0}, {x0, y, 0}, {x0, y, 1}, {x0, y - kH, 1});  // riser at x0
    quad({x0, y, 0}, {x1, y, 0}, {x1, y, 1}, {x0, y, 1});            // tread at height y
  }
  GeometryScene scene = oneMeshScene(m);
  auto accels = allBackends(scene);
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(0, 1);
  for (const auto& accel : accels) {
    SCOPED_TRACE(accel->name());
    int wrong = 0;
    // Embree does not count a hit exactly on a mesh's boundary edge: it is spared the rays
    // exactly in a riser's or tread's plane. Its distances come from an approximate
    // reciprocal refined by one Newton step (which instruction set it picks decides the last
    // bit), so they are held to two float steps; ours are exact.
    const bool edges = accel->name() != "embree";
    const float ulps = edges ? 0.0f : 2.0f;
    auto same = [ulps](float t, float exact) {
      return std::abs(t - exact) <= ulps * (std::nextafter(exact, 2 * exact) - exact);
    };
    for (int i = 0; i < 4000; ++i) {
      if (i % 4 == 0 && !edges) continue;
      // Down onto the treads, parallel to the risers, sometimes exactly in a riser's plane.
      int k = int(rng() % kSteps);
      float x = i % 4 == 0 ? k * kW : k * kW + std::max(u(rng), 0.01f) * kW * 0.98f;
      float z = 0.01f + 0.98f * u(rng);
      Hit hit;
      Ray down{{x, 10, z}, {0, -1, 0}};
      if (!accel->closestHit(down, &hit) || !same(hit.t, 10 - (k + 1) * kH)) ++wrong;
      if (!accel->anyHit(down)) ++wrong;
      // Towards -x onto the risers, parallel to the treads (in a tread's plane every 4th).
      float y = i % 4 == 0 ? k * kH : k * kH + std::max(u(rng), 0.01f) * kH * 0.98f;
      Ray left{{10, y, z}, {-1, 0, 0}};
      // In a tread's plane y = k kH the ray grazes tread k-1 edge-on and meets riser k.
      if (!accel->closestHit(left, &hit) || !same(hit.t, 10 - k * kW)) ++wrong;
    }
    EXPECT_EQ(wrong, 0);
  }
}

TEST(KdTree, RaysStartingOnTheBoundingBoxFaces) {
  std::mt19937 rng(10);
  GeometryScene scene = oneMeshScene(randomSoup(rng, 1000));
  BruteForce brute(scene);
  auto accels = allBackends(scene);
  const Bounds3f b = brute.bounds();
  Tally tally;
  for (int i = 0; i < 12000; ++i) {
    Vec3f o = randomIn(rng, b);
    int axis = int(rng() % 3);
    bool upper = rng() % 2;
    o[axis] = upper ? b.upper[axis] : b.lower[axis];
    Vec3f d = randomDirection(rng);
    switch (i % 3) {
      case 0:
        d[axis] = std::abs(d[axis]) * (upper ? -1 : 1);
        break;  // inwards
      case 1:
        d[axis] = 0, d = normalize(d);
        break;  // along the face
      default:
        d[axis] = std::abs(d[axis]) * (upper ? 1 : -1);  // outwards
    }
    Ray ray{o, d};
    check(accels, ray, brute.closest(ray), i, &tally);
  }
  expectClean(tally, 1500);
}

TEST(KdTree, DegenerateTrianglesNeverHitAndDoNotBreakTheBuild) {
  std::mt19937 rng(11);
  TriangleMesh m = randomSoup(rng, 1000);
  std::uniform_int_distribution<int> grid(-8, 8);
  for (int i = 0; i < 1000; ++i) {
    Vec3f p{grid(rng) / 8.0f, grid(rng) / 8.0f, grid(rng) / 8.0f};
    Vec3f e{grid(rng) / 16.0f, grid(rng) / 16.0f, grid(rng) / 16.0f};
    Vec3f tri[3][3] = {{p, p, p}, {p, p + e, p}, {p, p + e, p + e * 2}};  // point, two, line
    for (const Vec3f& v : tri[i % 3]) {
      m.positions.push_back(v);
      m.indices.push_back(uint32_t(m.positions.size() - 1));
    }
  }
  GeometryScene scene = oneMeshScene(m);
  Tally tally = checkRandomRays(scene, 12, 3000);
  expectClean(tally, 3000);
  // Only degenerate triangles: nothing to hit, and the build copes.
  TriangleMesh only;
  only.positions = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {0, 0, 0}};
  only.indices = {0, 1, 2, 3, 3, 3, 0, 0, 1};
  GeometryScene degenerate = oneMeshScene(only);
  for (const auto& accel : allBackends(degenerate)) {
    Hit hit;
    EXPECT_FALSE(accel->closestHit(Ray{{-1, 0, 2}, normalize(Vec3f{1, 1, -1})}, &hit));
  }
}

TEST(KdTree, EmptySceneMissesEverything) {
  GeometryScene scene;
  for (const char* name : {"kdtree", "kdtree-median"}) {
    auto accel = makeAccelerator(name, scene);
    Hit hit;
    EXPECT_FALSE(accel->closestHit(Ray{{0, 0, 0}, {0, 0, 1}}, &hit));
    EXPECT_FALSE(accel->anyHit(Ray{{0, 0, 0}, {0, 0, 1}}));
    EXPECT_EQ(accel->stats().leaves, 1u);
  }
}

TEST(KdTree, OneTriangleRespectsTminAndTmax) {
  TriangleMesh m;
  m.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
  m.indices = {0, 1, 2};
  GeometryScene scene = oneMeshScene(m);
  for (const char* name : {"kdtree", "kdtree-median"}) {
    auto accel = makeAccelerator(name, scene);
    Hit hit;
    ASSERT_TRUE(accel->closestHit(Ray{{0, 0, 1}, {0, 0, -1}, 0, 2}, &hit));
    EXPECT_EQ(hit.t, 1);
    EXPECT_EQ(hit.instance, 0u);
    EXPECT_EQ(hit.prim, 0u);
    EXPECT_FLOAT_EQ(hit.u, 0.25f);  // (0,0) = 0.25 p0 + 0.25 p1 + 0.5 p2
    EXPECT_FLOAT_EQ(hit.v, 0.5f);
    EXPECT_FALSE(accel->closestHit(Ray{{0, 0, 1}, {0, 0, -1}, 0, 0.5f}, &hit));
    EXPECT_FALSE(accel->closestHit(Ray{{0, 0, 1}, {0, 0, -1}, 1.5f, 3}, &hit));
    EXPECT_FALSE(accel->anyHit(Ray{{0, 0, 1}, {0, 0, -1}, 0, 0.5f}));
    EXPECT_TRUE(accel->anyHit(Ray{{0, 0, 1}, {0, 0, -1}, 0, 1}));
    EXPECT_FALSE(accel->anyHit(Ray{{0, 0, 0}, {0, 0, -1}}));  // t = 0 is not > tMin
  }
}

TEST(KdTree, AnalyticShapesMixedWithTrianglesAndAnInfinitePlane) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> u(-1, 1);
  GeometryScene scene;
  scene.meshes.push_back(randomSoup(rng, 500));
  scene.instances.push_back({0, Transform()});
  for (int i = 0; i < 40; ++i) {
    Vec3f c{u(rng) * 1.2f, u(rng) * 1.2f, u(rng) * 1.2f};
    if (i % 2)
      scene.shapes.push_back(std::make_unique<Sphere>(c, 0.05f + 0.1f * std::abs(u(rng))));
    else
      scene.shapes.push_back(std::make_unique<Box>(c, c + Vec3f{0.1f, 0.2f, 0.15f}));
    Transform place = i % 3 ? Transform() : Transform::rotate(30.0f * i, {1, 1, 0});
    scene.instances.push_back({Instance::kNone, place, uint32_t(scene.shapes.size() - 1)});
  }
  scene.shapes.push_back(std::make_unique<Plane>(Vec3f{0, -1.1f, 0}, Vec3f{0, 1, 0}, 1.0f));
  scene.instances.push_back({Instance::kNone, Transform(), uint32_t(scene.shapes.size() - 1)});
  Tally tally = checkRandomRays(scene, 14, 4000);
  expectClean(tally, 8000);
  auto kd = makeAccelerator("kdtree", scene);
  // The plane stays out of the tree: the tree's cell is the bounded geometry's.
  const auto& tree = dynamic_cast<const KdTreeAccelerator&>(*kd).tree();
  EXPECT_LT(length(tree.bounds.diagonal()), 10);
}

// A wall 4e-5 thick seen from 1e4 units away, nearly along its normal: t rounds at 1e-3 there,
// some 25 times the wall, yet every backend must report the near face (refineFarHit; and
// PlacedShape::toObject for analytic shapes). Three walls side by side: a double-sided mesh, a
// box placed by a rotation about the wall's normal, and an unplaced box. Before the fix, the
// mesh's back face came first for 1,126 of 2,000 rays with Embree.
TEST(Accelerators, AThinWallSeenFromFarAwayIsHitOnItsNearFace) {
  GeometryScene scene;
  TriangleMesh slab;
  for (int i = 0; i < 8; ++i)
    slab.positions.push_back({i & 1 ? -0.6f : -1.0f, i & 2 ? 0.2f : -0.2f, i & 4 ? 0.0f : -4e-5f});
  slab.indices = {0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5, 0, 1, 5, 0, 5, 4,
                  2, 6, 7, 2, 7, 3, 0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6};
  scene.meshes.push_back(slab);
  scene.instances.push_back({0, Transform()});
  scene.shapes.push_back(std::make_unique<Box>(Vec3f{-0.2f, -0.2f, -4e-5f}, Vec3f{0.2f, 0.2f, 0}));
  scene.instances.push_back({Instance::kNone, Transform::rotate(90, {0, 0, 1}), 0});
  scene.shapes.push_back(std::make_unique<Box>(Vec3f{0.6f, -0.2f, -4e-5f}, Vec3f{1.0f, 0.2f, 0}));
  scene.instances.push_back({Instance::kNone, Transform(), 1});
  std::mt19937 rng(49);
  std::uniform_real_distribution<float> u(-1, 1);
  for (const std::string& name : acceleratorNames()) {
    auto accel = makeAccelerator(name, scene);
    int misses = 0, backFaces = 0;
    for (int i = 0; i < 2000; ++i) {
      const Vec3f o{u(rng) * 3, u(rng) * 3, 1e4f};
      const Vec3f target{0.8f * float(i % 3 - 1) + u(rng) * 0.19f, u(rng) * 0.19f, 0};
      const Ray ray{o, target - o};
      Hit hit;
      if (!accel->closestHit(ray, &hit)) {
        ++misses;
        continue;
      }
      float z;
      if (scene.instances[hit.instance].mesh == 0) {
        const Vec3f* p = slab.positions.data();
        const uint32_t* t = &slab.indices[3 * hit.prim];
        z = (1 - hit.u - hit.v) * p[t[0]].z + hit.u * p[t[1]].z + hit.v * p[t[2]].z;
      } else {
        z = scene.placedShape(hit.instance).surface(ray, ShapeHit{hit.t, hit.prim}).p.z;
      }
      backFaces += z < -1e-5f;
    }
    std::printf("[ far wall ] %s: %d of 2000 rays on a back face, %d misses\n", name.c_str(),
                backFaces, misses);
    EXPECT_EQ(misses, 0) << name;
    EXPECT_EQ(backFaces, 0) << name;
  }
}

// ---------------------------------------------------------------------------------------------
// Structure
// ---------------------------------------------------------------------------------------------

TEST(KdTree, StatsAreSensibleAndSahBeatsMedianOnBunny) {
  GeometryScene scene = loadBunny();
  auto sah = makeAccelerator("kdtree", scene);
  auto median = makeAccelerator("kdtree-median", scene);
  EXPECT_EQ(sah->name(), "kdtree");
  EXPECT_EQ(median->name(), "kdtree-median");
  const int maxDepth = KdTree::maxDepthFor(69451);
  for (const auto* accel : {sah.get(), median.get()}) {
    SCOPED_TRACE(accel->name());
    AccelStats s = accel->stats();
    EXPECT_GT(s.leaves, 1000u);
    EXPECT_GT(s.bytes, 0u);
    EXPECT_EQ(s.nodes, 2 * s.leaves - 1);  // a full binary tree
    EXPECT_LE(s.emptyLeaves, s.leaves);
    EXPECT_GT(s.maxDepth, 10u);
    EXPECT_LE(s.maxDepth, uint32_t(maxDepth));
    EXPECT_GE(s.meanPrimsPerLeaf, 1.0);
    EXPECT_LT(s.meanPrimsPerLeaf, 20.0);
    EXPECT_GT(s.sahCost, 0);
  }
  EXPECT_LT(sah->stats().sahCost, median->stats().sahCost);
}

TEST(KdTree, BytesAreEightPerNodePlusTheLeafRecords) {
  static_assert(sizeof(KdNode) == 8);
  static_assert(sizeof(KdLeafPrim) == 40);
  std::mt19937 rng(15);
  GeometryScene scene = oneMeshScene(randomSoup(rng, 3000));
  for (const char* name : {"kdtree", "kdtree-median"}) {
    auto accel = makeAccelerator(name, scene);
    const KdTree& tree = dynamic_cast<const KdTreeAccelerator&>(*accel).tree();
    AccelStats s = accel->stats();
    EXPECT_EQ(s.nodes, tree.nodes.size());
    EXPECT_EQ(s.bytes, s.nodes * 8 + tree.leafRecords.size() * sizeof(KdLeafPrim)) << name;
    EXPECT_TRUE(tree.leafPrims.empty()) << name;  // the ids live in the records now
    // Every leaf's run follows the previous leaf's, in node order, and they cover the records.
    uint64_t next = 0;
    for (const KdNode& n : tree.nodes) {
      if (!n.isLeaf()) continue;
      ASSERT_EQ(n.word, next) << name;
      next += n.primCount();
    }
    EXPECT_EQ(next, tree.leafRecords.size());
  }
}

// Packing the leaves changes where a leaf's primitives are read from, nothing else: the packed
// tree is the built one node for node, and each record holds its primitive's id, world-space
// vertices (bit for bit) and culling code. Single-sided, mirrored and analytic primitives
// included, so every culling code and the shapes' records occur.
TEST(KdTree, PackedLeavesHoldTheBuiltLeavesPrimitives) {
  std::mt19937 rng(16);
  GeometryScene scene;
  scene.meshes.push_back(randomSoup(rng, 800));
  scene.meshes.push_back(randomSoup(rng, 400, 0.5f, 0.1f));
  scene.meshes[1].singleSided = true;
  scene.instances.push_back({0, Transform()});
  scene.instances.push_back({1, Transform::translate({0.5f, 0, 0})});
  scene.instances.push_back({1, Transform::scale({-1, 1, 1})});  // mirrored: cull code -1
  for (int i = 0; i < 10; ++i) {
    scene.shapes.push_back(std::make_unique<Sphere>(Vec3f{0.2f * i - 1, 0, 0}, 0.1f));
    scene.instances.push_back({Instance::kNone, Transform(), uint32_t(scene.shapes.size() - 1)});
  }
  UnboundedShapes unbounded;
  unbounded.build(scene);
  KdPrimitives prims;
  prims.gather(scene, unbounded);
  int culls[3] = {0, 0, 0};
  for (int8_t c : prims.triCull) ++culls[c + 1];
  ASSERT_GT(culls[0], 0);
  ASSERT_GT(culls[1], 0);
  ASSERT_GT(culls[2], 0);
  for (KdSplitMethod method : {KdSplitMethod::Sah, KdSplitMethod::Median}) {
    KdTree built;
    if (method == KdSplitMethod::Sah)
      buildSahKdTree(prims, KdCostModel{}, &built);
    else
      buildMedianKdTree(prims, KdCostModel{}, &built);
    KdTreeAccelerator accel(scene, method);
    const KdTree& packed = accel.tree();
    SCOPED_TRACE(accel.name());
    ASSERT_EQ(packed.nodes.size(), built.nodes.size());
    int shapes = 0;
    for (size_t i = 0; i < built.nodes.size(); ++i) {
      const KdNode &b = built.nodes[i], &p = packed.nodes[i];
      ASSERT_EQ(p.bits, b.bits) << "node " << i;  // kind, axis, child or count
      if (!b.isLeaf()) {
        ASSERT_EQ(p.word, b.word) << "node " << i;  // the split
        continue;
      }
      const uint32_t* ids = b.primCount() == 1 ? &b.word : built.leafPrims.data() + b.word;
      for (uint32_t k = 0; k < b.primCount(); ++k) {
        const KdLeafPrim& r = packed.leafRecords[p.word + k];
        ASSERT_EQ(r.id(), ids[k]) << "node " << i;
        if (!prims.isTriangle(r.id())) {
          ++shapes;
          continue;
        }
        EXPECT_EQ(r.cull(), prims.triCull[r.id()]);
        EXPECT_EQ(std::memcmp(r.v.data(), prims.triangles[r.id()].data(), sizeof(r.v)), 0)
            << "node " << i;
      }
    }
    EXPECT_GT(shapes, 0);
  }
  // What the packed trees answer is checked by the brute-force tests above and, for culling,
  // by single_sided_test.cpp: all of them trace packed trees.
}

// Interior nodes flag their empty children (the traversal skips them unread), and only those.
TEST(KdTree, EmptyChildrenAreFlagged) {
  GeometryScene scene = loadBunny();
  for (KdSplitMethod method : {KdSplitMethod::Sah, KdSplitMethod::Median}) {
    KdTreeAccelerator accel(scene, method);
    const KdTree& tree = accel.tree();
    auto empty = [&](uint32_t i) {
      return tree.nodes[i].isLeaf() && tree.nodes[i].primCount() == 0;
    };
    size_t flagged = 0;
    for (uint32_t i = 0; i < tree.nodes.size(); ++i) {
      const KdNode& n = tree.nodes[i];
      if (n.isLeaf()) continue;
      ASSERT_EQ(n.belowEmpty(), empty(i + 1)) << accel.name() << " node " << i;
      ASSERT_EQ(n.aboveEmpty(), empty(n.aboveChild())) << accel.name() << " node " << i;
      ASSERT_FALSE(n.belowEmpty() && n.aboveEmpty()) << accel.name() << " node " << i;
      flagged += n.belowEmpty() + n.aboveEmpty();
    }
    EXPECT_EQ(flagged, accel.stats().emptyLeaves) << accel.name();
  }
}

// The parallel build makes the same tree whatever the number of threads.
TEST(KdTree, ParallelBuildIsIdenticalForOneAndTwoThreads) {
  GeometryScene scene = loadBunny();
  auto build = [&](int threads) {
    std::unique_ptr<KdTreeAccelerator> accel;
    tbb::task_arena(threads).execute(
        [&] { accel = std::make_unique<KdTreeAccelerator>(scene, KdSplitMethod::Sah); });
    return accel;
  };
  auto one = build(1), two = build(2);
  const KdTree &a = one->tree(), &b = two->tree();
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (size_t i = 0; i < a.nodes.size(); ++i) {
    ASSERT_EQ(a.nodes[i].word, b.nodes[i].word) << "node " << i;
    ASSERT_EQ(a.nodes[i].bits, b.nodes[i].bits) << "node " << i;
  }
  ASSERT_EQ(a.leafRecords.size(), b.leafRecords.size());
  EXPECT_EQ(std::memcmp(a.leafRecords.data(), b.leafRecords.data(),
                        a.leafRecords.size() * sizeof(KdLeafPrim)),
            0);
  EXPECT_EQ(a.stats.sahCost, b.stats.sahCost);
}

// The counted traversal (glint bench-accel --traversal-counts) is the plain one with counters:
// the same answers, and counts that add up.
TEST(KdTree, CountedTraversalGivesThePlainAnswers) {
  std::mt19937 rng(31);
  GeometryScene scene = oneMeshScene(randomSoup(rng, 2000));
  BruteForce brute(scene);
  for (const char* name : {"kdtree", "kdtree-median"}) {
    auto accel = makeAccelerator(name, scene);
    const auto& kd = dynamic_cast<const KdTreeAccelerator&>(*accel);
    KdTraversalCounts closest, any;
    for (int i = 0; i < 2000; ++i) {
      Ray ray = randomRay(rng, brute.bounds(), brute.triangles(), i % 4);
      Hit plain;
      const bool hit = kd.closestHit(ray, &plain);
      ASSERT_EQ(kd.countedTrace(ray, false, &closest), hit) << name << " ray " << i;
      ASSERT_EQ(kd.countedTrace(ray, true, &any), kd.anyHit(ray)) << name << " ray " << i;
    }
    for (const KdTraversalCounts* c : {&closest, &any}) {
      EXPECT_EQ(c->rays, 2000u) << name;
      EXPECT_GE(c->nodes, c->leaves) << name;
      EXPECT_GE(c->leaves, c->emptyLeaves) << name;
      EXPECT_GT(c->primTests, 0u) << name;
    }
    EXPECT_EQ(closest.hits, any.hits) << name;
    EXPECT_LE(any.primTests, closest.primTests) << name;  // any-hit stops at the first hit
  }
}

TEST(KdTree, FactoryNamesAllBackends) {
  EXPECT_EQ(acceleratorNames(), (std::vector<std::string>{"embree", "kdtree", "kdtree-median"}));
  GeometryScene scene;
  for (const std::string& name : acceleratorNames())
    EXPECT_EQ(makeAccelerator(name, scene)->name(), name);
}

}  // namespace
}  // namespace glint
