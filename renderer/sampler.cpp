// glint — the vectorised batch of film samples.
#include "renderer/sampler.h"

namespace glint {

namespace {

// reverseBits without bswap: shifts and masks only, which the vectoriser maps to SIMD lanes.
inline uint32_t reverseBitsByShifts(uint32_t v) {
  v = (v >> 16) | (v << 16);
  v = ((v & 0x00ff00ffu) << 8) | ((v >> 8) & 0x00ff00ffu);
  v = ((v & 0x0f0f0f0fu) << 4) | ((v >> 4) & 0x0f0f0f0fu);
  v = ((v & 0x33333333u) << 2) | ((v >> 2) & 0x33333333u);
  v = ((v & 0x55555555u) << 1) | ((v >> 1) & 0x55555555u);
  return v;
}

}  // namespace

// Straight loops over the batch, compiled twice (AVX2 and the baseline) and picked at run time
// (GCC target_clones): the integer hashing of a pixel's samples runs 8 lanes wide where the CPU
// allows. Integer arithmetic, so every clone gives sample2DFraction's results bit for bit.
__attribute__((target_clones("avx2", "default"))) void sample2DFractionBatch(
    uint32_t firstIndex, uint32_t count, const DimensionSeeds& seeds, uint32_t* xs, uint32_t* ys) {
  const uint32_t seedIndex = seeds.index, seedX = seeds.x, seedY = seeds.y;
  for (uint32_t i = 0; i < count; ++i) {
    uint32_t index =
        reverseBitsByShifts(laineKarrasHash(reverseBitsByShifts(firstIndex + i), seedIndex));
    xs[i] = reverseBitsByShifts(laineKarrasHash(index, seedX));
    ys[i] = reverseBitsByShifts(laineKarrasHash(reversedSobolSecondDimension(index), seedY));
  }
}

}  // namespace glint
