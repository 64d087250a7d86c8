// glint benchmark — image texture lookups per second (one thread), the same image served two
// ways side by side: in memory as glint's MIP pyramid (what glTF images and small files get)
// and from OpenImageIO's TextureSystem (what tiled, MIP-mapped files get). The image is a real
// glTF texture, DamagedHelmet's 2048x2048 RGB base colour (JPEG, sRGB), from $GLINT_ASSETS.
//
// Two access patterns, 4,096 lookups per iteration: "coherent" walks the image in small steps,
// as neighbouring camera rays do; "random" jumps anywhere, as bounce rays do (see coords for
// the footprints). Each case is warmed first, so this times lookups, not loading.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "image/oiio/plugin.h"
#include "materials/image_texture.h"

namespace glint {
namespace {

std::string assetsDir() {
  if (const char* env = std::getenv("GLINT_ASSETS"); env && *env) return env;
  return GLINT_DEFAULT_ASSETS;
}

const std::string& imagePath() {
  static const std::string path = assetsDir() + "/gltf/DamagedHelmet/glTF/Default_albedo.jpg";
  return path;
}

constexpr int kSize = 2048;

// Footprints as a ray cone makes them on a curved surface: a circle of 0.5 to 2 texels
// across, stretched by 1 / cos θ along a random direction, with cos θ uniform in [0.05, 1]
// (how a sphere's projected area is spread over viewing angles).
std::vector<TexCoord2> coords(bool coherent) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> st(0, 1), width(0.5f / kSize, 2.0f / kSize),
      cosine(0.05f, 1), angle(0, 6.2831853f), step(-0.5f / kSize, 1.5f / kSize);
  std::vector<TexCoord2> c(4096);
  Vec2f at{st(rng), st(rng)};
  for (TexCoord2& x : c) {
    if (coherent)
      at = {at.x + step(rng), at.y + 0.25f * step(rng)};
    else
      at = {st(rng), st(rng)};
    const float r = width(rng), stretch = 1 / cosine(rng), a = angle(rng);
    const Vec2f along{std::cos(a), std::sin(a)}, across{-along.y, along.x};
    x = {at, along * (r * stretch), across * r};
  }
  return c;
}

void run(benchmark::State& state, TextureStorage storage, TextureFilter filter, bool coherent) {
  TextureImages images(&oiio::imageDecoder);
  TextureImages::Handle h;
  try {
    h = images.addFile(imagePath(), ColorEncoding::Srgb, storage);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  const std::vector<TexCoord2> c = coords(coherent);
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
  state.SetLabel(textureStorageName(images.storage(h)));
}

#define GLINT_TEXTURE_CASES(storage, name)                                               \
  BENCHMARK_CAPTURE(run, name##_nearest_random, storage, TextureFilter::Nearest, false); \
  BENCHMARK_CAPTURE(run, name##_linear_random, storage, TextureFilter::Linear, false);   \
  BENCHMARK_CAPTURE(run, name##_mipmap_random, storage, TextureFilter::Mipmap, false);   \
  BENCHMARK_CAPTURE(run, name##_mipmap_coherent, storage, TextureFilter::Mipmap, true);

GLINT_TEXTURE_CASES(TextureStorage::Memory, memory)
GLINT_TEXTURE_CASES(TextureStorage::Cache, cache)

}  // namespace
}  // namespace glint

BENCHMARK_MAIN();
