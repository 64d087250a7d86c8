// glint benchmark — does a plain scene pay for the features it does not use, and what does each
// used effect cost?
//
// 1. Unused features. The issue's target: a plain scene rendered by the full renderer costs no
//    more than 3% over the same scene with every unused feature compiled out. glint has no
//    build switches for features (it decides at setup from SceneFeatures, see
//    renderer/features.h), so "compiled out" is measured against the simplest loop that
//    computes the same image from the same parts: BM_MinimalLoop is a hand-written Whitted
//    for opaque Lambert surfaces and point lights — the static pinhole ray, the same sample
//    addressing and filter, the same accelerator (closestHits in packets of 16, anyHit for
//    shadows), computeSurfaceInteraction, Material::eval and Light::sampleLi, a plain mean per
//    pixel — with no feature test anywhere, no AOVs, no variance, no ray counters. Against it,
//    `render()` with the Whitted integrator from makeIntegrator on the same scene; the two
//    images must have the same mean (printed). BM_PlainVsMinimal renders them in alternating
//    pairs and prints the median of the per-pair time ratios against the 1.03 target.
//    Limits: the ratio is an upper bound on what unused features cost, since the full renderer
//    also does work the minimal loop skips that is not a feature (per-pixel variance, ray
//    counters, NaN/Inf checks, tiles). On a shared machine the pairing cancels slow load drifts but
//    not a neighbour's burst within one pair; the median over pairs damps those.
// 2. Used effects. The same scene with one effect switched on at a time (depth of field,
//    motion blur, a procedural texture, glass, a quad area light, a projective light with a
//    clouds slide, fog in a box around the objects marched at the default step with single
//    scattering), each at the same resolution and spp; the summary prints each one's time
//    over the full renderer's time on the plain scene.
//    At equal spp, not equal quality: lens and motion need more samples for the same noise
//    (effects_cost.py measures that).
// Usage: features_bench [--out results.json] [google benchmark flags]
#include <benchmark/benchmark.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "bench_support.h"
#include "geometry/interaction.h"
#include "renderer/filter.h"
#include "renderer/render.h"
#include "scenes/build.h"
#include "scenes/sidecar.h"

namespace glint {
namespace {

constexpr int kWidth = 320, kHeight = 240, kSpp = 4;

// A plain scene: analytic spheres and a box on a plane, two point lights, Whitted.
// `camera`, `extraObjects`, `floor`, `lights`, `extra` let a variant switch on one effect.
struct Variant {
  std::string camera = R"("position": [0, 2, 7], "look_at": [0, 0.8, 0])";
  std::string floor = R"("diffuse": [0.6, 0.6, 0.6])";
  std::string ball = R"("type": "lambert", "diffuse": [0.7, 0.2, 0.1])";
  std::string ballAnimation;
  std::string lights = R"({"type": "point", "position": [3, 5, 4], "intensity": 60},
                          {"type": "point", "position": [-4, 3, 2], "intensity": 15})";
  std::string extra;  // more top-level sections (textures, media)
};

std::string sceneJson(const Variant& v) {
  return R"({"render": {"width": )" + std::to_string(kWidth) + R"(, "height": )" +
         std::to_string(kHeight) + R"(, "spp": )" + std::to_string(kSpp) +
         R"(, "camera": "c", "integrator": {"type": "whitted", "max_depth": 4}},
    "cameras": [{"name": "c", )" +
         v.camera + R"(}],
    "lights": [)" +
         v.lights + R"(],
    "materials": [{"name": "floor", "type": "lambert", )" +
         v.floor + R"(},
                  {"name": "ball", )" +
         v.ball + R"(},
                  {"name": "grey", "type": "lambert", "diffuse": [0.5, 0.5, 0.5]}],
    "objects": [{"type": "plane", "material": "floor"},
                {"type": "sphere", "center": [0, 1, 0], "radius": 1, "material": "ball")" +
         v.ballAnimation + R"(},
                {"type": "sphere", "center": [-2, 0.5, 1], "radius": 0.5, "material": "grey"},
                {"type": "box", "min": [1.5, 0, -1], "max": [2.5, 1.5, 0], "material": "grey"}])" +
         v.extra + "}";
}

struct Built {
  SceneDescription desc;
  RenderScene scene;
};

Built build(const Variant& v) {
  Built b;
  b.desc.file = "features_bench.json";
  applySceneJsonText(sceneJson(v), b.desc.file, SceneJsonKind::Scene, &b.desc);
  b.scene = buildRenderScene(b.desc);
  return b;
}

int threads() { return int(std::thread::hardware_concurrency()); }

// ---------------------------------------------------------------------------------------------
// The full renderer
// ---------------------------------------------------------------------------------------------

void renderBenchmark(benchmark::State& state, const Variant& v) {
  Built b = build(v);
  auto integrator = makeIntegrator(b.scene, b.desc.render);
  RenderOptions options;
  options.threads = threads();
  RenderStats stats;
  for (auto _ : state) {
    Film film = render(b.scene, *integrator, b.desc.render, options, &stats);
    benchmark::DoNotOptimize(film.color.data());
  }
  state.counters["ms_per_image"] = benchmark::Counter(
      1e-3, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.SetLabel(std::to_string(b.scene.features.names().size()) + " features");
}

// ---------------------------------------------------------------------------------------------
// The minimal loop: Whitted for opaque Lambert surfaces and point lights, nothing else
// ---------------------------------------------------------------------------------------------

double gMinimalMean = 0, gPlainMean = 0;  // image means: the two must agree

Film minimalRender(const RenderScene& scene, const RenderSettings& settings) {
  Film film(kWidth, kHeight, false);
  PixelFilter filter(settings.filter);
  SurfaceNeeds needs;
  needs.uvs = needs.colors = false;
  tbb::task_arena arena(threads());
  arena.execute([&] {
    tbb::parallel_for(0, kHeight, [&](int y) {
      for (int x = 0; x < kWidth; ++x) {
        const size_t index = film.index(x, y);
        const uint64_t key = pixelSampleKey(settings.seed, index);
        Ray rays[kSpp];
        Hit hits[kSpp];
        for (int s = 0; s < kSpp; ++s) {
          Sampler sampler(key, uint32_t(s), kFilmDimension);
          const Vec2f o = filter.sampleOffset(sampler.get2D());
          rays[s] = scene.camera.pinholeRay({float(x) + 0.5f + o.x, float(y) + 0.5f + o.y}, 0);
        }
        scene.accel->closestHits(rays, hits, kSpp);
        Rgb sum;
        for (int s = 0; s < kSpp; ++s) {
          if (hits[s].instance == Hit::kInvalid) continue;
          const SurfaceInteraction si =
              computeSurfaceInteraction(scene.geometry, rays[s], hits[s], needs);
          const Material& material = *scene.materials[scene.materialIndex(hits[s])];
          const LightSampleContext ctx(si, 0);
          for (const auto& light : scene.lights) {
            const std::optional<LightSample> ls = light->sampleLi(ctx, {0.5f, 0.5f});
            if (!ls) continue;
            const Rgb f = material.eval(si, ls->wi);
            if (!(maxComponent(f) > 0)) continue;
            if (scene.accel->anyHit(shadowRay(ctx, *ls))) continue;
            sum += f * ls->L * std::abs(dot(si.ns, ls->wi));
          }
        }
        film.color[index] = sum / float(kSpp);
      }
    });
  });
  return film;
}

double imageMean(const Film& film) {
  double m = 0;
  for (const Rgb& c : film.color) m += c.y;
  return m / double(film.color.size());
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

// The minimal loop and the full renderer in alternation (which goes first alternates too), so
// that a change in the machine's load between them hits both alike; the ratio is the median
// of the per-pair ratios.
void BM_PlainVsMinimal(benchmark::State& state) {
  Built b = build(Variant{});
  auto integrator = makeIntegrator(b.scene, b.desc.render);
  RenderOptions options;
  options.threads = threads();
  RenderStats stats;
  std::vector<double> minimal, plain, ratio;
  auto timed = [](auto&& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  };
  for (auto _ : state) {
    double m = 0, p = 0;
    auto runMinimal = [&] {
      m = timed([&] {
        Film film = minimalRender(b.scene, b.desc.render);
        benchmark::DoNotOptimize(film.color.data());
        gMinimalMean = imageMean(film);
      });
    };
    auto runPlain = [&] {
      p = timed([&] {
        Film film = render(b.scene, *integrator, b.desc.render, options, &stats);
        benchmark::DoNotOptimize(film.color.data());
        gPlainMean = imageMean(film);
      });
    };
    if (minimal.size() % 2) {
      runMinimal();
      runPlain();
    } else {
      runPlain();
      runMinimal();
    }
    minimal.push_back(m), plain.push_back(p), ratio.push_back(p / m);
  }
  state.counters["minimal_ms"] = median(minimal);
  state.counters["plain_ms"] = median(plain);
  state.counters["ratio"] = median(ratio);
  state.counters["pairs"] = double(ratio.size());
  state.SetLabel(std::to_string(b.scene.features.names().size()) + " features");
}

// ---------------------------------------------------------------------------------------------
// One effect at a time
// ---------------------------------------------------------------------------------------------

Variant lens() {
  Variant v;
  v.camera += R"(, "aperture": 0.08, "focus_distance": 7)";
  return v;
}
Variant motion() {
  Variant v;
  v.camera += R"(, "shutter": [0, 0.5])";
  v.ballAnimation =
      R"(, "animation": {"translation": {"keys": [[0, [0, 0, 0]], [1, [0.5, 0, 0]]]}})";
  return v;
}
Variant texture() {
  Variant v;
  v.floor = R"("diffuse": "marble")";
  v.extra = R"(, "textures": [{"name": "marble", "type": "marble", "mapping": {"scale": 2}}])";
  return v;
}
Variant glass() {
  Variant v;
  v.ball = R"("type": "glass", "ior": 1.5)";
  return v;
}
Variant areaLight() {
  Variant v;
  v.lights = R"({"type": "quad", "corner": [2.5, 5, 3.5], "edge_u": [1, 0, 0],
                 "edge_v": [0, 0, 1], "intensity": 20},
                {"type": "point", "position": [-4, 3, 2], "intensity": 15})";
  return v;
}
Variant projective() {
  Variant v;
  v.lights = R"({"type": "projective", "position": [3, 5, 4], "look_at": [0, 0, 0],
                 "fov_degrees": 60, "texture": "clouds", "intensity": 60},
                {"type": "point", "position": [-4, 3, 2], "intensity": 15})";
  v.extra = R"(, "textures": [{"name": "clouds", "type": "clouds", "mapping": {"scale": 3}}])";
  return v;
}
Variant fog() {
  Variant v;
  v.extra = R"(, "media": [{"name": "fog", "region": {"type": "box", "min": [-4, 0, -3],
                                                        "max": [4, 3, 3]},
                            "sigma_a": 0.01, "sigma_s": 0.1, "g": 0.3}])";
  return v;
}

#define EFFECT(name, variant)                                                           \
  void BM_Effect_##name(benchmark::State& state) { renderBenchmark(state, variant()); } \
  BENCHMARK(BM_Effect_##name)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);

BENCHMARK(BM_PlainVsMinimal)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(6.0);
EFFECT(lens, lens)
EFFECT(motion, motion)
EFFECT(texture, texture)
EFFECT(glass, glass)
EFFECT(area_light, areaLight)
EFFECT(projective, projective)
EFFECT(fog, fog)

const char* kEffects[] = {"lens", "motion", "texture", "glass", "area_light", "projective", "fog"};

}  // namespace
}  // namespace glint

int main(int argc, char** argv) {
  std::string out = glint::bench::initialize(argc, argv);
  glint::bench::CounterReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  const double minimal = reporter.value("BM_PlainVsMinimal", "minimal_ms");
  const double plain = reporter.value("BM_PlainVsMinimal", "plain_ms");
  const double ratio = reporter.value("BM_PlainVsMinimal", "ratio");
  const double pairs = reporter.value("BM_PlainVsMinimal", "pairs");
  if (minimal <= 0 || plain <= 0) {
    std::fprintf(stderr, "features_bench: missing results\n");
    return 1;
  }
  std::printf(
      "\nminimal loop:  %.2f ms/image (median; image mean %.5f)\nfull renderer: %.2f ms/image "
      "(median; image mean %.5f)\nratio:         %.3f (median of %.0f pairs; target <= 1.03) "
      "%s\n",
      minimal, glint::gMinimalMean, plain, glint::gPlainMean, ratio, pairs,
      ratio <= 1.03 ? "PASS" : "FAIL");
  std::string effects;
  for (const char* e : glint::kEffects) {
    const double ms = reporter.value(std::string("BM_Effect_") + e, "ms_per_image");
    if (ms <= 0) continue;
    std::printf("%-12s %8.2f ms/image  %.2f x plain\n", e, ms, ms / plain);
    effects += std::string(effects.empty() ? "" : ",\n") + "    \"" + e +
               "\": {\"ms_per_image\": " + std::to_string(ms) +
               ", \"vs_plain\": " + std::to_string(ms / plain) + "}";
  }
  if (!out.empty()) {
    std::ofstream f(out);
    f << "{\n  \"width\": " << glint::kWidth << ",\n  \"height\": " << glint::kHeight
      << ",\n  \"spp\": " << glint::kSpp << ",\n  \"threads\": " << glint::threads()
      << ",\n  \"minimal_loop_ms_per_image\": " << minimal
      << ",\n  \"plain_ms_per_image\": " << plain << ",\n  \"ratio\": " << ratio
      << ",\n  \"pairs\": " << pairs << ",\n  \"target\": 1.03,\n  \"effects\": {\n"
      << effects << "\n  }\n}\n";
  }
  return 0;
}
