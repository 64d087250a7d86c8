// glint — lights. Each light answers one question: how much light arrives at a point, from
// which direction, and where a shadow ray must go to check visibility.
#pragma once

#include <optional>

#include "geometry/interaction.h"

namespace glint {

struct LightSample {
  Rgb Li;            // incident radiance (delta lights: irradiance-like intensity / r^2)
  Vec3f wi;          // unit direction from the point towards the light
  Vec3f pLight;      // the light point (for shadow rays); unused when `infinite`
  bool infinite = false;  // directional: shadow rays go to infinity
  float pdf = 1;     // solid-angle pdf (1 for delta lights)
  bool delta = true; // point, spot, directional: cannot be hit by rays
};

class Light {
 public:
  virtual ~Light() = default;
  // Light arriving at `p` (a receiving point); nullopt when none can arrive (outside a cone,
  // beyond the range). `u` is unused by delta lights and drives area lights later.
  virtual std::optional<LightSample> sampleLi(Vec3f p, Vec2f u) const = 0;
  // Total emitted power (for power-proportional light selection later).
  virtual float power() const = 0;
  // True for lights that occupy no area or solid angle (they ignore `u`).
  virtual bool isDelta() const { return true; }
  bool castsShadows() const { return castsShadows_; }

 protected:
  bool castsShadows_ = true;
};

// Isotropic point light: I / r^2, with glTF's optional range window
// clamp(1 - (r/range)^4, 0, 1)^2 (KHR_lights_punctual's recommended falloff).
class PointLight final : public Light {
 public:
  PointLight(Vec3f position, Rgb intensity, float range, bool castsShadows);
  std::optional<LightSample> sampleLi(Vec3f p, Vec2f u) const override;
  float power() const override { return 4 * kPi * luminance(intensity_); }

 private:
  Vec3f position_;
  Rgb intensity_;
  float range_;
};

// Spot light: a point light shining down `direction`, full inside the inner cone and fading
// smoothly (smoothstep in cos) to zero at the outer cone.
class SpotLight final : public Light {
 public:
  SpotLight(Vec3f position, Vec3f direction, Rgb intensity, float innerAngle, float outerAngle,
            float range, bool castsShadows);
  std::optional<LightSample> sampleLi(Vec3f p, Vec2f u) const override;
  float power() const override;

 private:
  Vec3f position_, direction_;
  Rgb intensity_;
  float cosInner_, cosOuter_, range_;
};

// Directional light: irradiance E (on a surface facing it) from direction -`direction`.
class DirectionalLight final : public Light {
 public:
  DirectionalLight(Vec3f direction, Rgb irradiance, bool castsShadows);
  std::optional<LightSample> sampleLi(Vec3f p, Vec2f u) const override;
  float power() const override { return luminance(irradiance_); }  // per unit area

 private:
  Vec3f direction_;  // unit, the way the light travels
  Rgb irradiance_;
};

}  // namespace glint
