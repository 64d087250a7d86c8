// glint — the projective textured light (a slide projector; the competition's cloud light).
#pragma once

#include "materials/texture.h"
#include "renderer/light.h"

namespace glint {

// A point light shining through a slide: only into the square frustum of full angle `fov`
// around its -Z axis (of worldFromLight, +Y up), with its intensity multiplied by
// (1 - attenuation) + attenuation * texture(uv). uv runs over the slide from (0, 0) at the
// frustum's -X, -Y corner to (1, 1) at +X, +Y; 3D textures see the slide as the point
// (u, v, 0) of their space. attenuation 0 = a plain frustum light, 1 = the full texture.
class ProjectiveLight final : public Light {
 public:
  // `texture` may be null (no slide); it must outlive the light.
  ProjectiveLight(const Transform& worldFromLight, Rgb intensity, float fov, const Texture* texture,
                  float attenuation, bool castsShadows);
  std::optional<LightSample> sampleLi(const LightSampleContext& ctx, Vec2f u) const override;
  std::optional<LightLeSample> sampleLe(Vec2f uPos, Vec2f uDir, float time) const override;
  Rgb phi() const override { return phi_; }
  std::optional<LightBounds> bounds() const override;
  // The intensity leaving the light along unit world direction w (zero outside the frustum).
  Rgb intensity(Vec3f w) const;

 private:
  Transform worldFromLight_, lightFromWorld_;
  Vec3f position_, forward_;
  Rgb intensity_;
  float tanHalf_;
  const Texture* texture_;
  float attenuation_;
  Rgb phi_;
};

}  // namespace glint
