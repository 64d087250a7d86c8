// glint benchmark — noise evaluations per second (scalar), for the procedural textures and
// bump mapping of issue 5: 3D noise, its gradient, 6-octave fBm, and the marble, wood and
// clouds patterns, each at 4,096 pseudo-random points per iteration.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "materials/noise.h"

namespace glint {
namespace {

std::vector<Vec3f> points() {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-50, 50);
  std::vector<Vec3f> p(4096);
  for (Vec3f& v : p) v = {u(rng), u(rng), u(rng)};
  return p;
}

template <class F>
void run(benchmark::State& state, F f) {
  const std::vector<Vec3f> p = points();
  const PerlinNoise noise(7);
  float sink = 0;
  for (auto _ : state) {
    for (const Vec3f& v : p) sink += f(noise, v);
    benchmark::DoNotOptimize(sink);
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(p.size()));
}

void BM_Noise3D(benchmark::State& s) {
  run(s, [](const PerlinNoise& n, Vec3f p) { return n.noise(p); });
}
void BM_NoiseGradient(benchmark::State& s) {
  run(s, [](const PerlinNoise& n, Vec3f p) { return n.gradient(p).x; });
}
void BM_Fbm6(benchmark::State& s) {
  run(s, [](const PerlinNoise& n, Vec3f p) { return n.fbm(p, 6); });
}
void BM_Marble(benchmark::State& s) {
  run(s, [](const PerlinNoise& n, Vec3f p) { return marble(n, p); });
}
void BM_Wood(benchmark::State& s) {
  run(s, [](const PerlinNoise& n, Vec3f p) { return wood(n, p); });
}
void BM_Clouds(benchmark::State& s) {
  run(s, [](const PerlinNoise& n, Vec3f p) { return clouds(n, p); });
}

BENCHMARK(BM_Noise3D);
BENCHMARK(BM_NoiseGradient);
BENCHMARK(BM_Fbm6);
BENCHMARK(BM_Marble);
BENCHMARK(BM_Wood);
BENCHMARK(BM_Clouds);

}  // namespace
}  // namespace glint

BENCHMARK_MAIN();
