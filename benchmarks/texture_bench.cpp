// glint benchmark — image texture lookups per second (one thread) through OpenImageIO's
// TextureSystem: Nearest, Linear and Mipmap on a 1024x1024 RGBA image in memory, at 4,096
// pseudo-random coordinates per iteration with footprints of up to two texels. The cache is
// warmed first, so this times filtering, not loading.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "materials/image_texture.h"

namespace glint {
namespace {

constexpr int kSize = 1024;

std::vector<float> pixels() {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0, 1);
  std::vector<float> p(size_t(kSize) * kSize * 4);
  for (float& v : p) v = u(rng);
  return p;
}

std::vector<TexCoord2> coords() {
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> st(0, 1), d(-2.0f / kSize, 2.0f / kSize);
  std::vector<TexCoord2> c(4096);
  for (TexCoord2& x : c) x = {{st(rng), st(rng)}, {d(rng), d(rng)}, {d(rng), d(rng)}};
  return c;
}

void run(benchmark::State& state, TextureFilter filter) {
  TextureImages images;
  auto h = images.addPixels("random", kSize, kSize, 4, pixels(), ColorEncoding::Srgb);
  const std::vector<TexCoord2> c = coords();
  float sink = 0;
  for (int pass = 0; pass < 2; ++pass)  // load every tile and MIP level the lookups touch
    for (const TexCoord2& x : c)
      sink += images.lookup(h, x, TextureWrap::Repeat, TextureWrap::Repeat, filter).x;
  for (auto _ : state) {
    for (const TexCoord2& x : c)
      sink += images.lookup(h, x, TextureWrap::Repeat, TextureWrap::Repeat, filter).x;
    benchmark::DoNotOptimize(sink);
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(c.size()));
}

void BM_ImageNearest(benchmark::State& s) { run(s, TextureFilter::Nearest); }
void BM_ImageLinear(benchmark::State& s) { run(s, TextureFilter::Linear); }
void BM_ImageMipmap(benchmark::State& s) { run(s, TextureFilter::Mipmap); }

BENCHMARK(BM_ImageNearest);
BENCHMARK(BM_ImageLinear);
BENCHMARK(BM_ImageMipmap);

}  // namespace
}  // namespace glint

BENCHMARK_MAIN();
