// glint — improved Perlin noise, fBm, turbulence and the procedural patterns.
#include "materials/noise.h"

#include <algorithm>
#include <cmath>

namespace glint {

namespace {

// SplitMix64: a small, well-mixed 64-bit generator (Steele, Lea & Flood 2014).
uint64_t splitMix64(uint64_t* state) {
  uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// The 16 gradient directions of improved noise: the 12 cube edge midpoints, with (1,1,0),
// (-1,1,0), (0,-1,1) and (0,-1,-1) repeated to make 16 (Perlin 2002, section 3).
constexpr float kGradients[16][3] = {
    {1, 1, 0}, {-1, 1, 0}, {1, -1, 0}, {-1, -1, 0}, {1, 0, 1}, {-1, 0, 1}, {1, 0, -1}, {-1, 0, -1},
    {0, 1, 1}, {0, -1, 1}, {0, 1, -1}, {0, -1, -1}, {1, 1, 0}, {0, -1, 1}, {-1, 1, 0}, {0, -1, -1}};

float fade(float t) { return t * t * t * (t * (t * 6 - 15) + 10); }
float fadeDerivative(float t) { return 30 * t * t * (t * (t - 2) + 1); }

}  // namespace

PerlinNoise::PerlinNoise(uint64_t seed) {
  std::array<uint8_t, 256> p;
  for (int i = 0; i < 256; ++i) p[size_t(i)] = uint8_t(i);
  // Fisher–Yates with our own generator: the same permutation everywhere.
  uint64_t state = seed;
  for (int i = 255; i > 0; --i) {
    int j = int(splitMix64(&state) % uint64_t(i + 1));
    std::swap(p[size_t(i)], p[size_t(j)]);
  }
  for (size_t i = 0; i < 512; ++i) perm_[i] = p[i & 255];
}

float PerlinNoise::evaluate(Vec3f p, Vec3f* grad) const {
  const float fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
  // The lattice repeats every 256 cells; & 255 on a two's-complement int keeps negatives right.
  const int X = int(int64_t(fx) & 255), Y = int(int64_t(fy) & 255), Z = int(int64_t(fz) & 255);
  const float x = p.x - fx, y = p.y - fy, z = p.z - fz;
  const float u = fade(x), v = fade(y), w = fade(z);

  // Dot products of the 8 corner gradients with the offsets to p, and the gradients.
  float d[8];
  const float* g[8];
  for (int c = 0; c < 8; ++c) {
    const int cx = c & 1, cy = (c >> 1) & 1, cz = (c >> 2) & 1;
    const int h = perm_[size_t(perm_[size_t(perm_[size_t(X + cx)] + Y + cy)] + Z + cz)] & 15;
    g[c] = kGradients[h];
    d[c] = g[c][0] * (x - float(cx)) + g[c][1] * (y - float(cy)) + g[c][2] * (z - float(cz));
  }
  // Trilinear blend with the faded weights: x first, then y, then z.
  const float x00 = d[0] + u * (d[1] - d[0]), x10 = d[2] + u * (d[3] - d[2]);
  const float x01 = d[4] + u * (d[5] - d[4]), x11 = d[6] + u * (d[7] - d[6]);
  const float y0 = x00 + v * (x10 - x00), y1 = x01 + v * (x11 - x01);
  const float value = y0 + w * (y1 - y0);
  if (grad) {
    // Product rule: the blend weights depend on x, y, z through the fade, and each corner's
    // dot product has the corner's gradient as its own derivative.
    const float du = fadeDerivative(x), dv = fadeDerivative(y), dw = fadeDerivative(z);
    Vec3f sum{0, 0, 0};
    for (int c = 0; c < 8; ++c) {
      const int cx = c & 1, cy = (c >> 1) & 1, cz = (c >> 2) & 1;
      const float wx = cx ? u : 1 - u, wy = cy ? v : 1 - v, wz = cz ? w : 1 - w;
      const float sx = cx ? du : -du, sy = cy ? dv : -dv, sz = cz ? dw : -dw;
      const float weight = wx * wy * wz;
      sum.x += weight * g[c][0] + sx * wy * wz * d[c];
      sum.y += weight * g[c][1] + wx * sy * wz * d[c];
      sum.z += weight * g[c][2] + wx * wy * sz * d[c];
    }
    *grad = sum;
  }
  return value;
}

float PerlinNoise::noise(Vec3f p) const { return evaluate(p, nullptr); }

Vec3f PerlinNoise::gradient(Vec3f p) const {
  Vec3f g;
  evaluate(p, &g);
  return g;
}

float PerlinNoise::fbm(Vec3f p, int octaves, float lacunarity, float gain) const {
  float sum = 0, amplitude = 1;
  for (int i = 0; i < octaves; ++i, p = p * lacunarity, amplitude *= gain)
    sum += amplitude * noise(p);
  return sum;
}

float PerlinNoise::turbulence(Vec3f p, int octaves, float lacunarity, float gain) const {
  float sum = 0, amplitude = 1;
  for (int i = 0; i < octaves; ++i, p = p * lacunarity, amplitude *= gain)
    sum += amplitude * std::abs(noise(p));
  return sum;
}

float octaveAmplitudeSum(int octaves, float gain) {
  float sum = 0, amplitude = 1;
  for (int i = 0; i < octaves; ++i, amplitude *= gain) sum += amplitude;
  return sum;
}

float marble(const PerlinNoise& noise, Vec3f p, float frequency, float distortion, int octaves) {
  return 0.5f + 0.5f * std::sin(frequency * p.x + distortion * noise.turbulence(p, octaves));
}

float wood(const PerlinNoise& noise, Vec3f p, float ringFrequency, float jitter) {
  float r = ringFrequency * std::sqrt(p.x * p.x + p.z * p.z) + jitter * noise.noise(p);
  float f = r - std::floor(r);
  return f < 1 ? f : 0;  // guard the rounding of r - floor(r) to 1 for tiny negative r
}

float clouds(const PerlinNoise& noise, Vec3f p, int octaves) {
  float n = noise.fbm(p, octaves) / (PerlinNoise::kBound * octaveAmplitudeSum(octaves, 0.5f));
  return std::clamp(0.5f + 0.5f * n, 0.0f, 1.0f);
}

}  // namespace glint
