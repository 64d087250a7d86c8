// glint — point, spot and directional lights.
#include "renderer/light.h"

#include <cmath>

namespace glint {

namespace {
float rangeWindow(float distance, float range) {
  if (range <= 0) return 1;
  float x = distance / range;
  float w = std::clamp(1 - x * x * x * x, 0.0f, 1.0f);
  return w * w;
}
float smoothStep(float a, float b, float x) {
  if (a == b) return x < a ? 0.0f : 1.0f;
  float t = std::clamp((x - a) / (b - a), 0.0f, 1.0f);
  return t * t * (3 - 2 * t);
}
}  // namespace

PointLight::PointLight(Vec3f position, Rgb intensity, float range, bool castsShadows)
    : position_(position), intensity_(intensity), range_(range) {
  castsShadows_ = castsShadows;
}

std::optional<LightSample> PointLight::sampleLi(Vec3f p, Vec2f) const {
  Vec3f toLight = position_ - p;
  float r2 = lengthSquared(toLight);
  if (r2 == 0) return std::nullopt;
  float r = std::sqrt(r2);
  float window = rangeWindow(r, range_);
  if (window == 0) return std::nullopt;
  return LightSample{intensity_ * (window / r2), toLight / r, position_};
}

SpotLight::SpotLight(Vec3f position, Vec3f direction, Rgb intensity, float innerAngle,
                     float outerAngle, float range, bool castsShadows)
    : position_(position),
      direction_(normalize(direction)),
      intensity_(intensity),
      cosInner_(std::cos(innerAngle)),
      cosOuter_(std::cos(outerAngle)),
      range_(range) {
  castsShadows_ = castsShadows;
}

std::optional<LightSample> SpotLight::sampleLi(Vec3f p, Vec2f) const {
  Vec3f toLight = position_ - p;
  float r2 = lengthSquared(toLight);
  if (r2 == 0) return std::nullopt;
  float r = std::sqrt(r2);
  Vec3f wi = toLight / r;
  float cone = smoothStep(cosOuter_, cosInner_, dot(-wi, direction_));
  float window = rangeWindow(r, range_);
  if (cone == 0 || window == 0) return std::nullopt;
  return LightSample{intensity_ * (cone * window / r2), wi, position_};
}

float SpotLight::power() const {
  // Solid angle of the cone, counting the falloff band at half weight.
  return luminance(intensity_) * 2 * kPi * (1 - 0.5f * (cosInner_ + cosOuter_));
}

DirectionalLight::DirectionalLight(Vec3f direction, Rgb irradiance, bool castsShadows)
    : direction_(normalize(direction)), irradiance_(irradiance) {
  castsShadows_ = castsShadows;
}

std::optional<LightSample> DirectionalLight::sampleLi(Vec3f, Vec2f) const {
  LightSample s{irradiance_, -direction_, {}};
  s.infinite = true;
  return s;
}

}  // namespace glint
