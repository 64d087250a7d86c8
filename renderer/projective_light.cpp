// glint — the projective textured light.
#include "renderer/projective_light.h"

#include <algorithm>
#include <cmath>

namespace glint {

ProjectiveLight::ProjectiveLight(const Transform& worldFromLight, Rgb intensity, float fov,
                                 const Texture* texture, float attenuation, bool castsShadows)
    : Light(LightKind::DeltaPosition),
      worldFromLight_(worldFromLight),
      lightFromWorld_(worldFromLight.inverse()),
      position_(worldFromLight.point({0, 0, 0})),
      forward_(normalize(worldFromLight.vector({0, 0, -1}))),
      intensity_(intensity),
      tanHalf_(std::tan(fov / 2)),
      texture_(texture),
      attenuation_(std::clamp(attenuation, 0.0f, 1.0f)) {
  castsShadows_ = castsShadows;
  // Power: the intensity integrated over the frustum, on a grid over the slide at distance 1,
  // where a patch dA subtends dA cos^3(theta).
  constexpr int kGrid = 64;
  const float cell = 2 * tanHalf_ / kGrid;
  Rgb sum;
  for (int j = 0; j < kGrid; ++j)
    for (int i = 0; i < kGrid; ++i) {
      const Vec3f local{(float(i) + 0.5f) * cell - tanHalf_, (float(j) + 0.5f) * cell - tanHalf_,
                        -1};
      const float cosTheta = 1 / length(local);
      sum += this->intensity(normalize(worldFromLight_.vector(local))) *
             (cell * cell * cosTheta * cosTheta * cosTheta);
    }
  phi_ = sum;
}

Rgb ProjectiveLight::intensity(Vec3f w) const {
  const Vec3f l = lightFromWorld_.vector(w);
  if (!(l.z < 0)) return {};
  const float x = l.x / (-l.z * tanHalf_), y = l.y / (-l.z * tanHalf_);
  if (!(std::abs(x) <= 1 && std::abs(y) <= 1)) return {};
  if (!texture_ || attenuation_ == 0) return intensity_;
  TexturePoint tp;
  tp.uv = {0.5f * x + 0.5f, 0.5f * y + 0.5f};
  tp.p = {tp.uv.x, tp.uv.y, 0};
  const Vec4f t = texture_->evaluate(tp);
  return intensity_ * ((Rgb{1, 1, 1} * (1 - attenuation_)) + Rgb{t.x, t.y, t.z} * attenuation_);
}

std::optional<LightSample> ProjectiveLight::sampleLi(const LightSampleContext& ctx, Vec2f) const {
  const Vec3f toLight = position_ - ctx.p;
  const float r2 = lengthSquared(toLight);
  if (!(r2 > 0)) return std::nullopt;
  const Vec3f wi = toLight / std::sqrt(r2);
  const Rgb I = intensity(-wi);
  if (!(I.x > 0 || I.y > 0 || I.z > 0)) return std::nullopt;
  LightSample s;
  s.L = I * (1 / r2);
  s.wi = wi;
  s.pLight = position_;
  return s;
}

std::optional<LightLeSample> ProjectiveLight::sampleLe(Vec2f, Vec2f uDir, float time) const {
  // Uniform over the slide at distance 1: the solid-angle density is 1 / (area cos^3).
  const Vec3f local{(2 * uDir.x - 1) * tanHalf_, (2 * uDir.y - 1) * tanHalf_, -1};
  const float len = length(local), cosTheta = 1 / len;
  const Vec3f d = normalize(worldFromLight_.vector(local));
  LightLeSample s;
  s.L = intensity(d);
  if (!(s.L.x > 0 || s.L.y > 0 || s.L.z > 0)) return std::nullopt;
  s.ray = Ray{position_, d, 0, kInfinity, time};
  s.pdfDir = 1 / (4 * tanHalf_ * tanHalf_ * cosTheta * cosTheta * cosTheta);
  return s;
}

std::optional<LightBounds> ProjectiveLight::bounds() const {
  LightBounds b;
  b.bounds = Bounds3f{position_, position_};
  b.phi = luminance(phi_);
  b.w = forward_;
  b.cosThetaO = 1;
  b.cosThetaE = 1 / std::sqrt(1 + 2 * tanHalf_ * tanHalf_);  // the frustum's corner
  return b;
}

}  // namespace glint
