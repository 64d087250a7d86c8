// glint benchmark — what analytic shapes and CSG cost per ray.
//
//  1. One sphere as Embree user geometry (glint's analytic sphere) against the same sphere
//     tessellated into triangles at several resolutions, each with its geometric error: the
//     user's "show what accuracy costs in time".
//  2. A CSG tree's cost against its leaf count (2, 4, 8, 16 leaves): a row of spheres, unioned
//     and subtracted from a slab.
//  3. The CSG reference scene (scenes/csg/csg_scene.json) rendered at 800x600: seconds per
//     frame, for the comparison with POV-Ray on the same scene.
//  4. Several rays at a time (issue 50, item 4): the sphere's intersection as a lane kernel
//     (16 rays of a packet solved side by side, the same float pre-test and double solve with
//     the same error bounds as Sphere::span, branch-free so the compiler vectorises it, built
//     for the baseline SSE2 and for AVX2) against the per-lane loop glint's callback runs
//     today, on their own and behind Embree's rtcIntersect1 and rtcIntersect16. Every lane's
//     answer is checked against the scalar solve, to the bit.
// Usage: shapes_bench [--out results.json] [google benchmark flags]. Run from the repository
// root (the scene path is relative to it) with a Release build.
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "bench_support.h"
#include "geometry/accel/accelerator.h"
#include "geometry/csg.h"
#include "geometry/shapes/box.h"
#include "geometry/shapes/primitive_math.h"
#include "geometry/shapes/sphere.h"
#include "renderer/render.h"
#include "scenes/build.h"
#include "scenes/load.h"

namespace glint {
namespace {

// Camera-like rays through a 256x256 grid covering the unit sphere's silhouette and a margin,
// from z = 4 towards the origin.
std::vector<Ray> gridRays() {
  std::vector<Ray> rays;
  const int n = 256;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      Vec3f target{-1.2f + 2.4f * (float(x) + 0.5f) / n, -1.2f + 2.4f * (float(y) + 0.5f) / n, 0};
      Vec3f o{0, 0, 4};
      rays.push_back(Ray{o, normalize(target - o)});
    }
  return rays;
}

// A UV sphere of radius 1 with `rings` latitude bands and 2*rings longitude segments.
TriangleMesh uvSphere(int rings) {
  TriangleMesh m;
  const int segments = 2 * rings;
  for (int i = 0; i <= rings; ++i) {
    float theta = kPi * float(i) / float(rings);
    for (int j = 0; j <= segments; ++j) {
      float phi = 2 * kPi * float(j) / float(segments);
      m.positions.push_back(
          {std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)});
    }
  }
  auto at = [&](int i, int j) { return uint32_t(i * (segments + 1) + j); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      if (i > 0) m.indices.insert(m.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j)});
      if (i < rings - 1)
        m.indices.insert(m.indices.end(), {at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});
    }
  return m;
}

void addShape(GeometryScene* scene, std::unique_ptr<Shape> shape) {
  Instance inst;
  inst.shape = uint32_t(scene->shapes.size());
  scene->shapes.push_back(std::move(shape));
  scene->instances.push_back(inst);
}

uint64_t traceAll(const Accelerator& accel, const std::vector<Ray>& rays) {
  uint64_t hits = 0;
  Hit hit;
  for (const Ray& r : rays) hits += accel.closestHit(r, &hit);
  return hits;
}

void reportPerRay(benchmark::State& state, size_t rays, uint64_t hits) {
  // time / (rays * 1e-9) = nanoseconds per ray.
  state.counters["ns_per_ray"] =
      benchmark::Counter(double(rays) * 1e-9, benchmark::Counter::kIsIterationInvariantRate |
                                                  benchmark::Counter::kInvert);
  state.counters["hit_fraction"] = double(hits) / double(rays);
}

void BM_AnalyticSphere(benchmark::State& state) {
  GeometryScene scene;
  addShape(&scene, std::make_unique<Sphere>(Vec3f{0, 0, 0}, 1.0f));
  auto accel = makeAccelerator("embree", scene);
  std::vector<Ray> rays = gridRays();
  uint64_t hits = 0;
  for (auto _ : state) benchmark::DoNotOptimize(hits = traceAll(*accel, rays));
  reportPerRay(state, rays.size(), hits);
  state.counters["max_error"] = 0;  // exact up to rounding
}

// The same ball as a unit sphere under a rotation and non-uniform scale (object-space rays).
void BM_AnalyticSphereTransformed(benchmark::State& state) {
  GeometryScene scene;
  Instance inst;
  inst.shape = 0;
  inst.worldFromObject = Transform::rotate(30, {1, 1, 0}) * Transform::scale({1, 1, 1});
  scene.shapes.push_back(std::make_unique<Sphere>(Vec3f{0, 0, 0}, 1.0f));
  scene.instances.push_back(inst);
  auto accel = makeAccelerator("embree", scene);
  std::vector<Ray> rays = gridRays();
  uint64_t hits = 0;
  for (auto _ : state) benchmark::DoNotOptimize(hits = traceAll(*accel, rays));
  reportPerRay(state, rays.size(), hits);
}

void BM_TessellatedSphere(benchmark::State& state) {
  const int rings = int(state.range(0));
  GeometryScene scene;
  scene.meshes.push_back(uvSphere(rings));
  scene.instances.push_back({0, Transform()});
  auto accel = makeAccelerator("embree", scene);
  std::vector<Ray> rays = gridRays();
  uint64_t hits = 0;
  for (auto _ : state) benchmark::DoNotOptimize(hits = traceAll(*accel, rays));
  reportPerRay(state, rays.size(), hits);
  state.counters["triangles"] = double(scene.meshes[0].triangleCount());
  // Sagitta of the largest chord: how far the facets fall inside the true sphere.
  state.counters["max_error"] = 1 - std::cos(kPi / float(2 * rings));
}

// A slab minus a row of `leaves - 1` spheres (leaves = 2, 4, 8, 16), all inside one CSG tree.
void BM_CsgLeaves(benchmark::State& state) {
  const int leaves = int(state.range(0));
  auto csg = std::make_unique<CsgShape>();
  std::vector<uint32_t> nodes;
  nodes.push_back(csg->addLeaf(
      std::make_unique<Box>(Vec3f{-1.1f, -1.1f, -0.3f}, Vec3f{1.1f, 1.1f, 0.3f}), Transform()));
  for (int i = 1; i < leaves; ++i) {
    float x = -1.0f + 2.0f * (float(i) - 0.5f) / float(leaves - 1);
    nodes.push_back(csg->addLeaf(std::make_unique<Sphere>(Vec3f{x, 0, 0.3f}, 0.35f), Transform()));
  }
  csg->finish(csg->addOperation(CsgOperation::Difference, nodes));
  GeometryScene scene;
  addShape(&scene, std::move(csg));
  auto accel = makeAccelerator("embree", scene);
  std::vector<Ray> rays = gridRays();
  uint64_t hits = 0;
  for (auto _ : state) benchmark::DoNotOptimize(hits = traceAll(*accel, rays));
  reportPerRay(state, rays.size(), hits);
}

void BM_CsgSceneRender(benchmark::State& state) {
  SceneDescription desc = loadScene("scenes/csg/csg_scene.json");
  desc.render.width = 800;
  desc.render.height = 600;
  RenderScene scene = buildRenderScene(desc);
  auto integrator = makeIntegrator(scene, desc.render);
  RenderOptions options;
  RenderStats stats;
  for (auto _ : state) {
    Film film = render(scene, *integrator, desc.render, options, &stats);
    benchmark::DoNotOptimize(film.color.data());
  }
  state.counters["spp"] = desc.render.spp;
  state.counters["Mrays/s"] = benchmark::Counter(double(stats.rays.total()) * 1e-6,
                                                 benchmark::Counter::kIsIterationInvariantRate);
}

// ---- 4. Several rays at a time ----------------------------------------------------------------

constexpr int kLanes = 16;

// A packet's rays, structure of arrays (Embree's RTCRay16 layout for the fields used).
struct LaneRays {
  alignas(64) float ox[kLanes], oy[kLanes], oz[kLanes];
  alignas(64) float dx[kLanes], dy[kLanes], dz[kLanes];
  alignas(64) float tnear[kLanes], tfar[kLanes];
};

// Sphere::span and firstAccepted for 16 rays side by side: every step of the scalar code in the
// same order and precision, with selects in place of branches. Lane i's answer goes to
// t[i] (+inf where the ray misses or no crossing is accepted). Returns false when the float
// pre-test rejects all 16 lanes (the double solve is then skipped).
// W lanes of double (V), their masks (M), and of float (F) and its masks (I). Specialised per
// width: GCC drops a vector_size that depends on a template parameter.
template <int W>
struct LaneTypes;
template <>
struct LaneTypes<2> {
  typedef double V __attribute__((vector_size(16)));
  typedef long long M __attribute__((vector_size(16)));
  typedef float F __attribute__((vector_size(8)));
  typedef int I __attribute__((vector_size(8)));
};
template <>
struct LaneTypes<4> {
  typedef double V __attribute__((vector_size(32)));
  typedef long long M __attribute__((vector_size(32)));
  typedef float F __attribute__((vector_size(16)));
  typedef int I __attribute__((vector_size(16)));
};

// The vector lambdas below are always inlined into the AVX2 or SSE2 caller; GCC's note that a
// 32-byte vector passed to an out-of-line function would change the ABI does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"
template <int N, int Width>
[[gnu::always_inline]] inline bool sphereLanesBody(
    const float* __restrict ox, const float* __restrict oy, const float* __restrict oz,
    const float* __restrict dx, const float* __restrict dy, const float* __restrict dz,
    const float* __restrict tnear, const float* __restrict tfar, Vec3f c, float radius,
    float* __restrict t) {
  using prim::gammaD;
  using prim::kEpsD;
  alignas(64) int maybe[N];
  int any = 0;
  const float r2f = radius * radius;
  for (int i = 0; i < N; ++i) {
    const float fx = ox[i] - c.x, fy = oy[i] - c.y, fz = oz[i] - c.z;
    const float A = dx[i] * dx[i] + dy[i] * dy[i] + dz[i] * dz[i];
    const float k = (fx * dx[i] + fy * dy[i] + fz * dz[i]) / A;
    const float lx = fx - dx[i] * k, ly = fy - dy[i] * k, lz = fz - dz[i] * k;
    const bool far =
        lx * lx + ly * ly + lz * lz - r2f > 1e-4f * (fx * fx + fy * fy + fz * fz + r2f);
    maybe[i] = int(A > 0) & int(!far);  // & and |, not && and ||: no branches
    any |= maybe[i];
  }
  if (!any) return false;
  // The double solve, W lanes at a time in GCC vector types (W = 4 doubles under AVX2, 2 under
  // SSE2): the compiler does not if-convert the scalar loop, so the selects are written out.
  constexpr int W = Width;
  using V = typename LaneTypes<W>::V;
  using M = typename LaneTypes<W>::M;
  using F = typename LaneTypes<W>::F;
  using I = typename LaneTypes<W>::I;
  auto load = [](const float* p) {
    F v;
    std::memcpy(&v, p, sizeof v);
    return v;
  };
  auto wide = [](F v) { return __builtin_convertvector(v, V); };
  auto vabs = [](V v) { return v < 0 ? -v : v; };
  auto vsqrt = [](V v) {
    V r;
    for (int k = 0; k < W; ++k) r[k] = __builtin_sqrt(v[k]);
    return r;
  };
  const double r = radius, r2 = r * r;
  const V cx = V{} + double(c.x), cy = V{} + double(c.y), cz = V{} + double(c.z);
  for (int i = 0; i < N; i += W) {
    const V f[3] = {wide(load(ox + i)) - cx, wide(load(oy + i)) - cy, wide(load(oz + i)) - cz};
    const V d[3] = {wide(load(dx + i)), wide(load(dy + i)), wide(load(dz + i))};
    V ef[3];
    for (int a = 0; a < 3; ++a) ef[a] = kEpsD * vabs(f[a]);
    V A{}, B{}, absB{}, ff{}, efd{};
    for (int a = 0; a < 3; ++a) {
      A += d[a] * d[a];
      B += f[a] * d[a];
      absB += vabs(f[a] * d[a]);
      ff += f[a] * f[a];
      efd += ef[a] * vabs(d[a]);
    }
    const V C = ff - r2;
    const V eA = gammaD(3) * A;
    const V eB = gammaD(3) * absB + efd;
    V eC = gammaD(4) * (ff + r2);
    for (int a = 0; a < 3; ++a) eC += 2 * vabs(f[a]) * ef[a] * (1 + gammaD(2));
    const V s = B / A;
    const V es = (eB + vabs(s) * eA) / A + gammaD(1) * vabs(s);
    V l2{}, el2{};
    for (int a = 0; a < 3; ++a) {
      const V li = f[a] - s * d[a];
      const V eli = ef[a] + es * vabs(d[a]) + gammaD(2) * (vabs(f[a]) + vabs(s * d[a]));
      l2 += li * li;
      el2 += 2 * vabs(li) * eli + eli * eli;
    }
    el2 += gammaD(3) * l2;
    const V dp = r2 - l2;
    const V edp = el2 + gammaD(2) * (r2 + l2);
    const V D = A * (dp > 0 ? dp : 0);
    const V eD = A * edp + vabs(dp) * eA + gammaD(1) * D;
    // solveQuadratic
    const V sq = vsqrt(D);
    const V rootED = vsqrt(eD);
    const V ratio = eD / sq;
    const V eS = (sq > 0 ? (ratio < rootED ? ratio : rootED) : rootED) + gammaD(1) * sq;
    const V q = -(B + (B < 0 ? -sq : sq));  // copysign(sq, B) for sq >= 0 (B = -0: as +0)
    const V eq = eB + eS + gammaD(1) * vabs(q);
    const M q0 = q == 0;
    const V e00 = vsqrt((eC + eD) / vabs(A));
    V ta = q / A;
    V ea = (eq + vabs(ta) * eA) / vabs(A) + gammaD(1) * vabs(ta);
    V tb = C / q;
    V eb = (eC + vabs(tb) * eq) / vabs(q) + gammaD(1) * vabs(tb);
    ta = q0 ? V{} : ta, tb = q0 ? V{} : tb;
    ea = q0 ? e00 : ea, eb = q0 ? e00 : eb;
    const M swap = ta > tb;
    const V t0 = swap ? tb : ta, e0 = swap ? eb : ea;
    const V t1 = swap ? ta : tb, e1 = swap ? ea : eb;
    // toCrossing and accepts, for the entry and then the exit.
    const F tnearF = load(tnear + i), tfarF = load(tfar + i);
    auto accepted = [&](V tt, V e, F* out) {
      const F tf = __builtin_convertvector(tt, F);
      const V err = e + vabs(tt - wide(tf));
      F te = __builtin_convertvector(err, F);
      const I up = __builtin_convertvector(wide(te) < err, I);
      te = up ? (F)((I)te + 1) : te;
      *out = tf;
      return (tf - te > tnearF) & (tf <= tfarF) & (tf < kInfinity);
    };
    F tEnter, tExit;
    const I hit0 = accepted(t0, e0, &tEnter);
    const I hit1 = accepted(t1, e1, &tExit);
    I solved;
    std::memcpy(&solved, maybe + i, sizeof solved);
    solved = (solved != 0) & __builtin_convertvector(dp + edp >= 0, I);
    const F first = hit0 ? tEnter : tExit;
    const F answer = (solved & (hit0 | hit1)) ? first : F{} + kInfinity;
    std::memcpy(t + i, &answer, sizeof answer);
  }
  return true;
}

// The lane kernel over a packet in Embree's layout (RTCRayN, N lanes) or in LaneRays (16),
// both structure of arrays. Embree hands an N-wide callback its own SIMD width: on an AVX2 CPU
// an rtcIntersect16 packet arrives as two packets of 8.
struct LanePointers {
  const float *ox, *oy, *oz, *dx, *dy, *dz, *tnear, *tfar;
  explicit LanePointers(const LaneRays& r)
      : ox(r.ox), oy(r.oy), oz(r.oz), dx(r.dx), dy(r.dy), dz(r.dz), tnear(r.tnear), tfar(r.tfar) {}
  // RTCRayN: org_x, org_y, org_z, tnear, dir_x, dir_y, dir_z, time, tfar, ... N floats each.
  LanePointers(const RTCRayN* rays, unsigned N) {
    const auto* f = reinterpret_cast<const float*>(rays);
    ox = f, oy = f + N, oz = f + 2 * N, tnear = f + 3 * N;
    dx = f + 4 * N, dy = f + 5 * N, dz = f + 6 * N, tfar = f + 8 * N;
  }
};
template <int Width>
[[gnu::always_inline]] inline bool sphereLanesN(const LanePointers& r, unsigned N, Vec3f c,
                                                float radius, float* t) {
  if (N == 16)
    return sphereLanesBody<16, Width>(r.ox, r.oy, r.oz, r.dx, r.dy, r.dz, r.tnear, r.tfar, c,
                                      radius, t);
  return sphereLanesBody<8, Width>(r.ox, r.oy, r.oz, r.dx, r.dy, r.dz, r.tnear, r.tfar, c, radius,
                                   t);
}
// N = 8 or 16.
bool sphereLanesSse2(const LanePointers& r, unsigned N, Vec3f c, float radius, float* t) {
  return sphereLanesN<2>(r, N, c, radius, t);
}
[[gnu::target("avx2")]] bool sphereLanesAvx2(const LanePointers& r, unsigned N, Vec3f c,
                                             float radius, float* t) {
  return sphereLanesN<4>(r, N, c, radius, t);
}
bool haveAvx2() { return __builtin_cpu_supports("avx2"); }

// The scalar reference: what glint's callback does per lane today (Sphere::intersect).
float sphereScalar(const Sphere& sphere, const Ray& ray) {
  ShapeHit h;
  return sphere.intersect(ray, &h) ? h.t : kInfinity;
}

// The grid rays as packets of 16: 4x4 pixel tiles (the camera's packets are a pixel's samples;
// a tile of neighbouring pixels is as coherent).
std::vector<LaneRays> gridPackets(const std::vector<Ray>& rays) {
  const int n = 256;
  std::vector<LaneRays> packets;
  for (int ty = 0; ty < n; ty += 4)
    for (int tx = 0; tx < n; tx += 4) {
      LaneRays p;
      for (int i = 0; i < kLanes; ++i) {
        const Ray& ray = rays[size_t(ty + i / 4) * n + size_t(tx + i % 4)];
        p.ox[i] = ray.o.x, p.oy[i] = ray.o.y, p.oz[i] = ray.o.z;
        p.dx[i] = ray.d.x, p.dy[i] = ray.d.y, p.dz[i] = ray.d.z;
        p.tnear[i] = ray.tMin, p.tfar[i] = ray.tMax;
      }
      packets.push_back(p);
    }
  return packets;
}

Ray laneRay(const LaneRays& p, int i) {
  Ray r{{p.ox[i], p.oy[i], p.oz[i]}, {p.dx[i], p.dy[i], p.dz[i]}};
  r.tMin = p.tnear[i], r.tMax = p.tfar[i];
  return r;
}

// The kernels alone, no Embree: arg 0 the scalar loop, 1 the lane kernel (SSE2), 2 (AVX2).
void BM_SphereKernel(benchmark::State& state) {
  const int kind = int(state.range(0));
  if (kind == 2 && !haveAvx2()) return state.SkipWithError("no AVX2 on this CPU");
  const Sphere sphere({0, 0, 0}, 1.0f);
  const std::vector<LaneRays> packets = gridPackets(gridRays());
  // Check first: every lane against the scalar solve, to the bit.
  uint64_t mismatches = 0, hits = 0;
  for (const LaneRays& p : packets) {
    alignas(64) float t[kLanes];
    if (kind == 0 || !(kind == 1 ? sphereLanesSse2 : sphereLanesAvx2)(LanePointers(p), kLanes,
                                                                      {0, 0, 0}, 1.0f, t))
      std::fill(t, t + kLanes, kInfinity);
    for (int i = 0; i < kLanes; ++i) {
      const float ref = sphereScalar(sphere, laneRay(p, i));
      if (kind != 0) mismatches += std::bit_cast<uint32_t>(ref) != std::bit_cast<uint32_t>(t[i]);
      hits += ref < kInfinity;
    }
  }
  double sum = 0;
  for (auto _ : state) {
    for (const LaneRays& p : packets) {
      alignas(64) float t[kLanes];
      if (kind == 0) {
        for (int i = 0; i < kLanes; ++i) t[i] = sphereScalar(sphere, laneRay(p, i));
      } else if (!(kind == 1 ? sphereLanesSse2 : sphereLanesAvx2)(LanePointers(p), kLanes,
                                                                  {0, 0, 0}, 1.0f, t)) {
        continue;
      }
      for (int i = 0; i < kLanes; ++i) sum += t[i] < kInfinity ? t[i] : 0.0f;
    }
    benchmark::DoNotOptimize(sum);
  }
  reportPerRay(state, packets.size() * kLanes, hits);
  state.counters["mismatches"] = double(mismatches);
}

// Behind Embree: one user-geometry sphere, no glint accelerator in between (so the callback is
// the only glint code per ray). Arg 0: rtcIntersect1 with the scalar callback (today's path for
// scenes with a plane); 1: rtcIntersect16 with the scalar callback looping over the lanes
// (today's path for pixel packets); 2: rtcIntersect16 with the lane kernel (AVX2 where the CPU
// has it, else SSE2). Embree hands a packet callback the lanes still in the packet's traversal;
// the `lanes_per_call` counter says how full they were.
struct SphereUser {
  Sphere sphere{{0, 0, 0}, 1.0f};
  bool lanes = false, avx2 = false;
  mutable uint64_t calls = 0, activeLanes = 0, width[3] = {};  // calls with N < 8, 8, 16
};

void sphereUserBounds(const RTCBoundsFunctionArguments* args) {
  const auto* user = static_cast<const SphereUser*>(args->geometryUserPtr);
  const Bounds3f b = user->sphere.bounds();
  *args->bounds_o = {b.lower.x, b.lower.y, b.lower.z, 0, b.upper.x, b.upper.y, b.upper.z, 0};
}

void sphereUserIntersect(const RTCIntersectFunctionNArguments* args) {
  const auto* user = static_cast<const SphereUser*>(args->geometryUserPtr);
  const unsigned N = args->N;
  RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, N);
  RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, N);
  ++user->calls;
  ++user->width[N == 16 ? 2 : N == 8 ? 1 : 0];
  for (unsigned i = 0; i < N; ++i) user->activeLanes += args->valid[i] != 0;
  alignas(64) float t[kLanes];
  if (user->lanes && (N == 8 || N == 16)) {
    // Embree's packets are already structure of arrays: the kernel reads them in place.
    if (!(user->avx2 ? sphereLanesAvx2 : sphereLanesSse2)(
            LanePointers(rays, N), N, user->sphere.center(), user->sphere.radius(), t))
      return;
  } else {
    for (unsigned i = 0; i < N; ++i)
      if (args->valid[i]) {
        Ray r{{RTCRayN_org_x(rays, N, i), RTCRayN_org_y(rays, N, i), RTCRayN_org_z(rays, N, i)},
              {RTCRayN_dir_x(rays, N, i), RTCRayN_dir_y(rays, N, i), RTCRayN_dir_z(rays, N, i)}};
        r.tMin = RTCRayN_tnear(rays, N, i), r.tMax = RTCRayN_tfar(rays, N, i);
        t[i] = sphereScalar(user->sphere, r);
      }
  }
  for (unsigned i = 0; i < N; ++i) {
    if (!args->valid[i] || !(t[i] < kInfinity)) continue;
    RTCRayN_tfar(rays, N, i) = t[i];
    RTCHitN_Ng_x(hits, N, i) = 0, RTCHitN_Ng_y(hits, N, i) = 0, RTCHitN_Ng_z(hits, N, i) = 0;
    RTCHitN_u(hits, N, i) = 0, RTCHitN_v(hits, N, i) = 0;
    RTCHitN_primID(hits, N, i) = 0;
    RTCHitN_geomID(hits, N, i) = args->geomID;
    RTCHitN_instID(hits, N, i, 0) = args->context->instID[0];
  }
}

void BM_SpherePackets(benchmark::State& state) {
  const int kind = int(state.range(0));
  RTCDevice device = rtcNewDevice(nullptr);
  RTCScene scene = rtcNewScene(device);
  SphereUser user;
  user.lanes = kind == 2;
  user.avx2 = haveAvx2();
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(geom, 1);
  rtcSetGeometryUserData(geom, &user);
  rtcSetGeometryBoundsFunction(geom, sphereUserBounds, nullptr);
  rtcSetGeometryIntersectFunction(geom, sphereUserIntersect);
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(scene);
  const std::vector<Ray> rays = gridRays();
  const std::vector<LaneRays> packets = gridPackets(rays);
  uint64_t hits = 0;
  double sum = 0;
  for (auto _ : state) {
    hits = 0;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (const LaneRays& p : packets) {
      if (kind == 0) {
        for (int i = 0; i < kLanes; ++i) {
          RTCRayHit rh;
          rh.ray.org_x = p.ox[i], rh.ray.org_y = p.oy[i], rh.ray.org_z = p.oz[i];
          rh.ray.dir_x = p.dx[i], rh.ray.dir_y = p.dy[i], rh.ray.dir_z = p.dz[i];
          rh.ray.tnear = p.tnear[i], rh.ray.tfar = p.tfar[i], rh.ray.time = 0;
          rh.ray.mask = ~0u, rh.ray.id = 0, rh.ray.flags = 0;
          rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
          rtcIntersect1(scene, &context, &rh);
          hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
          sum += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID ? rh.ray.tfar : 0.0f;
        }
        continue;
      }
      alignas(64) int valid[kLanes];
      alignas(64) RTCRayHit16 rh;
      for (int i = 0; i < kLanes; ++i) {
        valid[i] = -1;
        rh.ray.org_x[i] = p.ox[i], rh.ray.org_y[i] = p.oy[i], rh.ray.org_z[i] = p.oz[i];
        rh.ray.dir_x[i] = p.dx[i], rh.ray.dir_y[i] = p.dy[i], rh.ray.dir_z[i] = p.dz[i];
        rh.ray.tnear[i] = p.tnear[i], rh.ray.tfar[i] = p.tfar[i], rh.ray.time[i] = 0;
        rh.ray.mask[i] = ~0u, rh.ray.id[i] = 0, rh.ray.flags[i] = 0;
        rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect16(valid, scene, &context, &rh);
      for (int i = 0; i < kLanes; ++i) {
        const bool hit = rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
        hits += hit;
        sum += hit ? rh.ray.tfar[i] : 0.0f;
      }
    }
    benchmark::DoNotOptimize(sum);
  }
  reportPerRay(state, rays.size(), hits);
  state.counters["lanes_per_call"] =
      user.calls ? double(user.activeLanes) / double(user.calls) : 0.0;
  state.counters["avx2"] = kind == 2 && user.avx2;
  state.counters["N"] = user.width[2] ? 16 : user.width[1] ? 8 : 1;
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
}

// glint's own accelerator on the same rays: closestHit one by one, and closestHits in
// packets of 16 (the pixel-packet path; today's callback loops over the lanes).
void BM_AnalyticSpherePackets(benchmark::State& state) {
  GeometryScene scene;
  addShape(&scene, std::make_unique<Sphere>(Vec3f{0, 0, 0}, 1.0f));
  auto accel = makeAccelerator("embree", scene);
  const std::vector<LaneRays> packets = gridPackets(gridRays());
  std::vector<Ray> tiled;
  for (const LaneRays& p : packets)
    for (int i = 0; i < kLanes; ++i) tiled.push_back(laneRay(p, i));
  uint64_t hits = 0;
  std::vector<Hit> out(kLanes);
  for (auto _ : state) {
    hits = 0;
    for (size_t first = 0; first < tiled.size(); first += kLanes) {
      accel->closestHits(&tiled[first], out.data(), kLanes);
      for (const Hit& h : out) hits += h.t < kInfinity;
    }
    benchmark::DoNotOptimize(hits);
  }
  reportPerRay(state, tiled.size(), hits);
}

BENCHMARK(BM_AnalyticSphere)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AnalyticSphereTransformed)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TessellatedSphere)->Arg(8)->Arg(32)->Arg(128)->Arg(512)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CsgLeaves)->Arg(2)->Arg(4)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SphereKernel)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SpherePackets)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AnalyticSpherePackets)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CsgSceneRender)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// Collects every run's counters for --out.
class JsonCollector : public benchmark::ConsoleReporter {
 public:
  std::vector<std::pair<std::string, std::map<std::string, double>>> runs;
  void ReportRuns(const std::vector<Run>& report) override {
    for (const Run& run : report) {
      std::map<std::string, double> values;
      values["real_ms"] = run.GetAdjustedRealTime();
      for (const auto& [name, counter] : run.counters) values[name] = double(counter);
      runs.emplace_back(run.benchmark_name(), values);
    }
    ConsoleReporter::ReportRuns(report);
  }
};

}  // namespace
}  // namespace glint

int main(int argc, char** argv) {
  std::string out = glint::bench::initialize(argc, argv);
  glint::JsonCollector collector;
  benchmark::RunSpecifiedBenchmarks(&collector);
  if (!out.empty()) {
    std::ofstream f(out);
    f << "{\n";
    for (size_t i = 0; i < collector.runs.size(); ++i) {
      f << "  \"" << collector.runs[i].first << "\": {";
      size_t k = 0;
      for (const auto& [name, value] : collector.runs[i].second)
        f << (k++ ? ", " : "") << "\"" << name << "\": " << value;
      f << "}" << (i + 1 < collector.runs.size() ? "," : "") << "\n";
    }
    f << "}\n";
  }
  return 0;
}
