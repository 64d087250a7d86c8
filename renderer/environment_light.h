// glint — the image environment: an equirectangular radiance map at infinity, importance
// sampled in proportion to its luminance.
#pragma once

#include <vector>

#include "renderer/light.h"

namespace glint {

// A piecewise-constant density on [0, 1) from n non-negative values (all zero: uniform).
class PiecewiseConstant1D {
 public:
  PiecewiseConstant1D() = default;
  explicit PiecewiseConstant1D(const std::vector<float>& f);
  size_t size() const { return func_.size(); }
  float integral() const { return integral_; }  // of the (clamped) function over [0, 1)
  // x in [0, 1) for u in [0, 1), its density, and the cell it fell in.
  float sample(float u, float* pdf, size_t* cell) const;
  float pdf(float x) const;

 private:
  std::vector<float> func_;
  std::vector<double> cdf_;  // size n + 1
  float integral_ = 0;
  bool uniform_ = false;
};

// A piecewise-constant density on [0, 1)^2 over an nu x nv grid of values (row v, column u):
// v from the marginal of the rows, then u from the chosen row.
class Distribution2D {
 public:
  Distribution2D() = default;
  Distribution2D(const std::vector<float>& f, int nu, int nv);
  Vec2f sample(Vec2f u, float* pdf) const;
  float pdf(Vec2f p) const;

 private:
  std::vector<PiecewiseConstant1D> rows_;
  PiecewiseConstant1D marginal_;
};

// Radiance from an equirectangular image (`width` x `height` RGB, row 0 at the top, +Y up):
// the image's centre looks down -Z, u grows towards +X; `rotation` (radians) turns the map
// about +Y. Radiance is the bilinear interpolation of the pixels times `scale`; the
// piecewise-constant sampling density follows the luminance, widened by one pixel so that it is
// non-zero wherever the interpolated radiance is.
class ImageEnvironmentLight final : public Light {
 public:
  ImageEnvironmentLight(int width, int height, std::vector<Rgb> pixels, float scale,
                        float rotation);
  std::optional<LightSample> sampleLi(const LightSampleContext& ctx, Vec2f u) const override;
  float pdfLi(const LightSampleContext& ctx, Vec3f wi, const LightHit& hit) const override;
  Rgb Le(Vec3f d) const override;
  std::optional<LightLeSample> sampleLe(Vec2f uPos, Vec2f uDir, float time) const override;
  Rgb phi() const override;
  DistantImportance distantImportance() const override;
  void preprocess(const Bounds3f& sceneBounds) override;

  // The map coordinates of a world direction, and back.
  Vec2f uvOf(Vec3f d) const;
  Vec3f directionOf(Vec2f uv) const;

 private:
  Rgb pixel(Vec2f uv) const;
  float pdfOf(Vec2f uv) const;  // solid-angle density of the direction at uv
  int width_, height_;
  std::vector<Rgb> pixels_;
  float scale_;
  float cosRot_, sinRot_;
  Distribution2D distribution_;
  Vec3f sceneCenter_;
  float sceneRadius_ = 1;
};

// The studio: glint's default environment, an equirectangular map (`width` x `height`, the
// layout ImageEnvironmentLight reads) of a neutral grey room. A bright round softbox above and
// to the front left of the default camera (towards -X, +Y, +Z: a glTF asset faces +Z) gives a
// soft shadow and a highlight on metals; a dimmer strip behind and to the right gives rough and
// metallic surfaces a rim; a sky that brightens towards the zenith and a darker floor below the
// horizon give reflections a horizon line. All of it is grey (R = G = B), so it does not tint an
// asset's colours, and it is scaled so that a white Lambert surface facing up reflects
// radiance 1 (irradiance pi), as glint's earlier headlight did for a surface facing it.
std::vector<Rgb> studioEnvironment(int width, int height);

}  // namespace glint
