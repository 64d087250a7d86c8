// glint benchmark — what analytic shapes and CSG cost per ray.
//
//  1. One sphere as Embree user geometry (glint's analytic sphere) against the same sphere
//     tessellated into triangles at several resolutions, each with its geometric error: the
//     user's "show what accuracy costs in time".
//  2. A CSG tree's cost against its leaf count (2, 4, 8, 16 leaves): a row of spheres, unioned
//     and subtracted from a slab.
//  3. The CSG reference scene (scenes/csg/csg_scene.json) rendered at 800x600: seconds per
//     frame, for the comparison with POV-Ray on the same scene.
// Usage: shapes_bench [--out results.json] [google benchmark flags]. Run from the repository
// root (the scene path is relative to it) with a Release build.
#include <benchmark/benchmark.h>

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

BENCHMARK(BM_AnalyticSphere)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AnalyticSphereTransformed)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TessellatedSphere)->Arg(8)->Arg(32)->Arg(128)->Arg(512)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CsgLeaves)->Arg(2)->Arg(4)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond);
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
