// glint — procedural textures: Perlin-noise patterns (noise, fBm, turbulence, marble, wood,
// clouds) and random colours.
//
// A pattern gives a weight w in [0, 1] at the mapped 3D point; the texture's colour is
// lerp(colorA, colorB, w), so the same pattern serves as a colour (black to white by default),
// as a weight between two colours, and as a height field (bump.h reads its scalar). Patterns
// know their exact gradient, which bump mapping uses instead of finite differences.
#pragma once

#include "materials/noise.h"
#include "materials/texture.h"

namespace glint {

enum class NoisePattern { Noise, Fbm, Turbulence, Marble, Wood, Clouds };

struct NoiseParams {
  NoisePattern pattern = NoisePattern::Noise;
  uint64_t seed = 0;
  int octaves = 5;  // fbm, turbulence, marble, clouds
  float lacunarity = 2, gain = 0.5f;
  float frequency = 4;      // marble: veins per unit along x
  float distortion = 6;     // marble: turbulence added to the phase
  float ringFrequency = 8;  // wood: rings per unit of radius
  float jitter = 0.6f;      // wood: noise added to the ring radius
  Rgb colorA{0, 0, 0}, colorB{1, 1, 1};
};

class NoiseTexture final : public Texture {
 public:
  NoiseTexture(TextureMapping mapping, const NoiseParams& params);
  Vec4f evaluate(const TexturePoint& tp) const override;
  bool scalarGradient(const TexturePoint& tp, Vec3f* gradient) const override;
  TextureNeeds needs() const override {
    return {.uvs = mapping_.usesUvs(), .objectSpace = mapping_.usesObjectSpace()};
  }
  Rgb upperBound() const override { return max(params_.colorA, params_.colorB); }
  // The pattern's weight in [0, 1] at texture-space point q, and its gradient by q.
  float weight(Vec3f q, Vec3f* gradient) const;

 private:
  TextureMapping mapping_;
  NoiseParams params_;
  PerlinNoise noise_;
  float amplitudeSum_;
};

// A deterministic random colour per object (instance), per primitive, or per hit point:
// a hash of (seed, object[, primitive[, position]]), the same on every frame and thread.
class RandomColorTexture final : public Texture {
 public:
  enum class Mode { Object, Primitive, Hit };
  RandomColorTexture(Mode mode, uint64_t seed) : mode_(mode), seed_(seed) {}
  Vec4f evaluate(const TexturePoint& tp) const override;
  TextureNeeds needs() const override { return {.objectSpace = mode_ == Mode::Hit}; }

 private:
  Mode mode_;
  uint64_t seed_;
};

}  // namespace glint
