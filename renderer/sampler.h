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

// Sobol's second dimension of index i, bit-reversed (least significant bit first): what the
// Owen scramble takes, so the sample path needs no reversal. Its generator matrix is the
// Pascal matrix mod 2, whose entry (k, j) is odd exactly when k's bits are a subset of j's
// (Lucas' theorem), so output bit k is the XOR of the index bits j that contain k: a
// superset transform over the five bits of a bit position, done in five shift-mask-XOR steps.
// No table, so a batch of indices vectorises without gathers.
inline uint32_t reversedSobolSecondDimension(uint32_t i) {
  i ^= (i >> 1) & 0x55555555u;
  i ^= (i >> 2) & 0x33333333u;
  i ^= (i >> 4) & 0x0f0f0f0fu;
  i ^= (i >> 8) & 0x00ff00ffu;
  i ^= (i >> 16) & 0x0000ffffu;
  return i;
}

// The second Sobol dimension of index i as a 32-bit fraction (the first is reverseBits(i)).
inline uint32_t sobolSecondDimension(uint32_t i) {
  return reverseBits(reversedSobolSecondDimension(i));
}

// A 32-bit fraction to a float in [0, 1).
inline float fractionToFloat(uint32_t v) { return float(v >> 8) * 0x1p-24f; }

// The scramble seeds of one dimension pair of one pixel: a function of (pixel key, dimension)
// only, so a renderer can compute the film pair's once per pixel instead of once per sample.
struct DimensionSeeds {
  uint32_t index = 0, x = 0, y = 0;  // sample-index shuffle, first and second coordinate
  DimensionSeeds() = default;
  DimensionSeeds(uint64_t pixelKey, uint32_t dimension) {
    uint64_t h = mixBits(pixelKey + uint64_t(dimension) * 0x9e3779b97f4a7c15ull);
    index = uint32_t(h), x = uint32_t(h >> 32), y = uint32_t(mixBits(h));
  }
};

// Two 32-bit fractions: a 2D sample before conversion to float.
struct Fraction2 {
  uint32_t x = 0, y = 0;
  Vec2f toFloat() const { return {fractionToFloat(x), fractionToFloat(y)}; }
};

// Sample `sampleIndex` of the dimension pair with `seeds`, as fractions.
inline Fraction2 sample2DFraction(uint32_t sampleIndex, const DimensionSeeds& seeds) {
  uint32_t index = owenScramble(sampleIndex, seeds.index);
  // x: Owen-scrambled first Sobol dimension, reverse(LK(reverse(reverse(index)))).
  // y: Owen-scrambled second dimension, with its reversal folded into the table.
  return {reverseBits(laineKarrasHash(index, seeds.x)),
          reverseBits(laineKarrasHash(reversedSobolSecondDimension(index), seeds.y))};
}

// Samples firstIndex .. firstIndex + count - 1 of one dimension pair at once, as fractions
// (xs[i], ys[i]): equal to sample2DFraction bit for bit, vectorised across the batch.
void sample2DFractionBatch(uint32_t firstIndex, uint32_t count, const DimensionSeeds& seeds,
                           uint32_t* xs, uint32_t* ys);

// The same sample in [0,1)^2.
inline Vec2f sample2D(uint32_t sampleIndex, const DimensionSeeds& seeds) {
  return sample2DFraction(sampleIndex, seeds).toFloat();
}

// The samples of one pixel sample (one camera path). Consumes dimensions in call order, so a
// path that asks for the same things in the same order sees the same numbers.
class Sampler {
 public:
  // `pixelKey` = pixelSampleKey(seed, pixel index). A renderer that drew dimensions
  // [0, firstDimension) itself (the film position, with sample2D) starts after them.
  Sampler(uint64_t pixelKey, uint32_t sampleIndex, uint32_t firstDimension = 0)
      : key_(pixelKey), sample_(sampleIndex), dim_(firstDimension) {}

  float get1D() {
    uint64_t h = dimensionHash();
    ++dim_;
    uint32_t index = owenScramble(sample_, uint32_t(h));
    // Owen-scrambled first Sobol dimension: reverse(LK(reverse(reverse(index)))).
    return fractionToFloat(reverseBits(laineKarrasHash(index, uint32_t(h >> 32))));
  }
  Vec2f get2D() {
    DimensionSeeds seeds(key_, dim_);
    dim_ += 2;
    return sample2D(sample_, seeds);
  }
  uint32_t dimension() const { return dim_; }

 private:
  uint64_t dimensionHash() const { return mixBits(key_ + uint64_t(dim_) * 0x9e3779b97f4a7c15ull); }
  uint64_t key_;
  uint32_t sample_;
  uint32_t dim_;
};

}  // namespace glint
