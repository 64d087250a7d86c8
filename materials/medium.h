// glint — participating media: what a medium is made of, independent of how rays cross it
// (renderer/volume.h integrates along rays; scenes/build_media.cpp builds media from the
// sidecar's "media").
//
// A Medium has base coefficients per unit length — absorption sigma_a, scattering sigma_s
// (RGB), emission Le (RGB radiance emitted per unit length) — a Henyey–Greenstein g
// (materials/phase.h) and a density field d(p) >= 0 that scales all three:
//   sigma_t(p) = (sigma_a + sigma_s) d(p),   emitted radiance per unit length = Le d(p).
// A homogeneous segment of length s thus adds Le / sigma_t (1 - exp(-sigma_t s)) (Le s where
// sigma_t = 0) and transmits exp(-sigma_t s).
//
// Density fields are evaluated in the object space of the region the medium fills, and report
// a maximum (the majorant for tracking) over that region's object-space bounds.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "geometry/math.h"
#include "materials/majorant_grid.h"
#include "materials/noise.h"

namespace glint {

// ---------------------------------------------------------------------------------------------
// Density fields
// ---------------------------------------------------------------------------------------------

class DensityField {
 public:
  virtual ~DensityField() = default;
  // The density at an object-space point (>= 0, finite).
  virtual float density(Vec3f p) const = 0;
  // An upper bound of density() over the object-space box `region`.
  virtual float maxDensity(const Bounds3f& region) const = 0;
  // True when density() is the same everywhere: transmittance is then exp(-sigma_t s).
  virtual bool isConstant() const { return false; }
  // Bounds of density() cell by cell over the object-space region, for trackers that skip
  // empty space (materials/majorant_grid.h); null: maxDensity() of the region is the only one.
  virtual const MajorantGrid* majorantGrid() const { return nullptr; }
};

// Emission of a medium's own that is not proportional to its density (a VDB fire's blackbody
// radiation from a temperature grid, a flame grid): radiance per unit length at an
// object-space point, added to Le x density.
class EmissionField {
 public:
  virtual ~EmissionField() = default;
  virtual Rgb emission(Vec3f p) const = 0;
  // A bound of emission()'s luminance cell by cell, over the same cells as the density's
  // majorant grid (positive wherever the emission can be); null: none. It tells the path
  // tracer's emission estimator where to spend its samples (renderer/volume.cpp).
  virtual const MajorantGrid* luminanceBound() const { return nullptr; }
};

// A scattering colour per point (a VDB medium's colour grid): sigma_s(p) = sigma_s x color(p)
// x density(p). Object space, as density fields.
class ColorField {
 public:
  virtual ~ColorField() = default;
  // >= 0 per component. `density` is the medium's density at p (its DensityField's value, which
  // the caller has already looked up): a colour weighted by the density divides by it.
  virtual Rgb color(Vec3f p, float density) const = 0;
  virtual Rgb maxColor() const = 0;  // a bound of color() per component
};

// The same density everywhere (a homogeneous medium).
class ConstantDensity final : public DensityField {
 public:
  explicit ConstantDensity(float value) : value_(value) {}
  float density(Vec3f) const override { return value_; }
  float maxDensity(const Bounds3f&) const override { return value_; }
  bool isConstant() const override { return true; }

 private:
  float value_;
};

// A grid of nx x ny x nz values (x fastest) whose nodes span the box `bounds`: node (0,0,0) at
// bounds.lower, node (nx-1, ny-1, nz-1) at bounds.upper (Mitsuba's gridvolume convention);
// trilinear in between, clamped to the boundary nodes outside. Values < 0 are read as 0.
// (Grids come from the sidecar's values or from .vol files, read by scenes/vol_file.h.)
class GridDensity final : public DensityField {
 public:
  // Throws std::logic_error when values.size() is not nx * ny * nz: the sidecar's reader
  // checks the count (scenes/sidecar_media.cpp), so a mismatch here is a bug.
  GridDensity(int nx, int ny, int nz, std::vector<float> values, const Bounds3f& bounds);
  float density(Vec3f p) const override;
  float maxDensity(const Bounds3f&) const override { return max_; }

 private:
  float at(int x, int y, int z) const { return values_[(size_t(z) * ny_ + y) * nx_ + x]; }
  int nx_, ny_, nz_;
  std::vector<float> values_;
  Bounds3f bounds_;
  float max_ = 0;
};

// Clouds from fractal Perlin noise: n = 0.5 + 0.5 fbm(scale (p - offset)) / (sum of octave
// amplitudes), clamped to [0, 1]; density = max(0, n - threshold) / (1 - threshold), in [0, 1].
// A keyframed offset moves the pattern through its region (smoke rising, clouds drifting).
class NoiseDensity final : public DensityField {
 public:
  NoiseDensity(float scale, int octaves, float threshold, uint64_t seed, Vec3f offset = {0, 0, 0});
  float density(Vec3f p) const override;
  float maxDensity(const Bounds3f&) const override { return 1; }

 private:
  PerlinNoise noise_;
  float scale_;
  Vec3f offset_;
  int octaves_;
  float threshold_;
  float amplitudeSum_;
};

// Height fog: density = exp(-falloff (dot(p, up) - h0)), densest below h0 for falloff > 0.
// The exponent is clamped at 60 so that far below h0 the density stays finite.
class ExponentialDensity final : public DensityField {
 public:
  ExponentialDensity(Vec3f up, float falloff, float h0);
  float density(Vec3f p) const override;
  float maxDensity(const Bounds3f& region) const override;

 private:
  Vec3f up_;  // unit
  float falloff_, h0_;
};

// ---------------------------------------------------------------------------------------------
// Medium
// ---------------------------------------------------------------------------------------------

struct Medium {
  std::string name;
  Rgb sigmaA{0, 0, 0}, sigmaS{0, 0, 0};  // per unit length, at density 1
  Rgb Le{0, 0, 0};                       // emitted radiance per unit length, at density 1
  float g = 0;                           // Henyey–Greenstein asymmetry, |g| < 1
  std::unique_ptr<DensityField> density;
  std::unique_ptr<EmissionField> emissionField;  // null: Le x density is all it emits
  std::unique_ptr<ColorField> color;             // null: sigma_s alone (a colour of 1)
  // What the colour field does besides scaling sigma_s: false, nothing (sigma_a stays, so
  // sigma_t = sigma_a + sigma_s x colour); true, it tints the albedo, sigma_a taking what
  // scattering gives up, so sigma_t stays sigma_a + sigma_s where the colour is at most 1
  // (sigma_t = max(sigma_a + sigma_s, sigma_s x colour)): Cycles' Principled Volume with a
  // colour attribute and a black Absorption Color.
  bool colorTintsAlbedo = false;
  // Coloured extinction (sigma_t differing between channels) tracked by spectral MIS over a
  // hero channel (renderer/volume.cpp); false: against the largest channel, with channel-mean
  // event probabilities (the older estimator: unbiased, heavy-tailed).
  bool heroTracking = true;

  Rgb sigmaT() const { return sigmaA + sigmaS; }
  // sigma_t at density 1 where sigma_s (the colour field's included) is `scattering`.
  Rgb sigmaT(const Rgb& scattering) const {
    return colorTintsAlbedo ? max(sigmaT(), scattering) : sigmaA + scattering;
  }
  // sigma_t's bound per channel at density 1, the colour field's included: the majorants'.
  Rgb sigmaTBound() const { return color ? sigmaT(sigmaS * color->maxColor()) : sigmaT(); }
  bool emits() const { return maxComponent(Le) > 0 || emissionField; }
  bool scatters() const { return maxComponent(sigmaS) > 0; }
  bool homogeneous() const { return density->isConstant(); }
};

}  // namespace glint
