// glint — Kensler's permutation and correlated multi-jittered sampling.
#include "renderer/sampler.h"

#include <cmath>

namespace glint {

uint32_t permuteIndex(uint32_t i, uint32_t n, uint32_t p) {
  if (n <= 1) return 0;
  // Mask covering n-1; hash within the power-of-two range and cycle-walk until in range.
  uint32_t w = n - 1;
  w |= w >> 1, w |= w >> 2, w |= w >> 4, w |= w >> 8, w |= w >> 16;
  do {
    i ^= p;
    i *= 0xe170893d;
    i ^= p >> 16;
    i ^= (i & w) >> 4;
    i ^= p >> 8;
    i *= 0x0929eb3f;
    i ^= p >> 23;
    i ^= (i & w) >> 1;
    i *= 1 | p >> 27;
    i *= 0x6935fa69;
    i ^= (i & w) >> 11;
    i *= 0x74dcb303;
    i ^= (i & w) >> 2;
    i *= 0x9e501cc3;
    i ^= (i & w) >> 2;
    i *= 0xc860a3df;
    i &= w;
    i ^= i >> 5;
  } while (i >= n);
  return (i + p) % n;
}

namespace {
// Kensler's small hash to a float in [0, 1).
float randFloat(uint32_t i, uint32_t p) {
  i ^= p;
  i ^= i >> 17;
  i ^= i >> 10;
  i *= 0xb36534e5;
  i ^= i >> 12;
  i ^= i >> 21;
  i *= 0x93fc4795;
  i ^= 0xdf6e307f;
  i ^= i >> 17;
  i *= 1 | p >> 18;
  return std::min(float(i) * (1.0f / 4294967808.0f), 0x1.fffffep-1f);
}
}  // namespace

Vec2f cmjSample(uint32_t s, uint32_t n, uint32_t p) {
  // An m x k grid with m*k >= n, as square as possible.
  uint32_t m = uint32_t(std::sqrt(double(n)));
  if (m == 0) m = 1;
  uint32_t k = (n + m - 1) / m;
  s = permuteIndex(s, n, p * 0x51633e2d);
  uint32_t sx = permuteIndex(s % m, m, p * 0x68bc21eb);
  uint32_t sy = permuteIndex(s / m, k, p * 0x02e5be93);
  float jx = randFloat(s, p * 0x967a889b);
  float jy = randFloat(s, p * 0x368cc8b7);
  float x = (float(sx) + (float(sy) + jx) / float(k)) / float(m);
  float y = (float(s) + jy) / float(n);
  return {std::min(x, 0x1.fffffep-1f), std::min(y, 0x1.fffffep-1f)};
}

}  // namespace glint
