// glint — addressed samples: every sample value is a pure function of
// (pixel, sample index, dimension, seed), so images are identical for any thread count or
// tiling, and any sample can be recomputed on its own.
//
// 2D dimensions are stratified across a pixel's samples with Kensler's correlated
// multi-jittered sampling ("Correlated Multi-Jittered Sampling", Pixar TM 13-01, 2013), which
// stratifies any sample count, not only squares; 1D dimensions are jittered strata in a
// per-pixel random order. Each dimension gets its own scramble, so dimensions are decorrelated.
#pragma once

#include <cstdint>

#include "geometry/math.h"

namespace glint {

// 64-bit finaliser (Stafford's Mix13 variant of MurmurHash3's fmix64): a strong bijective mix.
inline uint64_t mixBits(uint64_t v) {
  v ^= v >> 31;
  v *= 0x7fb5d329728ea185ull;
  v ^= v >> 27;
  v *= 0x81dadef4bc2dd44dull;
  v ^= v >> 33;
  return v;
}

// Hash of several keys, order-sensitive.
inline uint64_t hashKeys(uint64_t a, uint64_t b, uint64_t c = 0, uint64_t d = 0) {
  uint64_t h = mixBits(a + 0x9e3779b97f4a7c15ull);
  h = mixBits(h ^ (b + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2)));
  h = mixBits(h ^ (c + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2)));
  h = mixBits(h ^ (d + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2)));
  return h;
}

// A float in [0, 1) from the top 24 bits of a hash.
inline float hashToFloat(uint64_t h) { return float(h >> 40) * 0x1p-24f; }

// Kensler's hash-based permutation of [0, n): element i of permutation `pattern`.
uint32_t permuteIndex(uint32_t i, uint32_t n, uint32_t pattern);

// Sample `s` of `n` correlated multi-jittered points in [0,1)^2 for `pattern`.
Vec2f cmjSample(uint32_t s, uint32_t n, uint32_t pattern);

// The samples of one pixel sample (one camera path). Consumes dimensions in call order, so a
// path that asks for the same things in the same order sees the same numbers.
class Sampler {
 public:
  Sampler(uint64_t pixelIndex, uint32_t sampleIndex, uint32_t samplesPerPixel, uint64_t seed)
      : pixel_(pixelIndex), sample_(sampleIndex), spp_(samplesPerPixel), seed_(seed) {}

  float get1D() {
    uint32_t pattern = uint32_t(hashKeys(seed_, pixel_, dim_, 1));
    uint32_t stratum = permuteIndex(sample_, spp_, pattern);
    float jitter = hashToFloat(hashKeys(seed_, pixel_, sample_, (uint64_t(dim_) << 1) | 1));
    ++dim_;
    return std::min((float(stratum) + jitter) / float(spp_), 0x1.fffffep-1f);
  }
  Vec2f get2D() {
    uint32_t pattern = uint32_t(hashKeys(seed_, pixel_, dim_, 2));
    dim_ += 2;
    return cmjSample(sample_, spp_, pattern);
  }
  uint32_t dimension() const { return dim_; }

 private:
  uint64_t pixel_;
  uint32_t sample_, spp_;
  uint64_t seed_;
  uint32_t dim_ = 0;
};

}  // namespace glint
