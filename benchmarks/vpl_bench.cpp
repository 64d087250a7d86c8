// glint benchmark — instant radiosity: VPL count against time and error. The Cornell-style box
// of tests/reference_images/scenes/cornell_ir.json (quad light, Lambert walls, a block and a ball)
// at 32x32, 16 spp, max depth 6, rendered with 16, 64, 256 and 1024 light paths, unclamped, with
// the G bound 100 the reference scene uses, and with a tight bound of 10 (the box is 2 wide:
// 10 is below 1 / (0.2 x size)^2, so its bias shows). Each run's time includes tracing the light
// paths. Error: RMSE of the green channel and the relative bias of the image mean, against the
// path tracer at 4096 spp on the same box (its own noise: RMSE about 0.0013). The path tracer
// itself at 16 to 1024 spp gives the other side: its time for the same error. No target; the
// table at the end is the record.
// Usage: vpl_bench [--out results.json] [google benchmark flags]
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "bench_support.h"
#include "renderer/instant_radiosity.h"
#include "renderer/render.h"
#include "scenes/build.h"
#include "scenes/sidecar.h"

namespace glint {
namespace {

constexpr int kSize = 32, kSpp = 16, kReferenceSpp = 4096;

// The box of tests/reference_images/scenes/cornell_ir.json, rendered smaller and with the light
// paths and clamp each run asks for.
std::string boxJson() {
  const std::string path =
      std::string(GLINT_SOURCE_DIR) + "/tests/reference_images/scenes/cornell_ir.json";
  std::ifstream in(path);
  if (!in) {
    std::fprintf(stderr, "vpl_bench: cannot read %s\n", path.c_str());
    std::exit(1);
  }
  return std::string(std::istreambuf_iterator<char>(in), {});
}

struct Fixture {
  SceneDescription desc;
  RenderScene scene;
  Film reference;
  int threads = int(std::thread::hardware_concurrency());

  Fixture() {
    desc.file = "cornell_ir.json";
    applySceneJsonText(boxJson(), desc.file, SceneJsonKind::Scene, &desc);
    desc.render.width = desc.render.height = kSize;
    desc.render.spp = kSpp;
    scene = buildRenderScene(desc);
    RenderSettings path = desc.render;
    path.integrator.type = "path";
    path.spp = kReferenceSpp;
    path.seed = 11;
    reference = render(scene, *makeIntegrator(scene, path), path, {.threads = threads}, nullptr);
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

struct Error {
  double rmse = 0, bias = 0;  // RMSE (green), relative bias of the image mean
};
Error compare(const Film& f, const Film& ref) {
  double s = 0, sum = 0, sumRef = 0;
  for (size_t i = 0; i < f.color.size(); ++i) {
    const double d = double(f.color[i].y) - ref.color[i].y;
    s += d * d, sum += f.color[i].y, sumRef += ref.color[i].y;
  }
  return {std::sqrt(s / double(f.color.size())), sum / sumRef - 1};
}

// One row of the summary table: instant radiosity (paths > 0) or the path tracer (paths = 0).
struct Row {
  int spp = 0, paths = 0, clamp = 0;
  size_t vpls = 0;
  double seconds = 0;
  Error error;
};
std::vector<Row>& rows() {
  static std::vector<Row> r;
  return r;
}

// state.range(0): light paths; state.range(1): G bound (0 = none).
void BM_InstantRadiosity(benchmark::State& state) {
  Fixture& fx = fixture();
  RenderSettings settings = fx.desc.render;
  settings.integrator.vplPaths = int(state.range(0));
  settings.integrator.vplClamp = float(state.range(1));
  Film film;
  size_t vpls = 0;
  RenderStats stats;
  double seconds = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    InstantRadiosityIntegrator ir(fx.scene, settings.integrator, settings.seed);
    vpls = ir.vpls().size();
    film = render(fx.scene, ir, settings, {.threads = fx.threads}, &stats);
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  const Error e = compare(film, fx.reference);
  rows().push_back({settings.spp, int(state.range(0)), int(state.range(1)), vpls, seconds, e});
  state.counters["vpls"] = double(vpls);
  state.counters["rmse"] = e.rmse;
  state.counters["bias"] = e.bias;
  state.counters["Mshadow"] = double(stats.rays.shadow) * 1e-6;
}
BENCHMARK(BM_InstantRadiosity)
    ->ArgsProduct({{16, 64, 256, 1024}, {0, 10, 100}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->UseRealTime();

// The path tracer from the IR runs' spp up, for the same error at what time.
void BM_PathTracer(benchmark::State& state) {
  Fixture& fx = fixture();
  RenderSettings settings = fx.desc.render;
  settings.integrator.type = "path";
  settings.spp = int(state.range(0));
  Film film;
  double seconds = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    film = render(fx.scene, *makeIntegrator(fx.scene, settings), settings, {.threads = fx.threads},
                  nullptr);
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  const Error e = compare(film, fx.reference);
  rows().push_back({settings.spp, 0, 0, 0, seconds, e});
  state.counters["rmse"] = e.rmse;
  state.counters["bias"] = e.bias;
}
BENCHMARK(BM_PathTracer)
    ->Arg(kSpp)
    ->Arg(4 * kSpp)
    ->Arg(16 * kSpp)
    ->Arg(64 * kSpp)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->UseRealTime();

}  // namespace
}  // namespace glint

int main(int argc, char** argv) {
  const std::string out = glint::bench::initialize(argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  std::printf(
      "\nInstant radiosity and the path tracer on the Cornell box, %dx%d, against the path "
      "tracer at %d spp\n",
      glint::kSize, glint::kSize, glint::kReferenceSpp);
  std::printf("%-18s %6s %8s %8s %8s %10s %10s %10s\n", "integrator", "spp", "paths", "clamp",
              "VPLs", "seconds", "RMSE", "mean bias");
  for (const glint::Row& r : glint::rows())
    std::printf("%-18s %6d %8d %8d %8zu %10.3f %10.4f %+9.2f%%\n",
                r.paths ? "instant-radiosity" : "path", r.spp, r.paths, r.clamp, r.vpls, r.seconds,
                r.error.rmse, 100 * r.error.bias);
  if (!out.empty()) {
    std::ofstream f(out);
    f << "[\n";
    for (size_t i = 0; i < glint::rows().size(); ++i) {
      const glint::Row& r = glint::rows()[i];
      f << "  {\"integrator\": \"" << (r.paths ? "instant-radiosity" : "path")
        << "\", \"spp\": " << r.spp << ", \"paths\": " << r.paths << ", \"clamp\": " << r.clamp
        << ", \"vpls\": " << r.vpls << ", \"seconds\": " << r.seconds
        << ", \"rmse\": " << r.error.rmse << ", \"bias\": " << r.error.bias << "}"
        << (i + 1 < glint::rows().size() ? "," : "") << "\n";
    }
    f << "]\n";
  }
  benchmark::Shutdown();
  return 0;
}
