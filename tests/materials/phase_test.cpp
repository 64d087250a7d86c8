// Henyey–Greenstein: normalisation, sampling against the density by chi-square, and the
// limits g -> 0 and |g| -> 1.
#include "materials/phase.h"

#include <gtest/gtest.h>

#include <cmath>

#include "chi2.h"

namespace glint {
namespace {

// The integral of p over the sphere, 2 pi * integral over cosTheta, by the midpoint rule on a
// fine grid in cosTheta (the integrand is smooth for |g| < 1).
double integrateOverSphere(float g) {
  const int n = 2'000'000;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double c = -1 + (i + 0.5) * 2.0 / n;
    sum += henyeyGreenstein(float(c), g);
  }
  return 2 * M_PI * sum * 2.0 / n;
}

TEST(HenyeyGreenstein, NormalisesToOne) {
  for (float g : {-0.9f, -0.3f, 0.0f, 0.5f, 0.95f})
    EXPECT_NEAR(integrateOverSphere(g), 1.0, 2e-3) << "g = " << g;
}

TEST(HenyeyGreenstein, IsotropicAtZeroAndPeakedForwardForPositiveG) {
  EXPECT_NEAR(henyeyGreenstein(0.3f, 0), 1 / (4 * kPi), 1e-7f);
  EXPECT_GT(henyeyGreenstein(1, 0.5f), henyeyGreenstein(-1, 0.5f));
  EXPECT_GT(henyeyGreenstein(-1, -0.5f), henyeyGreenstein(1, -0.5f));
  // Closed form at the poles: (1 - g^2) / (4 pi (1 -+ g)^3).
  EXPECT_NEAR(henyeyGreenstein(1, 0.5f), (1 - 0.25f) / (4 * kPi * 0.125f), 1e-5f);
}

TEST(HenyeyGreenstein, SamplingIsContinuousAcrossGZero) {
  // The isotropic branch near g = 0 must agree with the general inverse CDF just outside it.
  for (float u : {0.05f, 0.3f, 0.5f, 0.8f, 0.99f}) {
    EXPECT_NEAR(sampleHenyeyGreensteinCos(0.99e-3f, u), sampleHenyeyGreensteinCos(1.01e-3f, u),
                5e-3f);
    EXPECT_NEAR(sampleHenyeyGreensteinCos(0.0f, u), 2 * u - 1, 1e-6f);
  }
}

TEST(HenyeyGreenstein, StaysFiniteNearTheLimits) {
  for (float g : {-0.9999f, 0.9999f, 1e-7f, -1e-7f})
    for (float u : {0.0f, 1e-7f, 0.5f, 0.9999999f}) {
      float pdf = 0;
      Vec3f w = sampleHenyeyGreenstein({0, 0, 1}, g, {u, 0.3f}, &pdf);
      EXPECT_TRUE(isFinite(w) && std::isfinite(pdf) && pdf > 0) << g << " " << u;
      EXPECT_NEAR(length(w), 1, 1e-5f);
      EXPECT_NEAR(pdf, henyeyGreenstein(w.z, g), 1e-3f * pdf);
    }
}

class HenyeyGreensteinChi2 : public testing::TestWithParam<float> {};

TEST_P(HenyeyGreensteinChi2, SamplesFollowTheDensity) {
  const float g = GetParam();
  const Vec3f forward = normalize(Vec3f{0.3f, -0.5f, 0.8f});
  test::Chi2Options options;
  options.binFrame = Frame::fromZ(forward);
  options.testCount = 4;
  // A strongly peaked lobe gets its resolution from a cap around the peak.
  if (std::abs(g) > 0.8f) {
    options.binFrame = Frame::fromZ(g > 0 ? forward : -forward);
    options.capCosTheta = 0.8f;
  }
  test::Chi2Result r = test::chi2Test(
      [&](Vec2f u, float) { return std::optional(sampleHenyeyGreenstein(forward, g, u, nullptr)); },
      [&](Vec3f w) { return henyeyGreenstein(dot(forward, w), g); }, options);
  EXPECT_TRUE(r.passed) << "g = " << g << ": " << r.message;
  EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-3);
}

INSTANTIATE_TEST_SUITE_P(G, HenyeyGreensteinChi2, testing::Values(-0.9f, 0.0f, 0.5f, 0.95f));

}  // namespace
}  // namespace glint
