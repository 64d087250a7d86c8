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

}  // namespace glint
