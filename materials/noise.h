// glint — Perlin noise and the course's procedural patterns built from it.
//
// Improved noise (Perlin, "Improving Noise", SIGGRAPH 2002): a lattice of pseudo-random
// gradients chosen from a fixed set of 16 (the 12 edge directions of a cube, four repeated),
// blended with the quintic fade 6t^5 - 15t^4 + 10t^3, so the noise is C2 and its gradient
// continuous (bump mapping differentiates it). The lattice hash is a permutation of 0..255
// shuffled from a 64-bit seed with our own integer generator, so values are identical on every
// platform and compiler (no std:: distributions).
//
// Patterns (Perlin 1985; Ebert et al., "Texturing & Modeling: A Procedural Approach") return a
// weight in [0, 1] that a material uses to mix two colours or as a height field;
// materials/procedural.h turns them into textures.
#pragma once

#include <array>
#include <cstdint>

#include "geometry/math.h"

namespace glint {

class PerlinNoise {
 public:
  explicit PerlinNoise(uint64_t seed = 0);

  // Noise at p: 0 at every lattice point, |noise| < kBound everywhere.
  float noise(Vec3f p) const;
  // The 2D noise is the z = 0 slice of the 3D noise.
  float noise(Vec2f p) const { return noise(Vec3f{p.x, p.y, 0}); }
  // The exact gradient of noise(p) (differentiating the fade and the blend).
  Vec3f gradient(Vec3f p) const;
  // Value and exact gradient in one evaluation.
  float noise(Vec3f p, Vec3f* gradient) const { return evaluate(p, gradient); }
  // Fractal sum of `octaves` noise layers, frequency times `lacunarity` and amplitude times
  // `gain` per layer. |fbm| < kBound * (1 + gain + gain^2 + ...).
  float fbm(Vec3f p, int octaves, float lacunarity = 2, float gain = 0.5f) const;
  // The same sum of |noise|: in [0, kBound * (1 + gain + ...)).
  float turbulence(Vec3f p, int octaves, float lacunarity = 2, float gain = 0.5f) const;

  // A bound on |noise(p)|. The improved-noise maximum is about 1.04 (reached only near a few
  // lattice-cell configurations); tests check this bound over millions of points.
  static constexpr float kBound = 1.1f;

 private:
  // Value and gradient at p (the gradient only when `grad` is not null).
  float evaluate(Vec3f p, Vec3f* grad) const;
  std::array<uint8_t, 512> perm_;  // the shuffled 0..255, twice (no index wrapping)
};

// The sum of amplitudes of an fbm / turbulence with these parameters (for normalising).
float octaveAmplitudeSum(int octaves, float gain);

// Marble: veins from a sine along x, bent by turbulence.
//   0.5 + 0.5 sin(frequency * p.x + distortion * turbulence(p, octaves)) -> [0, 1]
float marble(const PerlinNoise& noise, Vec3f p, float frequency = 4, float distortion = 6,
             int octaves = 5);

// Wood: rings around the y axis, their radii jittered by noise.
//   fract(ringFrequency * sqrt(x^2 + z^2) + jitter * noise(p)) -> [0, 1)
float wood(const PerlinNoise& noise, Vec3f p, float ringFrequency = 8, float jitter = 0.6f);

// Clouds (the course's "structure" texture): fbm mapped to [0, 1].
//   clamp(0.5 + 0.5 * fbm(p) / octaveAmplitudeSum) -> [0, 1]
float clouds(const PerlinNoise& noise, Vec3f p, int octaves = 6);

}  // namespace glint
