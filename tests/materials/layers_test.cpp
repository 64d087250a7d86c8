// The physics of glTF's material layers against closed forms (materials/layers.h): thin films
// (bare interface, quarter- and half-wave layers), the Charlie sheen's normalisation and its
// albedo table, the dispersion formula's Abbe number, and dispersive refraction obeying Snell's
// law per channel.
#include "materials/layers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "materials/bxdfs.h"
#include "materials/scattering.h"

namespace glint {
namespace {

// A film of zero thickness is no film: the bare substrate's Fresnel reflectance, at every angle
// and for every film index.
TEST(ThinFilm, ZeroThicknessIsTheBareInterface) {
  for (float film : {1.0f, 1.3f, 2.0f})
    for (float c : {1.0f, 0.8f, 0.5f, 0.2f, 0.05f})
      EXPECT_NEAR(thinFilmReflectance(c, film, 1.5f, 0, 550), fresnelDielectric(c, 1.5f), 1e-5f)
          << "film " << film << " cos " << c;
}

// A quarter-wave layer of index sqrt(n_substrate) cancels the reflection at its wavelength at
// normal incidence (the classic anti-reflection coating): both interfaces reflect the same
// amplitude, half a wave apart. A half-wave layer is "absent": the bare substrate's
// reflectance. Away from the design wavelength the coating reflects again.
TEST(ThinFilm, QuarterWaveCoatingCancelsAndHalfWaveIsAbsent) {
  const float substrate = 2.25f, film = 1.5f, lambda = 550;
  const float quarter = lambda / (4 * film), half = lambda / (2 * film);
  EXPECT_LT(thinFilmReflectance(1, film, substrate, quarter, lambda), 1e-6f);
  EXPECT_NEAR(thinFilmReflectance(1, film, substrate, half, lambda),
              fresnelDielectric(1, substrate), 1e-5f);
  EXPECT_GT(thinFilmReflectance(1, film, substrate, quarter, 400), 0.01f);
  // The closed form for the quarter-wave layer at normal incidence, off its wavelength, is
  // the Airy sum with cos(delta) = cos(pi lambda0 / lambda).
  const float r12 = (1 - film) / (1 + film), r23 = (film - substrate) / (film + substrate);
  const float cd = std::cos(kPi * lambda / 450);
  const float expected = (r12 * r12 + r23 * r23 + 2 * r12 * r23 * cd) /
                         (1 + r12 * r12 * r23 * r23 + 2 * r12 * r23 * cd);
  EXPECT_NEAR(thinFilmReflectance(1, film, substrate, quarter, 450), expected, 1e-5f);
}

// The film reflects at most everything, and its RGB Fresnel moves with the thickness (the
// colours of a soap film).
TEST(ThinFilm, ColoursChangeWithThicknessAndStayInRange) {
  Rgb previous;
  int changes = 0;
  for (float d = 100; d <= 800; d += 50) {
    const Rgb f = thinFilmFresnel(0.7f, 1.3f, Rgb{1.5f, 1.5f, 1.5f}, d);
    for (int c = 0; c < 3; ++c) {
      EXPECT_GE(f[c], 0);
      EXPECT_LE(f[c], 1);
    }
    if (d > 100 && maxComponent(abs(f - previous)) > 0.01f) ++changes;
    previous = f;
  }
  EXPECT_GE(changes, 10);
}

// The Charlie distribution is normalised: the integral of D cos(theta_h) over the hemisphere
// is 1 (midpoint rule in cos(theta), 4000 steps).
TEST(Sheen, DistributionIsNormalised) {
  for (float alpha : {0.1f, 0.3f, 0.7f, 1.0f}) {
    double sum = 0;
    constexpr int kSteps = 4000;
    for (int i = 0; i < kSteps; ++i) {
      const double c = (i + 0.5) / kSteps;
      sum += double(sheenD(float(c), alpha)) * c * 2 * kPi / kSteps;
    }
    EXPECT_NEAR(sum, 1, 2e-3) << "alpha " << alpha;
  }
}

// The albedo table agrees with a Monte Carlo integral of the BRDF (uniform hemisphere
// sampling, 2e5 samples), and no white sheen reflects more than it receives.
TEST(Sheen, AlbedoTableMatchesTheIntegral) {
  std::mt19937_64 rng(5);
  auto uniform = [&] { return float(rng() >> 40) * 0x1p-24f; };
  for (float roughness : {0.2f, 0.5f, 1.0f})
    for (float c : {1.0f, 0.6f, 0.3f, 0.1f}) {
      const float alpha = std::max(roughness * roughness, kMinSheenAlpha);
      const Vec3f wo{std::sqrt(1 - c * c), 0, c};
      double sum = 0, sum2 = 0;
      constexpr int kN = 200'000;
      for (int i = 0; i < kN; ++i) {
        const float z = uniform(), phi = 2 * kPi * uniform();
        const float r = std::sqrt(std::max(0.0f, 1 - z * z));
        const Vec3f wi{r * std::cos(phi), r * std::sin(phi), z};
        const Vec3f h = normalize(wo + wi);
        const double v = double(sheenBrdf(c, z, h.z, alpha)) * z * 2 * kPi;
        sum += v, sum2 += v * v;
      }
      const double mean = sum / kN, se = std::sqrt((sum2 / kN - mean * mean) / kN);
      const float table = sheenAlbedo(c, roughness);
      EXPECT_LE(table, 1);
      EXPECT_NEAR(table, mean, 4 * se + 5e-3) << "roughness " << roughness << " cos " << c;
    }
}

// Abbe's number V = (n_d - 1) / (n_F - n_C) is what glTF's dispersion = 20 / V says; the index
// at the d line (587.6 nm) is the material's.
TEST(Dispersion, IndexFollowsTheAbbeNumber) {
  for (float ior : {1.33f, 1.5f, 1.9f})
    for (float dispersion : {0.2f, 0.5f, 1.0f}) {
      const float V = 20 / dispersion;
      EXPECT_NEAR(dispersedIor(ior, dispersion, 587.56f), ior, 2e-4f);
      const float nF = dispersedIor(ior, dispersion, 486.13f),
                  nC = dispersedIor(ior, dispersion, 656.27f);
      EXPECT_NEAR((ior - 1) / (nF - nC), V, 0.01f * V);
    }
  EXPECT_EQ(dispersedIor(1.5f, 0, 400), 1.5f);
}

// Smooth dispersive glass: each colour channel refracts by Snell's law with its own index,
// one channel per sample (the lobe number's remainder picks it), carrying three times its
// transmittance in that channel only.
TEST(Dispersion, EachChannelRefractsWithItsOwnIndex) {
  PbrHit hit;
  hit.base = {1, 1, 1};
  hit.roughness = 0;
  hit.transmission = 1;
  hit.eta = 1.5f;
  hit.dispersion = 1;
  const float sinI = 0.6f;
  const Vec3f wo{sinI, 0, 0.8f};
  const PbrBxdf bxdf(wo, hit);
  for (int c = 0; c < 3; ++c) {
    BsdfSample s;
    ASSERT_TRUE(bxdf.sample(wo, {0.5f, 0.5f}, (c + 0.5f) / 3, kBsdfTransmission, &s))
        << "channel " << c;
    const float n = dispersedIor(1.5f, 1, kChannelWavelengthNm[c]);
    const float sinT = std::sqrt(s.wi.x * s.wi.x + s.wi.y * s.wi.y);
    EXPECT_NEAR(sinT, sinI / n, 1e-5f) << "channel " << c;
    EXPECT_LT(s.wi.z, 0);
    EXPECT_NEAR(s.eta, n, 1e-5f);
    for (int k = 0; k < 3; ++k) {
      if (k == c)
        EXPECT_GT(s.f[k], 0);
      else
        EXPECT_EQ(s.f[k], 0);
    }
    // Weight: T / (eta^2) per unit pdf, with the 1/3 channel choice in the pdf.
    const float T = 1 - fresnelDielectric(0.8f, n);
    EXPECT_NEAR(s.f[c] * std::abs(s.wi.z) / s.pdf, 3 * T / (n * n), 1e-4f);
  }
  // Blue bends most: its refracted direction lies closest to the normal.
  BsdfSample red, blue;
  ASSERT_TRUE(bxdf.sample(wo, {0.5f, 0.5f}, 0.1f, kBsdfTransmission, &red));
  ASSERT_TRUE(bxdf.sample(wo, {0.5f, 0.5f}, 0.9f, kBsdfTransmission, &blue));
  EXPECT_GT(std::abs(red.wi.x), std::abs(blue.wi.x));
}

// Anisotropy stretches the highlight along its direction: at normal incidence the sampled
// reflections of a rough metal spread further along the direction than across it, and
// turning the direction by 90 degrees swaps the axes.
TEST(Anisotropy, HighlightStretchesAlongTheDirection) {
  PbrHit hit;
  hit.base = {1, 1, 1};
  hit.metallic = 1;
  hit.roughness = 0.3f;
  hit.anisotropy = 0.8f;
  const Vec3f wo{0, 0, 1};
  for (Vec2f dir : {Vec2f{1, 0}, Vec2f{0, 1}}) {
    hit.anisotropyDirection = dir;
    const PbrBxdf bxdf(wo, hit);
    std::mt19937_64 rng(9);
    auto uniform = [&] { return float(rng() >> 40) * 0x1p-24f; };
    double xx = 0, yy = 0;
    for (int i = 0; i < 20'000; ++i) {
      BsdfSample s;
      if (!bxdf.sample(wo, {uniform(), uniform()}, uniform(), kBsdfAllLobes, &s)) continue;
      xx += s.wi.x * s.wi.x, yy += s.wi.y * s.wi.y;
    }
    if (dir.x == 1)
      EXPECT_GT(xx, 3 * yy);
    else
      EXPECT_GT(yy, 3 * xx);
  }
}

}  // namespace
}  // namespace glint
