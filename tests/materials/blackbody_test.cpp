// glint tests — blackbody emission against Planck's law: the Stefan–Boltzmann total, the
// luminance normalisation (as Cycles' Principled Volume), the T^4 growth, and the colour on
// the Planckian locus (Kim et al. 2002's cubic fit of the CIE 1931 locus, an independent
// reference).
#include "materials/blackbody.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace glint {
namespace {

// CIE xy of a linear Rec.709 colour.
Vec2f chromaticity(Rgb c) {
  const float X = 0.4124564f * c.x + 0.3575761f * c.y + 0.1804375f * c.z;
  const float Y = luminance(c);
  const float Z = 0.0193339f * c.x + 0.1191920f * c.y + 0.9503041f * c.z;
  return {X / (X + Y + Z), Y / (X + Y + Z)};
}

// The Planckian locus, Kim et al. (2002), for 1,667 K to 25,000 K.
Vec2f planckianLocus(double T) {
  const double t = 1e3 / T, t2 = t * t, t3 = t2 * t;
  const double x = T <= 4000 ? -0.2661239 * t3 - 0.2343589 * t2 + 0.8776956 * t + 0.179910
                             : -3.0258469 * t3 + 2.1070379 * t2 + 0.2226347 * t + 0.240390;
  const double x2 = x * x, x3 = x2 * x;
  double y;
  if (T <= 2222)
    y = -1.1063814 * x3 - 1.34811020 * x2 + 2.18555832 * x - 0.20219683;
  else if (T <= 4000)
    y = -0.9549476 * x3 - 1.37418593 * x2 + 2.09137015 * x - 0.16748867;
  else
    y = 3.0817580 * x3 - 5.87338670 * x2 + 3.75112997 * x - 0.37001483;
  return {float(x), float(y)};
}

// pi times Planck's law integrated over all wavelengths is sigma T^4 (the constants agree).
TEST(Blackbody, PlancksLawIntegratesToStefanBoltzmann) {
  for (double T : {800.0, 1500.0, 6500.0}) {
    // Log-spaced from 10 nm to 1 mm: the spectrum is negligible outside.
    double total = 0;
    const int n = 20000;
    const double a = std::log(10.0), b = std::log(1e6);
    for (int i = 0; i < n; ++i) {
      const double l0 = std::exp(a + (b - a) * i / n), l1 = std::exp(a + (b - a) * (i + 1) / n);
      const double mid = 0.5 * (l0 + l1);
      total += planck(mid, T) * (l1 - l0) * 1e-9;  // per metre of wavelength
    }
    EXPECT_NEAR(std::numbers::pi * total / (kStefanBoltzmann * T * T * T * T), 1.0, 1e-3) << T;
  }
}

// Luminance 1e-6 sigma T^4 / pi: Cycles' Principled Volume at Blackbody Intensity 1.
TEST(Blackbody, LuminanceIsStefanBoltzmannOverPiTimesOneMillionth) {
  for (float T : {600.0f, 1000.0f, 1500.0f, 3000.0f, 6500.0f, 12000.0f}) {
    const double expected = 1e-6 * kStefanBoltzmann * std::pow(double(T), 4) / std::numbers::pi;
    EXPECT_NEAR(luminance(blackbodyEmission(T)) / expected, 1.0, 2e-4) << T;
  }
  EXPECT_NEAR(luminance(blackbodyEmission(3000)) / luminance(blackbodyEmission(1500)), 16, 0.01);
  EXPECT_EQ(blackbodyEmission(0), (Rgb{0, 0, 0}));
  EXPECT_EQ(blackbodyEmission(-5), (Rgb{0, 0, 0}));
}

// The colour is Planck's: on the locus where Rec.709 can show it, red and dim below, bluish
// above 6,500 K.
TEST(Blackbody, ColourLiesOnThePlanckianLocus) {
  for (float T : {3000.0f, 4000.0f, 5000.0f, 6500.0f, 10000.0f, 20000.0f}) {
    const Vec2f xy = chromaticity(blackbodyColor(T)), ref = planckianLocus(T);
    EXPECT_NEAR(xy.x, ref.x, 0.004f) << T;
    EXPECT_NEAR(xy.y, ref.y, 0.004f) << T;
  }
  const Rgb low = blackbodyColor(1200), high = blackbodyColor(15000);
  EXPECT_GT(low.x, low.y);
  EXPECT_GE(low.y, low.z);
  EXPECT_GT(high.z, high.x);
  for (float T = 500; T < 40000; T *= 1.1f) {
    const Rgb c = blackbodyColor(T);
    EXPECT_GE(std::min({c.x, c.y, c.z}), 0) << T;
  }
}

}  // namespace
}  // namespace glint
