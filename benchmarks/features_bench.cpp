// glint benchmark — does a plain scene pay for the features it does not use, and what does each
// used effect cost?
//
// 1. Unused features. The issue's target: a plain scene rendered by the full renderer costs no
//    more than 3% over the same scene with every unused feature compiled out. glint has no
//    build switches for features (it decides at setup from SceneFeatures, see
//    renderer/features.h), so "compiled out" is a hand-written Whitted for opaque Lambert
//    surfaces and point lights over the same parts — the static pinhole ray, the same sample
//    addressing and filter, the same accelerator (closestHits in packets of 16, anyHit for
//    shadows), computeSurfaceInteraction, Material::bsdf and Light::sampleLi — with no
//    feature test anywhere (minimalRender). With kBookkeeping it also does what render() does
//    that is not a feature (tiles, per-pixel moments for the variance, alpha, NaN/Inf checks,
//    ray counters): that is the renderer with every unused feature compiled out, the target's
//    baseline. Without, the bare loop, a stricter bound. Against them, `render()` with the
//    Whitted integrator from makeIntegrator on the same scene; the three images must have the
//    same mean (printed). BM_PlainVsMinimal renders them in rounds of three (each first,
//    second and third in turn) and prints the median of the per-round time ratios against the
//    1.03 target; BM_Blocked renders each 15 times in a row as a cross-check of the
//    interleaving (an earlier pairwise version measured both loops 12-19% slower and a ratio
//    of 1.05 on the same code; see benchmarks/README.md).
// 2. Used effects. The same scene with one effect switched on at a time (depth of field,
//    motion blur, a procedural texture, glass, a quad area light, a projective light with a
//    clouds slide, fog in a box around the objects marched at the default step with single
//    scattering), each at the same resolution and spp; the summary prints each one's time
//    over the full renderer's time on the plain scene.
//    At equal spp, not equal quality: lens and motion need more samples for the same noise
//    (effects_cost.py measures that).
// Usage: features_bench [--out results.json] [google benchmark flags]
#include <benchmark/benchmark.h>
#include <tbb/enumerable_thread_specific.h>
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
  state.SetLabel(std::to_string(b.scene.features().names().size()) + " features");
}

// ---------------------------------------------------------------------------------------------
// The minimal loop: Whitted for opaque Lambert surfaces and point lights, nothing else
// ---------------------------------------------------------------------------------------------

double gMinimalMean = 0, gKeptMean = 0, gPlainMean = 0;  // image means: they must agree

// With kBookkeeping, the minimal loop also does what render() does that is not a feature:
// 16x16 tiles, each pixel's sums and sums of squares in double for the film's variance, its
// alpha, the NaN/Inf check and per-thread ray counters. That is the renderer with every unused
// feature compiled out; without it, the bare loop.
template <bool kBookkeeping>
Film minimalRender(const RenderScene& scene, const RenderSettings& settings) {
  Film film(kWidth, kHeight, false);
  PixelFilter filter(settings.filter);
  SurfaceNeeds needs;
  needs.uvs = needs.colors = false;
  struct Tally {
    uint64_t camera = 0, shadow = 0, nonfinite = 0;
  };
  tbb::enumerable_thread_specific<Tally> tallies;
  constexpr int kTile = 16;
  constexpr int kTilesX = (kWidth + kTile - 1) / kTile, kTilesY = (kHeight + kTile - 1) / kTile;
  auto pixel = [&](int x, int y, Tally& tally) {
    const size_t index = film.index(x, y);
    const uint64_t key = pixelSampleKey(settings.seed, index);
    Ray rays[kSpp];
    Hit hits[kSpp];
    for (int s = 0; s < kSpp; ++s) {
      Sampler sampler(key, uint32_t(s), kFilmDimension);
      const Vec2f o = filter.sampleOffset(sampler.get2D());
      rays[s] = scene.camera().pinholeRay({float(x) + 0.5f + o.x, float(y) + 0.5f + o.y}, 0);
    }
    scene.accel().closestHits(rays, hits, kSpp);
    if constexpr (kBookkeeping) tally.camera += kSpp;
    Rgb sum;
    double sums[3] = {0, 0, 0}, squares[3] = {0, 0, 0}, found = 0;
    for (int s = 0; s < kSpp; ++s) {
      if (hits[s].instance == Hit::kInvalid) continue;
      Rgb L;
      const SurfaceInteraction si =
          computeSurfaceInteraction(scene.geometry(), rays[s], hits[s], needs);
      const Material& material = *scene.materials()[scene.materialIndex(hits[s])];
      const LightSampleContext ctx(si, 0);
      TextureLookups lookups(si);
      const Bsdf bsdf = material.bsdf(si, lookups);
      for (const auto& light : scene.lights()) {
        const std::optional<LightSample> ls = light->sampleLi(ctx, {0.5f, 0.5f});
        if (!ls) continue;
        const Rgb f = bsdf.f(ls->wi);
        if (!(maxComponent(f) > 0)) continue;
        if constexpr (kBookkeeping) ++tally.shadow;
        if (scene.accel().anyHit(shadowRay(ctx, *ls))) continue;
        L += f * ls->L * std::abs(dot(si.ns, ls->wi));
      }
      if constexpr (kBookkeeping) {
        if (!isFinite(L)) ++tally.nonfinite, L = {};
        found += 1;
        for (int c = 0; c < 3; ++c) sums[c] += L[c], squares[c] += double(L[c]) * L[c];
      } else {
        sum += L;
      }
    }
    if constexpr (kBookkeeping) {
      Rgb variance;
      for (int c = 0; c < 3; ++c) {
        sum[c] = float(sums[c] / kSpp);
        variance[c] =
            float(std::max(0.0, (squares[c] - sums[c] * sums[c] / kSpp) / ((kSpp - 1) * kSpp)));
      }
      film.color[index] = sum;
      film.variance[index] = variance;
      film.alpha[index] = float(found / kSpp);
    } else {
      film.color[index] = sum / float(kSpp);
    }
  };
  tbb::task_arena arena(threads());
  arena.execute([&] {
    if constexpr (kBookkeeping) {
      tbb::parallel_for(0, kTilesX * kTilesY, [&](int t) {
        const int x0 = (t % kTilesX) * kTile, y0 = (t / kTilesX) * kTile;
        Tally& tally = tallies.local();
        for (int y = y0; y < std::min(y0 + kTile, kHeight); ++y)
          for (int x = x0; x < std::min(x0 + kTile, kWidth); ++x) pixel(x, y, tally);
      });
    } else {
      tbb::parallel_for(0, kHeight, [&](int y) {
        Tally unused;
        for (int x = 0; x < kWidth; ++x) pixel(x, y, unused);
      });
    }
  });
  uint64_t rays = 0;
  for (const Tally& t : tallies) rays += t.camera + t.shadow + t.nonfinite;
  benchmark::DoNotOptimize(rays);
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
  std::vector<double> minimal, kept, plain, ratio, keptRatio;
  auto timed = [](auto&& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  };
  for (auto _ : state) {
    double m = 0, k = 0, p = 0;
    auto runMinimal = [&] {
      m = timed([&] {
        Film film = minimalRender<false>(b.scene, b.desc.render);
        benchmark::DoNotOptimize(film.color.data());
        gMinimalMean = imageMean(film);
      });
    };
    auto runKept = [&] {
      k = timed([&] {
        Film film = minimalRender<true>(b.scene, b.desc.render);
        benchmark::DoNotOptimize(film.color.data());
        gKeptMean = imageMean(film);
      });
    };
    auto runPlain = [&] {
      p = timed([&] {
        Film film = render(b.scene, *integrator, b.desc.render, options, &stats);
        benchmark::DoNotOptimize(film.color.data());
        gPlainMean = imageMean(film);
      });
    };
    // Each of the three goes first, second and third in turn.
    switch (minimal.size() % 3) {
      case 0:
        runPlain(), runMinimal(), runKept();
        break;
      case 1:
        runMinimal(), runKept(), runPlain();
        break;
      default:
        runKept(), runPlain(), runMinimal();
        break;
    }
    minimal.push_back(m), kept.push_back(k), plain.push_back(p);
    ratio.push_back(p / m), keptRatio.push_back(p / k);
  }
  state.counters["minimal_ms"] = median(minimal);
  state.counters["kept_ms"] = median(kept);
  state.counters["plain_ms"] = median(plain);
  state.counters["ratio"] = median(ratio);
  state.counters["kept_ratio"] = median(keptRatio);
  state.counters["pairs"] = double(ratio.size());  // rounds of three
  state.SetLabel(std::to_string(b.scene.features().names().size()) + " features");
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

// A cross-check of BM_PlainVsMinimal's interleaving: each loop 15 times in a row, in three
// rounds, so that each runs in the steady state of its own; the medians per loop. Load drift
// between the blocks is not cancelled, so it is only trustworthy on a quiet machine.
void BM_Blocked(benchmark::State& state) {
  Built b = build(Variant{});
  auto integrator = makeIntegrator(b.scene, b.desc.render);
  RenderOptions options;
  options.threads = threads();
  RenderStats stats;
  std::vector<double> minimal, kept, plain;
  auto block = [](std::vector<double>* times, auto&& renderOnce) {
    for (int i = 0; i < 15; ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      Film film = renderOnce();
      benchmark::DoNotOptimize(film.color.data());
      times->push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
  };
  for (auto _ : state) {
    for (int round = 0; round < 3; ++round) {
      block(&plain, [&] { return render(b.scene, *integrator, b.desc.render, options, &stats); });
      block(&minimal, [&] { return minimalRender<false>(b.scene, b.desc.render); });
      block(&kept, [&] { return minimalRender<true>(b.scene, b.desc.render); });
    }
  }
  state.counters["minimal_ms"] = median(minimal);
  state.counters["kept_ms"] = median(kept);
  state.counters["plain_ms"] = median(plain);
}
BENCHMARK(BM_Blocked)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
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
  const double kept = reporter.value("BM_PlainVsMinimal", "kept_ms");
  const double ratio = reporter.value("BM_PlainVsMinimal", "ratio");
  const double keptRatio = reporter.value("BM_PlainVsMinimal", "kept_ratio");
  const double pairs = reporter.value("BM_PlainVsMinimal", "pairs");
  if (minimal <= 0 || kept <= 0 || plain <= 0) {
    std::fprintf(stderr, "features_bench: missing results\n");
    return 1;
  }
  std::printf(
      "\nbare minimal loop:              %.2f ms/image (median; image mean %.5f)\n"
      "features compiled out, same bookkeeping: %.2f ms/image (median; image mean %.5f)\n"
      "full renderer:                  %.2f ms/image (median; image mean %.5f)\n"
      "full / features compiled out:   %.3f (median of %.0f rounds; target <= 1.03) %s\n"
      "full / bare loop:               %.3f (the bookkeeping included)\n",
      minimal, glint::gMinimalMean, kept, glint::gKeptMean, plain, glint::gPlainMean, keptRatio,
      pairs, keptRatio <= 1.03 ? "PASS" : "FAIL", ratio);
  const double blockedPlain = reporter.value("BM_Blocked", "plain_ms");
  const double blockedMinimal = reporter.value("BM_Blocked", "minimal_ms");
  const double blockedKept = reporter.value("BM_Blocked", "kept_ms");
  if (blockedPlain > 0 && blockedMinimal > 0 && blockedKept > 0)
    std::printf("blocked (15 in a row x 3): full / features compiled out %.3f, full / bare %.3f\n",
                blockedPlain / blockedKept, blockedPlain / blockedMinimal);
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
      << ",\n  \"features_compiled_out_ms_per_image\": " << kept
      << ",\n  \"plain_ms_per_image\": " << plain << ",\n  \"ratio\": " << keptRatio
      << ",\n  \"ratio_to_bare_loop\": " << ratio << ",\n  \"rounds\": " << pairs
      << ",\n  \"blocked_ratio\": " << (blockedKept > 0 ? blockedPlain / blockedKept : 0)
      << ",\n  \"blocked_ratio_to_bare_loop\": "
      << (blockedMinimal > 0 ? blockedPlain / blockedMinimal : 0)
      << ",\n  \"target\": 1.03,\n  \"effects\": {\n"
      << effects << "\n  }\n}\n";
  }
  return 0;
}
