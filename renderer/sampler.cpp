// glint — Sobol's second dimension by table lookup.
#include "renderer/sampler.h"

#include <array>

namespace glint {

namespace {

// Column j of the dimension's generator matrix (as a 32-bit fraction): c0 = 1/2, and each next
// column is c ^ (c >> 1) (the Pascal matrix mod 2). Tables combine 8 index bits per lookup and
// store the XOR of the columns bit-reversed (reversal distributes over XOR).
constexpr auto makeTables() {
  std::array<std::array<uint32_t, 256>, 4> t{};
  uint32_t column[32] = {};
  uint32_t c = 1u << 31;
  for (int j = 0; j < 32; ++j, c ^= c >> 1) column[j] = c;
  for (int k = 0; k < 4; ++k)
    for (uint32_t b = 0; b < 256; ++b) {
      uint32_t v = 0;
      for (int j = 0; j < 8; ++j)
        if (b & (1u << j)) v ^= column[8 * k + j];
      uint32_t r = 0;
      for (int bit = 0; bit < 32; ++bit) r |= ((v >> bit) & 1u) << (31 - bit);
      t[size_t(k)][b] = r;
    }
  return t;
}

}  // namespace

// Computed at compile time: no static-initialisation order question for other static objects.
alignas(64) constinit const std::array<std::array<uint32_t, 256>, 4> kReversedSobolSecondDimension =
    makeTables();

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
  const auto& t = kReversedSobolSecondDimension;
  const uint32_t seedIndex = seeds.index, seedX = seeds.x, seedY = seeds.y;
  for (uint32_t i = 0; i < count; ++i) {
    uint32_t index =
        reverseBitsByShifts(laineKarrasHash(reverseBitsByShifts(firstIndex + i), seedIndex));
    xs[i] = reverseBitsByShifts(laineKarrasHash(index, seedX));
    uint32_t sobol = t[0][index & 0xff] ^ t[1][(index >> 8) & 0xff] ^ t[2][(index >> 16) & 0xff] ^
                     t[3][index >> 24];
    ys[i] = reverseBitsByShifts(laineKarrasHash(sobol, seedY));
  }
}

}  // namespace glint
