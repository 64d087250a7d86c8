// glint benchmark — what a medium costs per unit optical depth.
//
// A slab of medium (a box region 8 × 6 wide, 1 deep along the view) fills the view in front of
// a grey wall, lit by a point light; the Whitted integrator with single scattering renders it
// at 96 × 72, 2 spp. The slab's optical depth along the view axis is tau in {0.5, 1, 2, 4, 8}
// (σ_t = tau per unit length, albedo 0.8, g = 0.3), for a homogeneous medium and a noise
// density (fBm, 4 octaves; its coefficients are scaled by the same tau, so tau is the optical
// depth at density 1 and the mean density is about 1/2), under both volume estimators:
//   march — fixed steps of the default length (1/64 of the region's diagonal) with a shadow
//           ray per step: cost set by the slab's length, not by tau;
//   track — ratio tracking with a light sample per tentative collision: for the homogeneous
//           medium one exponentially distributed sample and closed-form transmittance, for the
//           noise density as many collisions as the majorant's optical depth.
// The summary prints ms per image and ms per million camera rays per unit optical depth.
// Usage: volume_bench [--out results.json] [google benchmark flags]
#include <benchmark/benchmark.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <thread>

#include "bench_support.h"
#include "renderer/render.h"
#include "scenes/build.h"
#include "scenes/sidecar.h"

namespace glint {
namespace {

constexpr int kWidth = 96, kHeight = 72, kSpp = 2;
const double kTaus[] = {0.5, 1, 2, 4, 8};
const char* kEstimators[] = {"march", "track"};
const char* kDensities[] = {"homogeneous", "noise"};

std::string sceneJson(double tau, const std::string& estimator, bool noise) {
  const std::string sa = std::to_string(0.2 * tau), ss = std::to_string(0.8 * tau);
  return R"({"render": {"width": )" + std::to_string(kWidth) + R"(, "height": )" +
         std::to_string(kHeight) + R"(, "spp": )" + std::to_string(kSpp) +
         R"(, "camera": "c",
       "integrator": {"type": "whitted", "volume": "single", "volume_estimator": ")" +
         estimator + R"("}},
    "cameras": [{"name": "c", "position": [0, 0, 5], "look_at": [0, 0, 0], "yfov_degrees": 40}],
    "lights": [{"type": "point", "position": [2, 3, 3], "intensity": 30}],
    "materials": [{"name": "wall", "type": "lambert", "diffuse": [0.5, 0.5, 0.5]}],
    "objects": [{"type": "plane", "point": [0, 0, -2], "normal": [0, 0, 1], "material": "wall"}],
    "media": [{"name": "slab", "region": {"type": "box", "min": [-4, -3, -0.5], "max": [4, 3, 0.5]},
               "sigma_a": )" +
         sa + R"(, "sigma_s": )" + ss + R"(, "g": 0.3)" +
         (noise ? R"(, "density": {"type": "noise", "scale": 2, "octaves": 4})" : "") + "}]}";
}

void BM_Volume(benchmark::State& state, double tau, std::string estimator, bool noise) {
  SceneDescription desc;
  desc.file = "volume_bench.json";
  applySceneJsonText(sceneJson(tau, estimator, noise), desc.file, SceneJsonKind::Scene, &desc);
  RenderScene scene = buildRenderScene(desc);
  auto integrator = makeIntegrator(scene, desc.render);
  RenderOptions options;
  options.threads = int(std::thread::hardware_concurrency());
  RenderStats stats;
  for (auto _ : state) {
    Film film = render(scene, *integrator, desc.render, options, &stats);
    benchmark::DoNotOptimize(film.color.data());
  }
  state.counters["ms_per_image"] = benchmark::Counter(
      1e-3, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["shadow_rays_per_camera_ray"] =
      double(stats.rays.shadow) / double(stats.rays.camera);
}

void registerAll() {
  for (const char* density : kDensities)
    for (const char* estimator : kEstimators)
      for (double tau : kTaus) {
        const std::string name = std::string("BM_Volume/") + density + "/" + estimator +
                                 "/tau:" + std::to_string(tau).substr(0, 3);
        const bool noise = std::string(density) == "noise";
        benchmark::RegisterBenchmark(
            name.c_str(), [=](benchmark::State& s) { BM_Volume(s, tau, estimator, noise); })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime()
            ->MinTime(0.5);
      }
}

}  // namespace
}  // namespace glint

int main(int argc, char** argv) {
  std::string out = glint::bench::initialize(argc, argv);
  glint::registerAll();
  glint::bench::CounterReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  const double mrays = double(glint::kWidth) * glint::kHeight * glint::kSpp * 1e-6;
  std::printf("\n%-12s %-6s %5s %10s %14s %18s %12s\n", "density", "est.", "tau", "ms/image",
              "ms/Mray", "ms/Mray per tau", "shadow/ray");
  std::string rows;
  for (const char* density : glint::kDensities)
    for (const char* estimator : glint::kEstimators)
      for (double tau : glint::kTaus) {
        const std::string name = std::string("BM_Volume/") + density + "/" + estimator +
                                 "/tau:" + std::to_string(tau).substr(0, 3);
        const double ms = reporter.value(name, "ms_per_image");
        if (ms <= 0) continue;
        const double shadow = reporter.value(name, "shadow_rays_per_camera_ray");
        std::printf("%-12s %-6s %5.1f %10.2f %14.1f %18.1f %12.2f\n", density, estimator, tau, ms,
                    ms / mrays, ms / mrays / tau, shadow);
        rows += std::string(rows.empty() ? "" : ",\n") + "    {\"density\": \"" + density +
                "\", \"estimator\": \"" + estimator + "\", \"tau\": " + std::to_string(tau) +
                ", \"ms_per_image\": " + std::to_string(ms) +
                ", \"ms_per_mray\": " + std::to_string(ms / mrays) +
                ", \"ms_per_mray_per_tau\": " + std::to_string(ms / mrays / tau) +
                ", \"shadow_rays_per_camera_ray\": " + std::to_string(shadow) + "}";
      }
  if (!out.empty()) {
    std::ofstream f(out);
    f << "{\n  \"width\": " << glint::kWidth << ",\n  \"height\": " << glint::kHeight
      << ",\n  \"spp\": " << glint::kSpp
      << ",\n  \"threads\": " << std::thread::hardware_concurrency() << ",\n  \"runs\": [\n"
      << rows << "\n  ]\n}\n";
  }
  return 0;
}
