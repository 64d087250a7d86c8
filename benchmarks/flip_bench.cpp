// glint benchmark — FLIP on a 1920×1080 pair (issue 8: "a 1080p pair in a few seconds on two
// cores"): LDR-FLIP on an sRGB pair, and HDR-FLIP (ACES, exposure range from the reference) on
// a scene-linear pair whose reference spans 4.5 stops (5 exposures). Wall time, all threads.
// The images are smooth coloured gradients with a noisy test image, built in memory.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "image/flip.h"

namespace glint {
namespace {

constexpr int kWidth = 1920, kHeight = 1080;

struct Pair {
  std::vector<float> reference, test;
};

// Reference: per-channel sine gradients; test: the reference plus uniform noise of ±0.05 (a
// fixed linear congruential sequence, so every run sees the same pair). `hdr` squares and
// scales the values and makes the right fifth of the image 11 times brighter.
Pair makePair(bool hdr) {
  Pair p{std::vector<float>(size_t(kWidth) * kHeight * 3), {}};
  p.test.resize(p.reference.size());
  unsigned state = 1;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      for (int c = 0; c < 3; ++c) {
        size_t i = 3 * (size_t(y) * kWidth + size_t(x)) + size_t(c);
        state = state * 1664525u + 1013904223u;
        float noise = (float(state >> 8) / 16777216.0f - 0.5f) * 0.1f;
        float a = 0.5f + 0.4f * std::sin(0.01f * float(x * (c + 1)) + 0.013f * float(y));
        float b = std::clamp(a + noise, 0.0f, 1.0f);
        if (hdr) {
          float scale = x > 1500 ? 44.0f : 4.0f;
          a *= scale * a, b *= scale * b;
        }
        p.reference[i] = a, p.test[i] = b;
      }
  return p;
}

void BM_FlipLdr1080p(benchmark::State& state) {
  const Pair p = makePair(false);
  for (auto _ : state) {
    FlipResult r = flipLdr(p.reference, p.test, kWidth, kHeight);
    benchmark::DoNotOptimize(r.stats.mean);
  }
}

void BM_FlipHdr1080p(benchmark::State& state) {
  const Pair p = makePair(true);
  for (auto _ : state) {
    FlipResult r = flipHdr(p.reference, p.test, kWidth, kHeight);
    benchmark::DoNotOptimize(r.stats.mean);
    state.counters["exposures"] = r.exposures.count;
  }
}

}  // namespace

BENCHMARK(BM_FlipLdr1080p)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FlipHdr1080p)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace glint

BENCHMARK_MAIN();
