// glint — `glint bench-accel`: builds every acceleration backend over one mesh and measures
// build time, size, and single-ray rates for camera rays and incoherent occlusion rays.
//
// The protocol (benchmarks/README.md; outside checks repeat it, so keep it exactly):
//  - camera on +Z of the centre c of the mesh's bounding box, looking down -Z, at distance
//    r / tan(22.5°) with r = half the box diagonal; 45° vertical field of view;
//  - width x height pixels (800x600), spp jittered samples per pixel (16): the jitter is the
//    addressed sampler's first dimension pair (Sampler(pixelSampleKey(seed, pixel), s).get2D()),
//    so the rays depend on the seed only; rays are stored pixel by pixel, a pixel's samples
//    together;
//  - one occlusion ray per camera hit, from Embree's hits (so every backend traces the same
//    occlusion rays): the origin offset past the hit point's error bound
//    (SurfaceInteraction::spawnRay), the direction cosine-distributed about the geometric normal
//    on the camera's side, from the sampler's second dimension pair, tMax infinite;
//  - each backend traces the stored rays one at a time (closestHit, then anyHit) on `threads`
//    threads in one TBB arena; ray generation is never timed.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <thread>

#include "apps/cli_common.h"
#include "apps/commands.h"
#include "geometry/accel/bare_embree.h"
#include "geometry/accel/embree_accel.h"
#include "geometry/accel/kdtree.h"
#include "geometry/interaction.h"
#include "geometry/sampling.h"
#include "renderer/progress.h"
#include "renderer/sampler.h"
#include "scenes/build.h"
#include "scenes/load.h"

namespace glint::app {

namespace {

using Clock = std::chrono::steady_clock;

struct BenchArgs {
  std::string mesh;
  std::vector<std::string> accels;  // empty: every backend
  int width = 800, height = 600, spp = 16;
  uint64_t seed = 0;
  int threads = 0;       // 0 = hardware concurrency
  size_t subsample = 0;  // 0 = every triangle
  std::optional<std::string> json;
  bool quiet = false;
  bool embreeHighQuality = false;  // also time Embree's high-quality build (an extra JSON key)
  bool traversalCounts = false;    // kd-trees: also count node visits etc. (stdout only)
};

struct BackendResult {
  std::string name;
  double buildSeconds = 0;
  double highQualityBuildSeconds = 0;  // embree only: RTC_BUILD_QUALITY_HIGH, for the targets
  AccelStats stats;
  double cameraMrays = 0, occlusionMrays = 0;
  uint64_t cameraHits = 0, occluded = 0;
  std::optional<KdTraversalCounts> cameraCounts, occlusionCounts;  // --traversal-counts
};

double seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

// ---------------------------------------------------------------------------------------------
// The mesh
// ---------------------------------------------------------------------------------------------

// Keeps `keep` triangles spread evenly over the file's order (triangle floor(j * total / keep)
// for j < keep), so a subsample is deterministic and covers the whole mesh. Meshes left
// without triangles are dropped with their instances.
void subsampleTriangles(SceneDescription* desc, size_t keep) {
  size_t total = 0;
  for (const MeshDesc& m : desc->meshes) total += m.indices.size() / 3;
  if (keep > total)
    throw SceneError({"command line", "--subsample"}, "cannot keep " + std::to_string(keep) +
                                                          " triangles: " + desc->file + " has " +
                                                          std::to_string(total));
  size_t global = 0, picked = 0;
  auto nextPick = [&] { return picked < keep ? picked * total / keep : total; };
  size_t pick = nextPick();
  std::vector<MeshDesc> meshes;
  std::vector<int> newIndex(desc->meshes.size(), -1);
  for (size_t i = 0; i < desc->meshes.size(); ++i) {
    MeshDesc& m = desc->meshes[i];
    std::vector<uint32_t> kept;
    for (size_t t = 0; t < m.indices.size() / 3; ++t, ++global) {
      if (global != pick) continue;
      kept.insert(kept.end(), m.indices.begin() + ptrdiff_t(3 * t),
                  m.indices.begin() + ptrdiff_t(3 * t + 3));
      ++picked;
      pick = nextPick();
    }
    if (kept.empty()) continue;
    m.indices = std::move(kept);
    newIndex[i] = int(meshes.size());
    meshes.push_back(std::move(m));
  }
  std::vector<InstanceDesc> instances;
  for (InstanceDesc& inst : desc->instances)
    if (newIndex[size_t(inst.mesh)] >= 0) {
      inst.mesh = newIndex[size_t(inst.mesh)];
      instances.push_back(std::move(inst));
    }
  desc->meshes = std::move(meshes);
  desc->instances = std::move(instances);
}

// The protocol's camera: on +Z of the box centre, far enough that a 45° cone holds the box's
// bounding sphere.
Camera benchCamera(const Bounds3f& b, int width, int height) {
  const double halfFov = std::numbers::pi / 8;  // 22.5°
  double r = 0.5 * double(length(b.diagonal()));
  Vec3f eye = b.center() + Vec3f{0, 0, float(r / std::tan(halfFov))};
  return Camera::perspective(Transform::translate(eye), float(2 * halfFov), width, height, 0,
                             kInfinity);
}

// ---------------------------------------------------------------------------------------------
// Rays
// ---------------------------------------------------------------------------------------------

std::vector<Ray> cameraRays(const Camera& camera, const BenchArgs& a, tbb::task_arena& arena) {
  std::vector<Ray> rays(size_t(a.width) * size_t(a.height) * size_t(a.spp));
  arena.execute([&] {
    tbb::parallel_for(0, a.height, [&](int y) {
      for (int x = 0; x < a.width; ++x) {
        size_t pixel = size_t(y) * size_t(a.width) + size_t(x);
        uint64_t key = pixelSampleKey(a.seed, pixel);
        for (int s = 0; s < a.spp; ++s) {
          Vec2f u = Sampler(key, uint32_t(s)).get2D();
          rays[pixel * size_t(a.spp) + size_t(s)] =
              camera.generateRay({float(x) + u.x, float(y) + u.y}, 0);
        }
      }
    });
  });
  return rays;
}

// One cosine-distributed occlusion ray per hit of `accel`, in camera-ray order. Chunks of fixed
// size are filled in parallel and joined in order, so the set and its order are deterministic.
std::vector<Ray> occlusionRays(const std::vector<Ray>& camera, const Accelerator& accel,
                               const GeometryScene& geometry, const BenchArgs& a,
                               tbb::task_arena& arena) {
  constexpr size_t kChunk = 1 << 16;
  size_t chunks = (camera.size() + kChunk - 1) / kChunk;
  std::vector<std::vector<Ray>> parts(chunks);
  SurfaceNeeds needs;
  needs.uvs = needs.colors = false;
  arena.execute([&] {
    tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
      size_t end = std::min(camera.size(), (c + 1) * kChunk);
      for (size_t i = c * kChunk; i < end; ++i) {
        Hit hit;
        if (!accel.closestHit(camera[i], &hit)) continue;
        SurfaceInteraction si = computeSurfaceInteraction(geometry, camera[i], hit, needs);
        size_t pixel = i / size_t(a.spp);
        // Dimensions 0-1 were the film jitter; 2-3 are this ray's direction.
        Sampler sampler(pixelSampleKey(a.seed, pixel), uint32_t(i % size_t(a.spp)), 2);
        Vec3f d = Frame::fromZ(si.ng).fromLocal(sampleCosineHemisphere(sampler.get2D()));
        parts[c].push_back(si.spawnRay(d, 0));
      }
    });
  });
  std::vector<Ray> rays;
  size_t n = 0;
  for (const auto& p : parts) n += p.size();
  rays.reserve(n);
  for (const auto& p : parts) rays.insert(rays.end(), p.begin(), p.end());
  return rays;
}

// Traces every ray with `trace` on the arena's threads and counts the true answers; returns
// the wall time. Per-chunk counters are summed at the end, so no counter is shared. A template,
// not std::function: the loop around a backend's call should cost what the bare loop's does.
template <class Trace>
double timedCount(const std::vector<Ray>& rays, tbb::task_arena& arena, const Trace& trace,
                  uint64_t* count) {
  Clock::time_point start, end;
  arena.execute([&] {
    start = Clock::now();
    *count = tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, rays.size(), 4096), uint64_t(0),
        [&](const tbb::blocked_range<size_t>& r, uint64_t n) {
          for (size_t i = r.begin(); i != r.end(); ++i) n += trace(rays[i]);
          return n;
        },
        std::plus<uint64_t>());
    end = Clock::now();
  });
  return seconds(start, end);
}

// A bare loop: RTCRayHit setup + rtcIntersect1 per ray, nothing else (pipeline_bench's loop).
double bareEmbreeSeconds(const std::vector<Ray>& rays, RTCScene rtc, tbb::task_arena& arena,
                         uint64_t* hits) {
  Clock::time_point start, end;
  arena.execute([&] {
    start = Clock::now();
    *hits = tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, rays.size(), 4096), uint64_t(0),
        [&](const tbb::blocked_range<size_t>& r, uint64_t count) {
          return count + bench::bareIntersect1(rtc, rays.data() + r.begin(), r.size());
        },
        std::plus<uint64_t>());
    end = Clock::now();
  });
  return seconds(start, end);
}

// The kd-tree's work over `rays`, in an untimed pass of its own (the counters slow it down).
KdTraversalCounts countTraversal(const KdTreeAccelerator& kd, const std::vector<Ray>& rays,
                                 bool any, tbb::task_arena& arena) {
  KdTraversalCounts total;
  arena.execute([&] {
    total = tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, rays.size(), 4096), KdTraversalCounts{},
        [&](const tbb::blocked_range<size_t>& r, KdTraversalCounts c) {
          for (size_t i = r.begin(); i != r.end(); ++i) kd.countedTrace(rays[i], any, &c);
          return c;
        },
        [](KdTraversalCounts a, const KdTraversalCounts& b) { return a += b; });
  });
  return total;
}

double mrays(size_t rays, double seconds) {
  return seconds > 0 ? double(rays) / seconds * 1e-6 : 0;
}

// ---------------------------------------------------------------------------------------------
// Output
// ---------------------------------------------------------------------------------------------

std::string resultsJson(const BenchArgs& a, size_t triangles, int threads, double bare,
                        const std::vector<BackendResult>& results) {
  nlohmann::ordered_json j;
  j["mesh"] = a.mesh;
  j["triangles"] = triangles;
  j["width"] = a.width;
  j["height"] = a.height;
  j["spp"] = a.spp;
  j["threads"] = threads;
  j["bare_embree_camera_mrays_per_second"] = bare;
  nlohmann::ordered_json backends = nlohmann::ordered_json::object();
  for (const BackendResult& r : results) {
    nlohmann::ordered_json b;
    b["build_seconds"] = r.buildSeconds;
    if (r.highQualityBuildSeconds > 0) b["high_quality_build_seconds"] = r.highQualityBuildSeconds;
    b["bytes"] = r.stats.bytes;
    b["camera_mrays_per_second"] = r.cameraMrays;
    b["occlusion_mrays_per_second"] = r.occlusionMrays;
    b["camera_hits"] = r.cameraHits;
    b["nodes"] = r.stats.nodes;
    b["leaves"] = r.stats.leaves;
    b["empty_leaves"] = r.stats.emptyLeaves;
    b["max_depth"] = r.stats.maxDepth;
    b["mean_prims_per_leaf"] = r.stats.meanPrimsPerLeaf;
    b["sah_cost"] = r.stats.sahCost;
    backends[r.name] = std::move(b);
  }
  j["backends"] = std::move(backends);
  return j.dump(2) + "\n";
}

void printTable(const BenchArgs& a, size_t triangles, int threads, size_t cameraRays,
                size_t occlusionRays, uint64_t referenceHits, double bare,
                const std::vector<BackendResult>& results) {
  std::printf("mesh:    %s (%zu triangles)\n", a.mesh.c_str(), triangles);
  std::printf(
      "rays:    %dx%d, %d spp, seed %llu: %zu camera rays (%llu hit), %zu occlusion rays;"
      " %d threads\n",
      a.width, a.height, a.spp, (unsigned long long)a.seed, cameraRays,
      (unsigned long long)referenceHits, occlusionRays, threads);
  std::printf("bare rtcIntersect1 on the camera rays: %.2f Mrays/s\n\n", bare);
  std::printf("%-14s %9s %12s %10s %10s %11s %9s %9s %9s %9s %6s %10s %9s\n", "backend", "build s",
              "bytes", "camera", "occlusion", "camera", "occluded", "nodes", "leaves", "empty",
              "depth", "prims/leaf", "SAH cost");
  std::printf("%-14s %9s %12s %10s %10s %11s %9s %9s %9s %9s %6s %10s %9s\n", "", "", "", "Mrays/s",
              "Mrays/s", "hits", "", "", "", "leaves", "", "", "");
  for (const BackendResult& r : results) {
    std::printf(
        "%-14s %9.3f %12llu %10.2f %10.2f %11llu %8.1f%% %9llu %9llu %9llu %6u %10.2f %9.2f\n",
        r.name.c_str(), r.buildSeconds, (unsigned long long)r.stats.bytes, r.cameraMrays,
        r.occlusionMrays, (unsigned long long)r.cameraHits,
        occlusionRays ? 100.0 * double(r.occluded) / double(occlusionRays) : 0.0,
        (unsigned long long)r.stats.nodes, (unsigned long long)r.stats.leaves,
        (unsigned long long)r.stats.emptyLeaves, r.stats.maxDepth, r.stats.meanPrimsPerLeaf,
        r.stats.sahCost);
  }
  for (const BackendResult& r : results)
    if (r.cameraHits != referenceHits)
      std::printf("note: %s hits %lld camera rays more than Embree\n", r.name.c_str(),
                  (long long)r.cameraHits - (long long)referenceHits);
  std::printf("(bytes and tree statistics are 0 where a backend does not expose them)\n");
  bool header = false;
  for (const BackendResult& r : results) {
    if (!r.cameraCounts) continue;
    if (!header) {
      std::printf("\ntraversal per ray: %-14s %8s %10s %8s %8s %10s\n", "", "nodes", "node lines",
                  "leaves", "empty", "prim tests");
      header = true;
    }
    for (const auto& [kind, c] :
         {std::pair{"camera", *r.cameraCounts}, std::pair{"occlusion", *r.occlusionCounts}}) {
      const double n = c.rays ? double(c.rays) : 1;
      std::printf("%-14s %-10s %8.2f %10.2f %8.2f %8.2f %10.2f\n", r.name.c_str(), kind,
                  double(c.nodes) / n, double(c.nodeLines) / n, double(c.leaves) / n,
                  double(c.emptyLeaves) / n, double(c.primTests) / n);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// The command
// ---------------------------------------------------------------------------------------------

void runBenchAccel(const BenchArgs& args) {
  std::vector<std::string> names;
  for (const std::string& n : args.accels.empty() ? acceleratorNames() : args.accels)
    if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
  bool progress = !args.quiet && isTerminal(stderr);
  auto note = [&](const std::string& what) {
    if (progress) std::fprintf(stderr, "glint: bench-accel: %s\n", what.c_str());
  };

  // Only the triangles are benchmarked: analytic objects a sidecar may add are left out, and
  // the reference backend is always Embree, whatever the sidecar asks for.
  SceneDescription desc;
  RenderScene scene;
  namingFile(args.mesh, "cannot build the scene", [&] {
    note("loading " + args.mesh);
    desc = loadScene(args.mesh);
    desc.objects.clear();
    if (args.subsample) subsampleTriangles(&desc, args.subsample);
    desc.render.accel = "embree";
    scene = buildRenderScene(desc);
  });
  if (scene.geometry().instancedTriangleCount() == 0)
    throw SceneError({args.mesh, ""}, "has no triangles to benchmark");
  if (!(length(scene.geometry().bounds().diagonal()) > 0))
    throw SceneError({args.mesh, ""}, "all its triangles are in one point");
  size_t triangles = scene.geometry().instancedTriangleCount();
  const auto* embree = dynamic_cast<const EmbreeAccelerator*>(&scene.accel());
  // desc.render.accel is "embree" above: anything else is a bug (main: "internal error").
  if (!embree) throw std::logic_error("the reference accelerator is not Embree");

  int threads =
      args.threads > 0 ? args.threads : std::max(1, int(std::thread::hardware_concurrency()));
  tbb::task_arena arena(threads);
  Camera camera = benchCamera(scene.geometry().bounds(), args.width, args.height);
  note("generating camera and occlusion rays");
  std::vector<Ray> camRays = cameraRays(camera, args, arena);
  std::vector<Ray> occRays = occlusionRays(camRays, *embree, scene.geometry(), args, arena);
  uint64_t referenceHits = occRays.size();

  note("bare rtcIntersect1 loop");
  uint64_t bareHits = 0;
  double bare =
      mrays(camRays.size(), bareEmbreeSeconds(camRays, embree->rtcScene(), arena, &bareHits));

  std::vector<BackendResult> results;
  // The names were checked by CLI11; a build that fails (a kd-tree too big) names the mesh.
  namingFile(args.mesh, "", [&] {
    for (const std::string& name : names) {
      BackendResult r;
      r.name = name;
      note("building " + name);
      Clock::time_point start = Clock::now();
      std::unique_ptr<Accelerator> accel = makeAccelerator(name, scene.geometry());
      r.buildSeconds = seconds(start, Clock::now());
      r.stats = accel->stats();
      if (name == "embree" && args.embreeHighQuality) {
        // The kd-tree build target is relative to Embree's high-quality build.
        note("building embree (high quality)");
        Clock::time_point hq = Clock::now();
        EmbreeAccelerator high(scene.geometry(), /*highQuality=*/true);
        r.highQualityBuildSeconds = seconds(hq, Clock::now());
      }
      note("tracing with " + name);
      const Accelerator& acc = *accel;
      double camSeconds = timedCount(
          camRays, arena,
          [&](const Ray& ray) {
            Hit hit;
            return acc.closestHit(ray, &hit);
          },
          &r.cameraHits);
      double occSeconds = timedCount(
          occRays, arena, [&](const Ray& ray) { return acc.anyHit(ray); }, &r.occluded);
      r.cameraMrays = mrays(camRays.size(), camSeconds);
      r.occlusionMrays = mrays(occRays.size(), occSeconds);
      const auto* kd = dynamic_cast<const KdTreeAccelerator*>(&acc);
      if (args.traversalCounts && kd) {
        note("counting the traversal of " + name);
        r.cameraCounts = countTraversal(*kd, camRays, false, arena);
        r.occlusionCounts = countTraversal(*kd, occRays, true, arena);
      }
      results.push_back(r);
    }
  });

  printTable(args, triangles, threads, camRays.size(), occRays.size(), referenceHits, bare,
             results);
  if (bareHits != referenceHits)
    std::printf("note: the bare loop hit %llu camera rays, glint's Embree backend %llu\n",
                (unsigned long long)bareHits, (unsigned long long)referenceHits);
  if (args.json)
    writeTextAtomically(*args.json, resultsJson(args, triangles, threads, bare, results));
}

}  // namespace

void addBenchAccelCommand(CLI::App& app) {
  auto args = std::make_shared<BenchArgs>();
  CLI::App* cmd = app.add_subcommand(
      "bench-accel", "compare the acceleration backends on one mesh: build time, size, ray rates");
  cmd->add_option("mesh", args->mesh, "a .ply/.obj mesh or a .gltf/.glb scene")->required();
  cmd->add_option("--accel", args->accels, "backends to compare, comma-separated (default: all)")
      ->delimiter(',')
      ->check(CLI::IsMember(acceleratorNames()));
  cmd->add_option("--width", args->width, "image width in pixels")
      ->capture_default_str()
      ->check(numberIn({.ge = 1}, true));
  cmd->add_option("--height", args->height, "image height in pixels")
      ->capture_default_str()
      ->check(numberIn({.ge = 1}, true));
  cmd->add_option("--spp", args->spp, "camera rays per pixel")
      ->capture_default_str()
      ->check(numberIn({.ge = 1}, true));
  cmd->add_option("--seed", args->seed, "sampler seed of the camera and occlusion rays")
      ->capture_default_str();
  cmd->add_option("--threads", args->threads, "worker threads (0 = all cores)")
      ->check(numberIn({.ge = 0}, true));
  cmd->add_option("--subsample", args->subsample,
                  "keep this many triangles, spread evenly over the mesh (build-time scaling)")
      ->check(numberIn({.ge = 1}, true));
  cmd->add_option("--json", args->json, "write the results as JSON");
  cmd->add_flag("-q,--quiet", args->quiet, "no progress messages on stderr");
  cmd->add_flag("--embree-high-quality", args->embreeHighQuality,
                "also time Embree's high-quality BVH build (adds high_quality_build_seconds to "
                "the embree entry of the JSON)");
  cmd->add_flag("--traversal-counts", args->traversalCounts,
                "kd-trees: also count nodes, leaves and primitive tests per ray, in an untimed "
                "pass (printed in the table only)");
  cmd->callback([args] { runBenchAccel(*args); });
}

}  // namespace glint::app
