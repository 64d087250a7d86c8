// glint — addressed samples: every sample value is a pure function of
// (pixel, sample index, dimension, seed), so images are identical for any thread count or
// tiling, and any sample can be recomputed on its own.
//
// Each pair of dimensions is an Owen-scrambled Sobol (0,2)-sequence (Burley 2020, "Practical
// Hash-based Owen Scrambling", JCGT 9(4)): the sample index is shuffled by a nested uniform
// scramble and the two Sobol coordinates are Owen-scrambled, each with its own seed derived
// from (seed, pixel, dimension). For power-of-two sample counts every pixel's samples form a
// (0,2)-net: stratified in every elementary interval, not only in x and y. Different seeds per
// dimension pair decorrelate the pairs (pbrt-v4's padded Sobol idea). We chose this over
// Kensler's correlated multi-jitter because it costs a third as much per sample, and sampling
// cost is on the camera-ray path of every render.
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

// The key of one pixel's samples for a seed; computed once per pixel.
inline uint64_t pixelSampleKey(uint64_t seed, uint64_t pixel) {
  return mixBits(mixBits(seed + 0x9e3779b97f4a7c15ull) ^ (pixel * 0xd1b54a32d192ed03ull));
}

inline uint32_t reverseBits(uint32_t v) {
  v = __builtin_bswap32(v);
  v = ((v & 0x0f0f0f0fu) << 4) | ((v >> 4) & 0x0f0f0f0fu);
  v = ((v & 0x33333333u) << 2) | ((v >> 2) & 0x33333333u);
  v = ((v & 0x55555555u) << 1) | ((v >> 1) & 0x55555555u);
  return v;
}

// Laine–Karras-style hash (constants from Burley 2020): each output bit depends only on the
// input bits at or below it, which is what makes the bit-reversed version an Owen scramble.
inline uint32_t laineKarrasHash(uint32_t v, uint32_t seed) {
  v += seed;
  v ^= v * 0x6c50b47cu;
  v ^= v * 0xb82f1e52u;
  v ^= v * 0xc7afe638u;
  v ^= v * 0x8d22f6e6u;
  return v;
}

// Nested uniform (Owen) scramble of a 32-bit fixed-point fraction (most significant bit first).
inline uint32_t owenScramble(uint32_t v, uint32_t seed) {
  return reverseBits(laineKarrasHash(reverseBits(v), seed));
}

// The second Sobol dimension of index i as a 32-bit fraction (the first is reverseBits(i)).
uint32_t sobolSecondDimension(uint32_t i);

// A 32-bit fraction to a float in [0, 1).
inline float fractionToFloat(uint32_t v) { return float(v >> 8) * 0x1p-24f; }

// The samples of one pixel sample (one camera path). Consumes dimensions in call order, so a
// path that asks for the same things in the same order sees the same numbers.
class Sampler {
 public:
  // `pixelKey` = pixelSampleKey(seed, pixel index).
  Sampler(uint64_t pixelKey, uint32_t sampleIndex) : key_(pixelKey), sample_(sampleIndex) {}

  float get1D() {
    uint64_t h = dimensionHash();
    ++dim_;
    uint32_t index = owenScramble(sample_, uint32_t(h));
    // Owen-scrambled first Sobol dimension: reverse(LK(reverse(reverse(index)))).
    return fractionToFloat(reverseBits(laineKarrasHash(index, uint32_t(h >> 32))));
  }
  Vec2f get2D() {
    uint64_t h = dimensionHash();
    dim_ += 2;
    uint32_t index = owenScramble(sample_, uint32_t(h));
    uint32_t seedY = uint32_t(mixBits(h));
    return {fractionToFloat(reverseBits(laineKarrasHash(index, uint32_t(h >> 32)))),
            fractionToFloat(owenScramble(sobolSecondDimension(index), seedY))};
  }
  uint32_t dimension() const { return dim_; }

 private:
  uint64_t dimensionHash() const { return mixBits(key_ + uint64_t(dim_) * 0x9e3779b97f4a7c15ull); }
  uint64_t key_;
  uint32_t sample_;
  uint32_t dim_ = 0;
};

}  // namespace glint
