// The Trowbridge–Reitz distribution: D is normalized over the projected area, the visible
// normal distribution is a pdf and Sample_wm draws from it (chi-square), Smith's masking is a
// fraction that passes the weak white furnace test, and nothing turns into NaN at grazing
// angles or for a near-mirror alpha.
#include "materials/microfacet.h"

#include <gtest/gtest.h>

#include <functional>
#include <random>
#include <string>
#include <vector>

#include "chi2.h"

namespace glint {
namespace {

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

// A unit direction from polar angle theta (from +Z) and azimuth phi.
Vec3f direction(double theta, double phi) {
  return {float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
          float(std::cos(theta))};
}

// The integral of f over the upper hemisphere (solid angle): adaptive Simpson in theta over
// a periodic trapezoid rule in phi (spectrally accurate for smooth integrands; a kink costs
// O(h^2) with 1024 points).
double integrateHemisphere(const std::function<double(Vec3f)>& f) {
  constexpr int kPhiPoints = 1024;
  auto ring = [&](double theta) {
    double sum = 0;
    for (int j = 0; j < kPhiPoints; ++j)
      sum += f(direction(theta, 2 * kPi * (j + 0.5) / kPhiPoints));
    return sum * (2 * kPi / kPhiPoints) * std::sin(theta);
  };
  std::function<double(double, double, double, double, double, double, int)> simpson =
      [&](double a, double b, double fa, double fm, double fb, double whole, int depth) {
        const double m = (a + b) / 2, lm = (a + m) / 2, rm = (m + b) / 2;
        const double flm = ring(lm), frm = ring(rm);
        const double left = (m - a) / 6 * (fa + 4 * flm + fm);
        const double right = (b - m) / 6 * (fm + 4 * frm + fb);
        if (depth == 0 || std::abs(left + right - whole) < 1e-9)
          return left + right + (left + right - whole) / 15;
        return simpson(a, m, fa, flm, fm, left, depth - 1) +
               simpson(m, b, fm, frm, fb, right, depth - 1);
      };
  // Fixed pieces first, so that a narrow peak at the pole cannot hide from the first estimate.
  constexpr int kPieces = 32;
  double total = 0;
  for (int i = 0; i < kPieces; ++i) {
    const double a = (kPi / 2) * i / kPieces, b = (kPi / 2) * (i + 1) / kPieces;
    const double fa = ring(a), fm = ring((a + b) / 2), fb = ring(b);
    total += simpson(a, b, fa, fm, fb, (b - a) / 6 * (fa + 4 * fm + fb), 12);
  }
  return total;
}

struct Alphas {
  float x, y;
};
std::string describe(Alphas a) {
  return "alpha (" + std::to_string(a.x) + ", " + std::to_string(a.y) + ")";
}

const std::vector<Alphas> kAlphas = {
    {0.05f, 0.05f}, {0.2f, 0.2f}, {0.5f, 0.5f}, {1.0f, 1.0f}, {0.1f, 0.4f}};

// Directions seen from: normal, oblique, steep, grazing, and from below the surface.
const std::vector<Vec3f> kViews = {direction(0, 0), direction(0.7, 0.3), direction(1.3, 2.0),
                                   direction(1.55, -1.0), direction(kPi - 0.9, 4.0)};

Vec3f randomDirection(std::mt19937& rng) {
  std::normal_distribution<float> g;
  Vec3f v;
  do v = Vec3f{g(rng), g(rng), g(rng)};
  while (lengthSquared(v) < 1e-6f);
  return normalize(v);
}

// ---------------------------------------------------------------------------------------------
// Parameters and known values
// ---------------------------------------------------------------------------------------------

TEST(TrowbridgeReitz, RoughnessMapsToAlphaSquaredAboveAFloor) {
  EXPECT_FLOAT_EQ(TrowbridgeReitzDistribution::roughnessToAlpha(0.5f), 0.25f);
  EXPECT_FLOAT_EQ(TrowbridgeReitzDistribution::roughnessToAlpha(1), 1);
  EXPECT_FLOAT_EQ(TrowbridgeReitzDistribution::roughnessToAlpha(0), 1e-4f);
  EXPECT_TRUE(TrowbridgeReitzDistribution(TrowbridgeReitzDistribution::roughnessToAlpha(0))
                  .effectivelySmooth());
  EXPECT_TRUE(TrowbridgeReitzDistribution(9e-4f).effectivelySmooth());
  EXPECT_FALSE(TrowbridgeReitzDistribution(0.05f).effectivelySmooth());
  EXPECT_FALSE(TrowbridgeReitzDistribution(1e-4f, 0.3f).effectivelySmooth());
}

TEST(TrowbridgeReitz, MatchesTheClosedFormsOfDAndLambda) {
  for (float alpha : {0.05f, 0.3f, 1.0f}) {
    TrowbridgeReitzDistribution d(alpha);
    EXPECT_NEAR(d.D({0, 0, 1}), 1 / (kPi * alpha * alpha), 1e-5 / (alpha * alpha));
    EXPECT_EQ(d.Lambda({0, 0, 1}), 0);
    EXPECT_EQ(d.G1({0, 0, 1}), 1);
    for (double theta = 0.05; theta < kPi / 2; theta += 0.1) {
      const Vec3f w = direction(theta, 0.4);
      const double tan2 = std::tan(theta) * std::tan(theta),
                   cos2 = std::cos(theta) * std::cos(theta);
      const double a2 = double(alpha) * alpha;
      const double d0 = 1 / (kPi * a2 * cos2 * cos2 * (1 + tan2 / a2) * (1 + tan2 / a2));
      EXPECT_NEAR(d.D(w), d0, 1e-4 * d0) << alpha << " " << theta;
      const double lambda = (std::sqrt(1 + a2 * tan2) - 1) / 2;
      EXPECT_NEAR(d.Lambda(w), lambda, 1e-4 * lambda + 1e-7) << alpha << " " << theta;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Normalization
// ---------------------------------------------------------------------------------------------

TEST(TrowbridgeReitz, DIntegratesToOneOverTheProjectedArea) {
  for (Alphas a : kAlphas) {
    TrowbridgeReitzDistribution d(a.x, a.y);
    double integral = integrateHemisphere([&](Vec3f wm) { return d.D(wm) * wm.z; });
    EXPECT_NEAR(integral, 1, 1e-4) << describe(a);
  }
}

TEST(TrowbridgeReitz, VisibleNormalsIntegrateToOne) {
  for (Alphas a : kAlphas) {
    TrowbridgeReitzDistribution d(a.x, a.y);
    for (Vec3f w : kViews) {
      double integral = integrateHemisphere([&](Vec3f wm) { return d.D(w, wm); });
      EXPECT_NEAR(integral, 1, 1e-3) << describe(a) << " w.z " << w.z;
      // PDF is the visible normal density.
      EXPECT_EQ(d.PDF(w, direction(0.3, 0.2)), d.D(w, direction(0.3, 0.2)));
    }
  }
}

// Heitz 2014: the projected area of the visible microfacets equals that of the macro-surface.
TEST(TrowbridgeReitz, PassesTheWeakWhiteFurnaceTest) {
  for (Alphas a : kAlphas) {
    TrowbridgeReitzDistribution d(a.x, a.y);
    for (double thetaO : {0.0, 0.5, 1.0, 1.4, 1.5, 1.56}) {
      const Vec3f wo = direction(thetaO, 0.7);
      const double g1 = d.G1(wo);
      double integral = integrateHemisphere(
          [&](Vec3f wm) { return g1 * d.D(wm) * std::max(0.0f, dot(wo, wm)) / wo.z; });
      EXPECT_NEAR(integral, 1, 1e-3) << describe(a) << " theta_o " << thetaO;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Masking and shadowing
// ---------------------------------------------------------------------------------------------

TEST(TrowbridgeReitz, MaskingIsAFractionAndHeightCorrelationBoundsIt) {
  std::mt19937 rng(7);
  for (Alphas a : kAlphas) {
    TrowbridgeReitzDistribution d(a.x, a.y);
    for (int i = 0; i < 2000; ++i) {
      const Vec3f wo = randomDirection(rng), wi = randomDirection(rng);
      const float g1o = d.G1(wo), g1i = d.G1(wi), g = d.G(wo, wi);
      ASSERT_GE(g1o, 0);
      ASSERT_LE(g1o, 1);
      ASSERT_GE(g, 0);
      ASSERT_LE(g, std::min(g1o, g1i) * (1 + 1e-6f));
      // Correlated heights hide less than independent masking and shadowing would.
      ASSERT_GE(g, g1o * g1i * (1 - 1e-6f));
      // Masking depends on the line of sight, not on the side it comes from.
      ASSERT_FLOAT_EQ(d.G1(-wo), g1o);
    }
  }
}

TEST(TrowbridgeReitz, MaskingFallsFromOneAtTheNormalToZeroOnTheHorizon) {
  TrowbridgeReitzDistribution d(0.3f);
  float previous = 1;
  for (double theta = 0; theta <= kPi / 2; theta += 0.01) {
    const float g1 = d.G1(direction(theta, 1.0));
    EXPECT_LE(g1, previous + 1e-6f) << theta;
    previous = g1;
  }
  EXPECT_EQ(d.G1({1, 0, 0}), 0);
  EXPECT_EQ(d.G({1, 0, 0}, {0, 0, 1}), 0);
}

// ---------------------------------------------------------------------------------------------
// Sampling the visible normals
// ---------------------------------------------------------------------------------------------

// Every alpha against every view, with two seeds: 5 x 5 x 2 = 50 tests at 1% overall.
TEST(TrowbridgeReitz, SampledVisibleNormalsFollowThePdf) {
  constexpr int kSeeds = 2;
  const int testCount = int(kAlphas.size() * kViews.size()) * kSeeds;
  for (Alphas a : kAlphas) {
    TrowbridgeReitzDistribution d(a.x, a.y);
    for (Vec3f w : kViews)
      for (int seed = 1; seed <= kSeeds; ++seed) {
        test::Chi2Options options;
        options.seed = 1000 * seed + uint64_t(1000 * w.z) + uint64_t(100 * a.x);
        options.testCount = testCount;
        options.sampleCount = 300'000;
        // Zoom in on the narrow lobe of a smooth surface.
        const float lobe = 6 * std::max(a.x, a.y);
        if (lobe < 1.2f) options.capCosTheta = std::cos(lobe);
        test::Chi2Result r = test::chi2Test(
            [&](Vec2f u, float) -> std::optional<Vec3f> { return d.Sample_wm(w, u); },
            [&](Vec3f wm) { return d.PDF(w, wm); }, options);
        EXPECT_TRUE(r.passed) << describe(a) << " w " << w.x << " " << w.y << " " << w.z << " seed "
                              << seed << ": " << r.message;
        EXPECT_NEAR(r.pdfIntegral, 1, 1e-3);
      }
  }
}

// The test above has the power to notice a small error: 10% too much roughness, or the
// roughnesses of an anisotropic surface swapped.
TEST(TrowbridgeReitz, ChiSquareNoticesAWrongAlpha) {
  const Vec3f w = direction(0.9, 0.5);
  auto run = [&](TrowbridgeReitzDistribution sampled, TrowbridgeReitzDistribution claimed) {
    test::Chi2Options options;
    options.sampleCount = 300'000;
    return test::chi2Test(
        [&](Vec2f u, float) -> std::optional<Vec3f> { return sampled.Sample_wm(w, u); },
        [&](Vec3f wm) { return claimed.PDF(w, wm); }, options);
  };
  EXPECT_FALSE(run(TrowbridgeReitzDistribution(0.3f), TrowbridgeReitzDistribution(0.33f)).passed);
  EXPECT_FALSE(
      run(TrowbridgeReitzDistribution(0.2f, 0.3f), TrowbridgeReitzDistribution(0.3f, 0.2f)).passed);
}

TEST(TrowbridgeReitz, SampledNormalsAreUnitAboveTheHorizonAndFaceTheViewer) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> uniform(0, 1);
  for (Alphas a : kAlphas) {
    TrowbridgeReitzDistribution d(a.x, a.y);
    for (Vec3f w : kViews)
      for (int i = 0; i < 5000; ++i) {
        const Vec3f wm = d.Sample_wm(w, {uniform(rng), uniform(rng)});
        ASSERT_NEAR(length(wm), 1, 1e-5f);
        ASSERT_GT(wm.z, 0);
        ASSERT_GE(w.z > 0 ? dot(w, wm) : -dot(w, wm), -1e-5f);
      }
  }
}

// ---------------------------------------------------------------------------------------------
// Numerical robustness
// ---------------------------------------------------------------------------------------------

TEST(TrowbridgeReitz, StaysFiniteAtGrazingAnglesAndForANearMirror) {
  const std::vector<Vec2f> corners = {
      {0, 0},       {0, 0.999999f}, {0.999999f, 0}, {0.999999f, 0.999999f},
      {0.5f, 0.5f}, {0.5f, 0},      {0, 0.5f},      {0.25f, 0.75f}};
  const float grazing = std::sqrt(1 - 1e-12f);  // sin for cos = 1e-6
  const std::vector<Vec3f> views = {{grazing, 0, 1e-6f},
                                    {0, grazing, 1e-6f},
                                    {grazing * 0.6f, grazing * 0.8f, 1e-6f},
                                    {grazing, 0, -1e-6f},
                                    {1, 0, 0},
                                    {0, 0, 1},
                                    {0, 0, -1}};
  for (Alphas a : {Alphas{1e-4f, 1e-4f}, Alphas{1e-4f, 0.5f}, Alphas{0.05f, 0.05f}, Alphas{1, 1}}) {
    TrowbridgeReitzDistribution d(a.x, a.y);
    for (Vec3f w : views) {
      const std::string where = describe(a) + " w (" + std::to_string(w.x) + ", " +
                                std::to_string(w.y) + ", " + std::to_string(w.z) + ")";
      EXPECT_TRUE(std::isfinite(d.G1(w)) && d.G1(w) >= 0 && d.G1(w) <= 1) << where;
      EXPECT_FALSE(std::isnan(d.Lambda(w))) << where;
      EXPECT_TRUE(std::isfinite(d.G(w, w))) << where;
      EXPECT_TRUE(std::isfinite(d.G(w, {0, 0, 1}))) << where;
      for (Vec2f u : corners) {
        const Vec3f wm = d.Sample_wm(w, u);
        EXPECT_TRUE(isFinite(wm)) << where;
        EXPECT_NEAR(length(wm), 1, 1e-5f) << where;
        EXPECT_GT(wm.z, 0) << where;
        const float pdf = d.PDF(w, wm);
        EXPECT_TRUE(std::isfinite(pdf) && pdf >= 0) << where << " pdf " << pdf;
        EXPECT_TRUE(std::isfinite(d.D(wm))) << where;
      }
      // Normals on and near the horizon.
      for (Vec3f wm : {Vec3f{1, 0, 0}, Vec3f{0.6f, 0.8f, 0}, Vec3f{grazing, 0, 1e-6f}}) {
        EXPECT_TRUE(std::isfinite(d.D(wm)) && d.D(wm) >= 0) << where;
        const float pdf = d.D(w, wm);
        EXPECT_TRUE(std::isfinite(pdf) && pdf >= 0) << where;
      }
    }
  }
  // On the horizon a view sees nothing: the visible normal density is zero, not NaN.
  TrowbridgeReitzDistribution d(0.3f);
  EXPECT_EQ(d.D({1, 0, 0}, {0, 0, 1}), 0);
  EXPECT_EQ(d.D({0, 0, 1}, {0, 0, -1}), 0);
}

}  // namespace
}  // namespace glint
