// glint — procedural textures.
#include "materials/procedural.h"

#include <bit>
#include <cmath>

namespace glint {

NoiseTexture::NoiseTexture(TextureMapping mapping, const NoiseParams& params)
    : mapping_(mapping),
      params_(params),
      noise_(params.seed),
      amplitudeSum_(octaveAmplitudeSum(params.octaves, params.gain)) {}

namespace {

// fBm or turbulence with its gradient (the derivative of |n| is sign(n) grad n).
float fractalSum(const PerlinNoise& noise, Vec3f p, const NoiseParams& np, bool absolute,
                 Vec3f* gradient) {
  float sum = 0, amplitude = 1, scale = 1;
  Vec3f g{0, 0, 0};
  for (int i = 0; i < np.octaves; ++i) {
    Vec3f gi;
    float n = noise.noise(p * scale, gradient ? &gi : nullptr);
    float sign = absolute && n < 0 ? -1.0f : 1.0f;
    sum += amplitude * (absolute ? std::abs(n) : n);
    if (gradient) g += gi * (sign * amplitude * scale);
    amplitude *= np.gain;
    scale *= np.lacunarity;
  }
  if (gradient) *gradient = g;
  return sum;
}

}  // namespace

float NoiseTexture::weight(Vec3f q, Vec3f* gradient) const {
  const NoiseParams& np = params_;
  Vec3f g{0, 0, 0};
  float w = 0;
  const float bound = PerlinNoise::kBound;
  switch (np.pattern) {
    case NoisePattern::Noise:
      w = 0.5f + 0.5f * noise_.noise(q, gradient ? &g : nullptr) / bound;
      g = g * (0.5f / bound);
      break;
    case NoisePattern::Fbm:
      w = 0.5f + 0.5f * fractalSum(noise_, q, np, false, gradient ? &g : nullptr) /
                     (bound * amplitudeSum_);
      g = g * (0.5f / (bound * amplitudeSum_));
      break;
    case NoisePattern::Turbulence:
      w = fractalSum(noise_, q, np, true, gradient ? &g : nullptr) / (bound * amplitudeSum_);
      g = g * (1 / (bound * amplitudeSum_));
      break;
    case NoisePattern::Marble: {
      // 0.5 + 0.5 sin(f x + d T(q)), as noise.h's marble().
      Vec3f gt;
      float t = fractalSum(noise_, q, np, true, gradient ? &gt : nullptr);
      float phase = np.frequency * q.x + np.distortion * t;
      w = 0.5f + 0.5f * std::sin(phase);
      g = (Vec3f{np.frequency, 0, 0} + gt * np.distortion) * (0.5f * std::cos(phase));
      break;
    }
    case NoisePattern::Wood: {
      // fract(ring sqrt(x^2 + z^2) + jitter n(q)), as noise.h's wood().
      Vec3f gn;
      float n = noise_.noise(q, gradient ? &gn : nullptr);
      float radius = std::sqrt(q.x * q.x + q.z * q.z);
      float r = np.ringFrequency * radius + np.jitter * n;
      w = r - std::floor(r);
      if (w >= 1) w = 0;
      Vec3f gr = radius > 0 ? Vec3f{q.x, 0, q.z} * (np.ringFrequency / radius) : Vec3f{};
      g = gr + gn * np.jitter;
      break;
    }
    case NoisePattern::Clouds: {
      float f = fractalSum(noise_, q, np, false, gradient ? &g : nullptr);
      float raw = 0.5f + 0.5f * f / (bound * amplitudeSum_);
      w = std::clamp(raw, 0.0f, 1.0f);
      g = raw == w ? g * (0.5f / (bound * amplitudeSum_)) : Vec3f{};
      break;
    }
  }
  if (gradient) *gradient = g;
  return std::clamp(w, 0.0f, 1.0f);
}

Vec4f NoiseTexture::evaluate(const TexturePoint& tp) const {
  float w = weight(mapping_.map3D(tp), nullptr);
  Rgb c = lerp(w, params_.colorA, params_.colorB);
  return {c.x, c.y, c.z, 1};
}

bool NoiseTexture::scalarGradient(const TexturePoint& tp, Vec3f* gradient) const {
  if (mapping_.space == TextureMapping::Space::Uv) return false;
  Vec3f gq;
  weight(mapping_.map3D(tp), &gq);
  // scalar = lum(A) + (lum(B) - lum(A)) w; q = scale * (L p) + offset with L the linear part
  // of objectFromWorld (object space) or the identity, so grad_p = L^T (scale * grad_q).
  Vec3f v = gq * mapping_.scale * (luminance(params_.colorB) - luminance(params_.colorA));
  if (mapping_.space == TextureMapping::Space::Object && tp.objectFromWorld) {
    const auto& m = tp.objectFromWorld->matrix().m;
    v = {m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z,
         m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z,
         m[0][2] * v.x + m[1][2] * v.y + m[2][2] * v.z};
  }
  *gradient = v;
  return true;
}

Vec4f RandomColorTexture::evaluate(const TexturePoint& tp) const {
  uint64_t key = mixBits(seed_ + 0x9e3779b97f4a7c15ull) ^ mixBits(tp.instance + 1);
  if (mode_ != Mode::Object) key = mixBits(key ^ (uint64_t(tp.prim) << 32));
  if (mode_ == Mode::Hit) {
    Vec3f p = tp.pObject();
    key = mixBits(key ^ std::bit_cast<uint32_t>(p.x));
    key = mixBits(key ^ std::bit_cast<uint32_t>(p.y));
    key = mixBits(key ^ std::bit_cast<uint32_t>(p.z));
  }
  auto channel = [&](int i) {
    return float((mixBits(key + uint64_t(i)) >> 40) & 0xffffff) * 0x1p-24f;
  };
  return {channel(0), channel(1), channel(2), 1};
}

}  // namespace glint
