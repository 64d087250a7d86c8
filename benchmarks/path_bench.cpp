// glint benchmark — path tracer throughput: the Stanford dragon (202,520 triangles, Lambert
// 0.7) on the floor of a closed white box (Lambert 0.8, analytic box seen from inside) lit by a
// point light and an emitting ceiling patch, 320x240, 16 spp, max depth 5, Russian roulette
// from bounce 3, all hardware threads. Reports rays per second (camera + secondary + shadow)
// and paths per second; there is no target, only the record in benchmarks/results.
// Usage: path_bench [--out results.json] [google benchmark flags]
// The dragon is read from $GLINT_ASSETS/stanford/dragon_vrip_res2.glb.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "bench_support.h"
#include "geometry/shapes/box.h"
#include "geometry/shapes/quad.h"
#include "renderer/render.h"
#include "scenes/build.h"
#include "scenes/load.h"

namespace glint {
namespace {

constexpr int kWidth = 320, kHeight = 240, kSpp = 16, kMaxDepth = 5;

std::string assetsDir() {
  if (const char* env = std::getenv("GLINT_ASSETS"); env && *env) return env;
  return GLINT_DEFAULT_ASSETS;
}

struct Fixture {
  SceneDescription desc;
  RenderScene scene;
  int threads = int(std::thread::hardware_concurrency());

  Fixture() {
    std::string path = assetsDir() + "/stanford/dragon_vrip_res2.glb";
    if (!std::filesystem::exists(path)) {
      std::fprintf(stderr,
                   "path_bench: %s not found; set GLINT_ASSETS (see benchmarks/get_assets.sh)\n",
                   path.c_str());
      std::exit(2);
    }
    desc = loadScene(path);
    MaterialDesc dragon;
    dragon.name = "dragon";
    dragon.type = MaterialType::Lambert;
    dragon.baseColor = {0.7f, 0.7f, 0.7f};
    desc.materials = {dragon};
    for (MeshDesc& m : desc.meshes) m.material = 0;
    for (InstanceDesc& i : desc.instances) i.material = -1;
    // The dragon's extent (built once without the box) sizes the room around it.
    const Bounds3f b = buildRenderScene(desc).geometry().bounds();
    const Vec3f size = b.upper - b.lower, centre = (b.lower + b.upper) * 0.5f;
    const float r = std::max({size.x, size.y, size.z});

    MaterialDesc wall = dragon;
    wall.name = "wall";
    wall.baseColor = {0.8f, 0.8f, 0.8f};
    MaterialDesc lamp = wall;
    lamp.name = "lamp";
    lamp.emissive = {8, 8, 8};
    desc.materials.push_back(wall);
    desc.materials.push_back(lamp);
    ObjectDesc room;
    room.name = "room";
    const Vec3f roomUpper{centre.x + r, b.lower.y + 1.5f * r, centre.z + r};
    room.shape = std::make_shared<Box>(Vec3f{centre.x - r, b.lower.y, centre.z - r}, roomUpper);
    room.material = 1;
    desc.objects.push_back(room);
    ObjectDesc patch;
    patch.name = "lamp";
    const float ceiling = roomUpper.y - 1e-3f * r;
    patch.shape = std::make_shared<Quad>(Vec3f{centre.x - 0.25f * r, ceiling, centre.z - 0.25f * r},
                                         Vec3f{0.5f * r, 0, 0}, Vec3f{0, 0, 0.5f * r});
    patch.material = 2;
    desc.objects.push_back(patch);
    LightDesc bulb;
    bulb.name = "bulb";
    bulb.intensity = 0.5f * r * r;
    bulb.worldFromLight =
        Transform::translate({centre.x + 0.5f * r, b.lower.y + r, centre.z + 0.5f * r});
    desc.lights = {bulb};
    CameraDesc cam;
    cam.name = "inside";
    cam.yfov = 0.9f;
    cam.worldFromCamera = Transform::lookAt({centre.x, b.lower.y + 0.6f * r, centre.z + 0.95f * r},
                                            centre, {0, 1, 0});
    desc.cameras = {cam};
    desc.render.camera = "inside";
    desc.render.width = kWidth;
    desc.render.height = kHeight;
    desc.render.spp = kSpp;
    desc.render.integrator.type = "path";
    desc.render.integrator.maxDepth = kMaxDepth;
    desc.render.integrator.rrDepth = 3;
    scene = buildRenderScene(desc);
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

RenderStats gStats;

void BM_PathTracerDragonInABox(benchmark::State& state) {
  Fixture& f = fixture();
  auto integrator = makeIntegrator(f.scene, f.desc.render);
  RenderOptions options;
  options.threads = f.threads;
  RenderStats stats;
  uint64_t rays = 0;
  for (auto _ : state) {
    Film film = render(f.scene, *integrator, f.desc.render, options, &stats);
    benchmark::DoNotOptimize(film.color.data());
    rays = stats.rays.total();
  }
  gStats = stats;
  state.counters["Mrays/s"] =
      benchmark::Counter(double(rays) * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["Mpaths/s"] = benchmark::Counter(double(kWidth) * kHeight * kSpp * 1e-6,
                                                  benchmark::Counter::kIsIterationInvariantRate);
  state.counters["rays/path"] = double(rays) / (double(kWidth) * kHeight * kSpp);
}

BENCHMARK(BM_PathTracerDragonInABox)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);

}  // namespace
}  // namespace glint

int main(int argc, char** argv) {
  std::string out = glint::bench::initialize(argc, argv);
  glint::bench::CounterReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  const double mrays = reporter.value("BM_PathTracerDragonInABox", "Mrays/s");
  const double mpaths = reporter.value("BM_PathTracerDragonInABox", "Mpaths/s");
  if (mrays <= 0) {
    std::fprintf(stderr, "path_bench: missing results\n");
    return 1;
  }
  const glint::RenderStats& s = glint::gStats;
  std::printf(
      "\npath tracer, dragon in a box: %.2f Mrays/s, %.3f Mpaths/s (%d threads)\n"
      "rays per frame: camera %llu, secondary %llu, shadow %llu; non-finite samples %llu\n",
      mrays, mpaths, glint::fixture().threads, static_cast<unsigned long long>(s.rays.camera),
      static_cast<unsigned long long>(s.rays.secondary),
      static_cast<unsigned long long>(s.rays.shadow),
      static_cast<unsigned long long>(s.nonfiniteSamples));
  if (!out.empty()) {
    std::ofstream f(out);
    f << "{\n  \"scene\": \"stanford/dragon_vrip_res2.glb in a closed Lambert box\",\n"
      << "  \"width\": " << glint::kWidth << ",\n  \"height\": " << glint::kHeight
      << ",\n  \"spp\": " << glint::kSpp << ",\n  \"max_depth\": " << glint::kMaxDepth
      << ",\n  \"threads\": " << glint::fixture().threads
      << ",\n  \"path_mrays_per_second\": " << mrays
      << ",\n  \"path_mpaths_per_second\": " << mpaths << ",\n  \"camera_rays\": " << s.rays.camera
      << ",\n  \"secondary_rays\": " << s.rays.secondary
      << ",\n  \"shadow_rays\": " << s.rays.shadow
      << ",\n  \"nonfinite_samples\": " << s.nonfiniteSamples << "\n}\n";
  }
  return 0;
}
