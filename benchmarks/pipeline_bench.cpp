// glint benchmark — is the pipeline around Embree thin?
//
// Renders the Stanford dragon (202,520 triangles) with the eyelight shader at 800x600, 16 spp,
// and compares the ray rate with a bare rtcIntersect1 loop over exactly the same camera rays,
// in the same process, on the same threads. Target: glint reaches >= 80% of the bare rate.
// Usage: pipeline_bench [--out results.json] [google benchmark flags]
// The dragon is read from $GLINT_ASSETS/stanford/dragon_vrip_res2.glb.
#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>

#include "bare_embree.h"
#include "bench_support.h"
#include "geometry/accel/embree_accel.h"
#include "renderer/filter.h"
#include "renderer/render.h"
#include "scenes/build.h"
#include "scenes/load.h"

namespace glint {
namespace {

constexpr int kWidth = 800, kHeight = 600, kSpp = 16;

std::string assetsDir() {
  if (const char* env = std::getenv("GLINT_ASSETS"); env && *env) return env;
  return GLINT_DEFAULT_ASSETS;
}

// The scene and its camera rays, built once and shared by both benchmarks.
struct Fixture {
  SceneDescription desc;
  RenderScene scene;
  std::vector<Ray> rays;  // every camera ray the render traces, in the same order
  int threads = int(std::thread::hardware_concurrency());

  Fixture() {
    std::string path = assetsDir() + "/stanford/dragon_vrip_res2.glb";
    if (!std::filesystem::exists(path)) {
      std::fprintf(
          stderr, "pipeline_bench: %s not found; set GLINT_ASSETS (see benchmarks/get_assets.sh)\n",
          path.c_str());
      std::exit(2);
    }
    desc = loadScene(path);
    MaterialDesc eyelight;
    eyelight.name = "eyelight";
    eyelight.type = MaterialType::Eyelight;
    for (MaterialDesc& m : desc.materials) m.type = MaterialType::Eyelight;
    desc.materials.push_back(eyelight);
    for (MeshDesc& m : desc.meshes)
      if (m.material < 0) m.material = int(desc.materials.size() - 1);
    desc.render.width = kWidth;
    desc.render.height = kHeight;
    desc.render.spp = kSpp;
    scene = buildRenderScene(desc);

    // Same sample addressing, filter and camera as renderer/render.cpp.
    PixelFilter filter(desc.render.filter);

    rays.resize(size_t(kWidth) * kHeight * kSpp);
    tbb::parallel_for(0, kHeight, [&](int y) {
      for (int x = 0; x < kWidth; ++x) {
        size_t pixel = size_t(y) * kWidth + size_t(x);
        for (int s = 0; s < kSpp; ++s) {
          Sampler sampler(pixelSampleKey(desc.render.seed, pixel), uint32_t(s));
          Vec2f o = filter.sampleOffset(sampler.get2D());
          rays[pixel * kSpp + size_t(s)] =
              scene.camera.generateRay({float(x) + 0.5f + o.x, float(y) + 0.5f + o.y}, 0);
        }
      }
    });
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

// A bare loop: RTCRayHit setup + rtcIntersect1 for each precomputed ray, nothing else.
uint64_t bareEmbreePass(const Fixture& f) {
  RTCScene rtc = static_cast<const EmbreeAccelerator&>(*f.scene.accel).rtcScene();
  tbb::task_arena arena(f.threads);
  uint64_t hits = 0;
  arena.execute([&] {
    hits = tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, f.rays.size(), 4096), uint64_t(0),
        [&](const tbb::blocked_range<size_t>& r, uint64_t count) {
          return count + bench::bareIntersect1(rtc, f.rays.data() + r.begin(), r.size());
        },
        std::plus<uint64_t>());
  });
  return hits;
}

// For transparency, the ceiling glint's packet path works against: the same rays, each pixel's
// 16 samples as one rtcIntersect16 packet with a coherent context, nothing else.
uint64_t bareEmbreePacketPass(const Fixture& f) {
  RTCScene rtc = static_cast<const EmbreeAccelerator&>(*f.scene.accel).rtcScene();
  static_assert(kSpp == 16, "one packet per pixel");
  tbb::task_arena arena(f.threads);
  uint64_t hits = 0;
  arena.execute([&] {
    hits = tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, f.rays.size() / kSpp, 256), uint64_t(0),
        [&](const tbb::blocked_range<size_t>& r, uint64_t count) {
          RTCIntersectContext context;
          rtcInitIntersectContext(&context);
          context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
          alignas(64) int valid[16];
          std::fill(valid, valid + 16, -1);
          for (size_t p = r.begin(); p != r.end(); ++p) {
            alignas(64) RTCRayHit16 rh;
            for (int i = 0; i < 16; ++i) {
              const Ray& ray = f.rays[p * kSpp + size_t(i)];
              rh.ray.org_x[i] = ray.o.x, rh.ray.org_y[i] = ray.o.y, rh.ray.org_z[i] = ray.o.z;
              rh.ray.dir_x[i] = ray.d.x, rh.ray.dir_y[i] = ray.d.y, rh.ray.dir_z[i] = ray.d.z;
              rh.ray.tnear[i] = ray.tMin, rh.ray.tfar[i] = ray.tMax, rh.ray.time[i] = 0;
              rh.ray.mask[i] = ~0u, rh.ray.id[i] = unsigned(i), rh.ray.flags[i] = 0;
              rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
              rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
            }
            rtcIntersect16(valid, rtc, &context, &rh);
            for (int i = 0; i < 16; ++i) count += rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
          }
          return count;
        },
        std::plus<uint64_t>());
  });
  return hits;
}

void BM_BareEmbreeIntersect16(benchmark::State& state) {
  Fixture& f = fixture();
  uint64_t hits = 0;
  for (auto _ : state) benchmark::DoNotOptimize(hits = bareEmbreePacketPass(f));
  state.counters["Mrays/s"] = benchmark::Counter(double(f.rays.size()) * 1e-6,
                                                 benchmark::Counter::kIsIterationInvariantRate);
  state.counters["hit_fraction"] = double(hits) / double(f.rays.size());
}

void BM_BareEmbreeIntersect1(benchmark::State& state) {
  Fixture& f = fixture();
  uint64_t hits = 0;
  const double cpu0 = bench::processCpuSeconds();
  for (auto _ : state) benchmark::DoNotOptimize(hits = bareEmbreePass(f));
  state.counters["Mrays/s"] = benchmark::Counter(double(f.rays.size()) * 1e-6,
                                                 benchmark::Counter::kIsIterationInvariantRate);
  state.counters["hit_fraction"] = double(hits) / double(f.rays.size());
  state.counters["cpu_ns/ray"] = (bench::processCpuSeconds() - cpu0) * 1e9 /
                                 (double(f.rays.size()) * double(state.iterations()));
}

// FNV-1a over the film's colour and alpha bits: a performance change must leave it unchanged.
uint64_t imageChecksum(const Film& film) {
  uint64_t h = 0xcbf29ce484222325ull;
  auto add = [&](const void* data, size_t bytes) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < bytes; ++i) h = (h ^ b[i]) * 0x100000001b3ull;
  };
  add(film.color.data(), film.color.size() * sizeof(film.color[0]));
  add(film.alpha.data(), film.alpha.size() * sizeof(film.alpha[0]));
  return h;
}

uint64_t gImageChecksum = 0;

// The CPU the numbers came from (Linux /proc/cpuinfo), for the recorded results.
std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) {
      size_t colon = line.find(':');
      if (colon != std::string::npos) return line.substr(colon + 2);
    }
  return "unknown";
}

void BM_GlintEyelightRender(benchmark::State& state) {
  Fixture& f = fixture();
  auto integrator = makeIntegrator(f.scene, f.desc.render);
  RenderOptions options;
  options.threads = f.threads;
  RenderStats stats;
  Film film;
  const double cpu0 = bench::processCpuSeconds();
  for (auto _ : state) {
    film = render(f.scene, *integrator, f.desc.render, options, &stats);
    benchmark::DoNotOptimize(film.color.data());
  }
  // Outside the timed loop: hashing the film byte by byte took 3% of a render's time.
  gImageChecksum = imageChecksum(film);
  state.counters["Mrays/s"] = benchmark::Counter(double(stats.rays.total()) * 1e-6,
                                                 benchmark::Counter::kIsIterationInvariantRate);
  state.counters["cpu_ns/ray"] = (bench::processCpuSeconds() - cpu0) * 1e9 /
                                 (double(stats.rays.total()) * double(state.iterations()));
}

BENCHMARK(BM_BareEmbreeIntersect1)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);
BENCHMARK(BM_BareEmbreeIntersect16)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);
BENCHMARK(BM_GlintEyelightRender)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);

}  // namespace
}  // namespace glint

int main(int argc, char** argv) {
  std::string out = glint::bench::initialize(argc, argv);
  glint::bench::CounterReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  double bare = reporter.value("BM_BareEmbreeIntersect1", "Mrays/s");
  double glint = reporter.value("BM_GlintEyelightRender", "Mrays/s");
  double packet = reporter.value("BM_BareEmbreeIntersect16", "Mrays/s");  // 0 when filtered out
  if (bare <= 0 || glint <= 0) {
    std::fprintf(stderr, "pipeline_bench: missing results\n");
    return 1;
  }
  double ratio = glint / bare;
  // The same comparison by CPU time (all threads): it holds when other work shares the cores,
  // which the wall-clock ratio does not (the benchmarks run at different moments).
  const double cpuBare = reporter.value("BM_BareEmbreeIntersect1", "cpu_ns/ray");
  const double cpuGlint = reporter.value("BM_GlintEyelightRender", "cpu_ns/ray");
  const double cpuRatio = cpuGlint > 0 ? cpuBare / cpuGlint : 0.0;
  std::printf(
      "\nbare rtcIntersect1:  %.2f Mrays/s\nbare rtcIntersect16: %.2f Mrays/s (packet ceiling)\n"
      "glint eyelight:      %.2f Mrays/s\n"
      "ratio:               %.3f of rtcIntersect1 (target >= 0.80) %s; %.3f of rtcIntersect16\n"
      "CPU time per ray:    bare %.1f ns, glint %.1f ns: ratio %.3f\n"
      "image checksum:      %016llx\n",
      bare, packet, glint, ratio, ratio >= 0.8 ? "PASS" : "FAIL", packet > 0 ? glint / packet : 0.0,
      cpuBare, cpuGlint, cpuRatio, static_cast<unsigned long long>(glint::gImageChecksum));
  if (!out.empty()) {
    std::ofstream f(out);
    f << "{\n  \"scene\": \"stanford/dragon_vrip_res2.glb\",\n  \"width\": " << glint::kWidth
      << ",\n  \"height\": " << glint::kHeight << ",\n  \"spp\": " << glint::kSpp
      << ",\n  \"threads\": " << glint::fixture().threads
      << ",\n  \"bare_embree_mrays_per_second\": " << bare
      << ",\n  \"bare_embree_packet16_mrays_per_second\": " << packet
      << ",\n  \"glint_eyelight_mrays_per_second\": " << glint << ",\n  \"ratio\": " << ratio
      << ",\n  \"cpu_ns_per_ray_bare\": " << cpuBare << ",\n  \"cpu_ns_per_ray_glint\": " << cpuGlint
      << ",\n  \"cpu_ratio\": " << cpuRatio << ",\n  \"ratio_to_packet16\": " << (packet > 0 ? glint / packet : 0.0) << ",\n  \"cpu\": \""
      << glint::cpuModel() << "\""
      << ",\n  \"target\": 0.8\n}\n";
  }
  return ratio >= 0.8 ? 0 : 1;
}
