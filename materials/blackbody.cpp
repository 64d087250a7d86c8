// glint — blackbody emission.
#include "materials/blackbody.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace glint {

namespace {

constexpr double kPlanckH = 6.62607015e-34;   // J s
constexpr double kLightC = 2.99792458e8;      // m / s
constexpr double kBoltzmannK = 1.380649e-23;  // J / K

// The colour table: 500 K to 40,000 K in steps of 50 K (the colour changes fastest at low
// temperatures, where a step of 50 K moves it by less than the fit's own error).
constexpr float kTableMin = 500, kTableMax = 40000, kTableStep = 50;
constexpr int kTableSize = int((kTableMax - kTableMin) / kTableStep) + 1;

// One lobe of the fit: a Gaussian with different widths left and right of its peak.
float lobe(float x, float mu, float left, float right) {
  const float t = (x - mu) / (x < mu ? left : right);
  return std::exp(-0.5f * t * t);
}

// Planck's spectrum integrated against the matching functions, 360 to 830 nm in 5 nm steps
// (within 1e-4 of 1 nm steps at every entry of the table; both curves are smooth at that
// scale). The table is built when the first fire loads: 1 nm steps took 20 ms of it.
Rgb integrateColor(double kelvin) {
  double xyz[3] = {0, 0, 0};
  for (int nm = 360; nm <= 830; nm += 5) {
    const double b = planck(nm, kelvin);
    const Vec3f cmf = cieXyz(float(nm));
    for (int c = 0; c < 3; ++c) xyz[c] += b * double(cmf[c]);
  }
  // Only the chromaticity matters here: normalise before rounding to float.
  const double y = xyz[1];
  Rgb rgb = max(Rgb{0, 0, 0}, rec709FromXyz(Vec3f{float(xyz[0] / y), 1, float(xyz[2] / y)}));
  // Luminance 1 after clamping.
  return rgb / luminance(rgb);
}

const std::array<Rgb, kTableSize>& colorTable() {
  static const std::array<Rgb, kTableSize> table = [] {
    std::array<Rgb, kTableSize> t;
    for (int i = 0; i < kTableSize; ++i)
      t[size_t(i)] = integrateColor(double(kTableMin) + double(i) * double(kTableStep));
    return t;
  }();
  return table;
}

}  // namespace

double planck(double nm, double kelvin) {
  if (!(kelvin > 0)) return 0;
  const double l = nm * 1e-9;
  const double x = kPlanckH * kLightC / (l * kBoltzmannK * kelvin);
  return 2 * kPlanckH * kLightC * kLightC / (std::pow(l, 5) * std::expm1(x));
}

Vec3f cieXyz(float nm) {
  return {1.056f * lobe(nm, 599.8f, 37.9f, 31.0f) + 0.362f * lobe(nm, 442.0f, 16.0f, 26.7f) -
              0.065f * lobe(nm, 501.1f, 20.4f, 26.2f),
          0.821f * lobe(nm, 568.8f, 46.9f, 40.5f) + 0.286f * lobe(nm, 530.9f, 16.3f, 31.1f),
          1.217f * lobe(nm, 437.0f, 11.8f, 36.0f) + 0.681f * lobe(nm, 459.0f, 26.0f, 13.8f)};
}

Rgb rec709FromXyz(Vec3f v) {
  return {3.2404542f * v.x - 1.5371385f * v.y - 0.4985314f * v.z,
          -0.9692660f * v.x + 1.8760108f * v.y + 0.0415560f * v.z,
          0.0556434f * v.x - 0.2040259f * v.y + 1.0572252f * v.z};
}

Rgb blackbodyColor(float kelvin) {
  const std::array<Rgb, kTableSize>& table = colorTable();
  const float f = (std::clamp(kelvin, kTableMin, kTableMax) - kTableMin) / kTableStep;
  const int i = std::min(int(f), kTableSize - 2);
  const float t = f - float(i);
  return table[size_t(i)] * (1 - t) + table[size_t(i) + 1] * t;
}

Rgb blackbodyEmission(float kelvin) {
  if (!(kelvin > 0)) return {0, 0, 0};
  const double t2 = double(kelvin) * double(kelvin);
  const float radiance = float(1e-6 * kStefanBoltzmann * t2 * t2 / std::numbers::pi);
  return blackbodyColor(kelvin) * radiance;
}

}  // namespace glint
