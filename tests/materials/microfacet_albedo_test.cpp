// The GGX albedo tables (materials/microfacet_albedo.h) against an independent integration:
// the tables sample visible normals; here the albedo is integrated over the half vector with
// the NDF's own distribution D(h) cos(theta_h), in double precision on a fine stratified grid.
// Also: their limits (a smooth interface is its Fresnel reflectance, F = 1 at roughness 0 is
// a mirror, index 1 reflects nothing) and the averages' definition.
#include "materials/microfacet_albedo.h"

#include <gtest/gtest.h>

#include <cmath>

#include "materials/microfacet.h"
#include "materials/scattering.h"

namespace glint {
namespace {

// E_F(mu) = int D(h) G(wo, wi) F(wo.h) |wo.h| / mu dw_h, wi = reflect(wo, h), by sampling h
// with density D(h) h.z (tan^2 theta = alpha^2 u / (1 - u)) on an n x n midpoint grid.
// eta 0 stands for F = 1.
double referenceAlbedo(float mu, float roughness, float eta, int n = 600) {
  const double alpha = TrowbridgeReitzDistribution::roughnessToAlpha(roughness);
  const TrowbridgeReitzDistribution ggx{float(alpha)};
  const Vec3f wo{std::sqrt(1 - mu * mu), 0, mu};
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double u = (i + 0.5) / n;
    const double tan2 = alpha * alpha * u / (1 - u);
    const double cosH = 1 / std::sqrt(1 + tan2), sinH = std::sqrt(1 - cosH * cosH);
    for (int j = 0; j < n; ++j) {
      const double phi = 2 * kPi * (j + 0.5) / n;
      const Vec3f h{float(sinH * std::cos(phi)), float(sinH * std::sin(phi)), float(cosH)};
      const float woH = dot(wo, h);
      if (woH <= 0) continue;
      const Vec3f wi = h * (2 * woH) - wo;
      if (wi.z <= 0) continue;
      const double F = eta > 0 ? fresnelDielectric(woH, eta) : 1.0;
      sum += F * ggx.G(wo, wi) * woH / (mu * cosH);
    }
  }
  return sum / (double(n) * n);
}

// The tables agree with the independent integral within 4e-3 (their sampling and
// interpolation; the entries between grid points are the hard case, so most probes are off
// the grid), for F = 1 and for indices 1.33, 1.5 and 2.4.
TEST(GgxAlbedo, TablesMatchAnIndependentIntegral) {
  double worst = 0;
  for (float roughness : {0.15f, 0.3f, 0.55f, 0.8f, 1.0f})
    for (float mu : {0.05f, 0.2f, 0.45f, 0.7f, 1.0f}) {
      const double e1 = referenceAlbedo(mu, roughness, 0);
      EXPECT_NEAR(ggxAlbedo(mu, roughness), e1, 4e-3) << "roughness " << roughness << " mu " << mu;
      worst = std::max(worst, std::abs(ggxAlbedo(mu, roughness) - e1));
      for (float eta : {1.33f, 1.5f, 2.4f}) {
        const double eF = referenceAlbedo(mu, roughness, eta);
        EXPECT_NEAR(ggxDielectricAlbedo(mu, roughness, eta), eF, 4e-3)
            << "roughness " << roughness << " mu " << mu << " eta " << eta;
        worst = std::max(worst, std::abs(ggxDielectricAlbedo(mu, roughness, eta) - eF));
        // Seen from the denser side the opaque layer's table reads the same interface.
        EXPECT_EQ(ggxDielectricAlbedo(mu, roughness, 1 / eta),
                  ggxDielectricAlbedo(mu, roughness, eta));
      }
    }
  std::printf("  largest table error: %.4f\n", worst);
}

// A smooth interface: F = 1 is a mirror (E = 1), the exact Fresnel at the entry's grid; index
// 1 is no interface (E = 0); an albedo never exceeds 1. (E is not monotone in roughness: at
// grazing views, rougher surfaces turn some microfacets towards the viewer, E(0.1) rises from
// 0.88 at roughness 0.3 to 0.89 at 0.5 before it falls.)
TEST(GgxAlbedo, LimitsHold) {
  for (float mu : {0.1f, 0.5f, 1.0f}) {
    EXPECT_NEAR(ggxAlbedo(mu, 0), 1, 2e-3) << mu;
    EXPECT_NEAR(ggxDielectricAlbedo(mu, 0, 1.5f), fresnelDielectric(mu, 1.5f), 4e-3) << mu;
    EXPECT_EQ(ggxDielectricAlbedo(mu, 0.5f, 1), 0) << mu;
    for (float r = 0; r <= 1.0f; r += 0.1f) {
      EXPECT_LE(ggxAlbedo(mu, r), 1) << "mu " << mu << " roughness " << r;
      EXPECT_LE(ggxDielectricAlbedo(mu, r, 1.5f), ggxAlbedo(mu, r)) << "mu " << mu << " r " << r;
    }
  }
}

// The averages are 2 int E(mu) mu dmu of the same lookups, and the smooth average Fresnel is
// 2 int F(mu) mu dmu (for index 1.5 the classic value 0.0918, e.g. Walter et al.'s "internal
// reflection of a diffuse layer" tables: 1 - 0.0918 of diffuse light leaves glass).
TEST(GgxAlbedo, AveragesIntegrateTheirTables) {
  for (float roughness : {0.2f, 0.6f, 1.0f}) {
    double e1 = 0, eF = 0;
    constexpr int kN = 4000;
    for (int k = 0; k < kN; ++k) {
      const float mu = (k + 0.5f) / kN;
      e1 += ggxAlbedo(mu, roughness) * mu;
      eF += ggxDielectricAlbedo(mu, roughness, 1.5f) * mu;
    }
    EXPECT_NEAR(ggxAverageAlbedo(roughness), 2 * e1 / kN, 2e-3) << roughness;
    EXPECT_NEAR(ggxDielectricAverageAlbedo(roughness, 1.5f), 2 * eF / kN, 2e-3) << roughness;
  }
  EXPECT_NEAR(dielectricFresnelAverage(1.5f), 0.0918, 5e-4);
  EXPECT_NEAR(dielectricFresnelAverage(1 / 1.5f), 0.0918, 5e-4);
  EXPECT_EQ(dielectricFresnelAverage(1), 0);
}

}  // namespace
}  // namespace glint
