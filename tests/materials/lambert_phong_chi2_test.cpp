// Chi-square tests of the Lambert and Phong materials' sample() against their pdf(), and of
// the chi-square harness itself: it passes a correct sampler and fails wrong ones.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "chi2.h"
#include "geometry/sampling.h"
#include "materials/basic_materials.h"

namespace glint {
namespace {

// ---------------------------------------------------------------------------------------------
// The harness
// ---------------------------------------------------------------------------------------------

Vec3f uniformSphere(Vec2f u) {
  const float z = 1 - 2 * u.x, r = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 2 * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}
constexpr float kUniformSpherePdf = 1 / (4 * kPi);

TEST(Chi2Harness, ChiSquareTailMatchesTables) {
  // Critical values of the chi-square distribution at 5% and 1% (standard tables).
  EXPECT_NEAR(test::chi2SurvivalFunction(3.841459, 1), 0.05, 1e-6);
  EXPECT_NEAR(test::chi2SurvivalFunction(6.634897, 1), 0.01, 1e-6);
  EXPECT_NEAR(test::chi2SurvivalFunction(18.307038, 10), 0.05, 1e-6);
  EXPECT_NEAR(test::chi2SurvivalFunction(124.342113, 100), 0.05, 1e-6);
  EXPECT_NEAR(test::chi2SurvivalFunction(1106.969, 1000), 0.01, 1e-5);
  // Two degrees of freedom: an exponential tail, exp(-x / 2).
  for (double x : {0.1, 1.0, 5.0, 30.0})
    EXPECT_NEAR(test::chi2SurvivalFunction(x, 2), std::exp(-x / 2), 1e-12);
  EXPECT_EQ(test::chi2SurvivalFunction(0, 5), 1);
  EXPECT_NEAR(test::regularizedGammaQ(3, 2), 5 * std::exp(-2.0), 1e-12);  // (1 + x + x^2/2) e^-x
}

TEST(Chi2Harness, UniformSphereSamplerPasses) {
  for (uint64_t seed : {1, 2, 3}) {
    test::Chi2Options options;
    options.seed = seed;
    options.testCount = 3;
    test::Chi2Result r =
        test::chi2Test([](Vec2f u, float) { return std::optional(uniformSphere(u)); },
                       [](Vec3f) { return kUniformSpherePdf; }, options);
    EXPECT_TRUE(r.passed) << r.message;
    EXPECT_NEAR(r.pdfIntegral, 1, 1e-6);
    EXPECT_EQ(r.failureFraction, 0);
  }
}

TEST(Chi2Harness, SamplerThatFailsAsThePdfSaysPasses) {
  // Uniform over the sphere, but directions below the horizon are absorbed.
  test::Chi2Result r = test::chi2Test(
      [](Vec2f u, float) -> std::optional<Vec3f> {
        Vec3f w = uniformSphere(u);
        if (w.z <= 0) return std::nullopt;
        return w;
      },
      [](Vec3f w) { return w.z > 0 ? kUniformSpherePdf : 0.0f; });
  EXPECT_TRUE(r.passed) << r.message;
  EXPECT_NEAR(r.pdfIntegral, 0.5, 1e-6);
  EXPECT_NEAR(r.failureFraction, 0.5, 3e-3);
}

TEST(Chi2Harness, WrongPdfFails) {
  // Samples the cosine-weighted hemisphere but claims the uniform hemisphere.
  test::Chi2Result r =
      test::chi2Test([](Vec2f u, float) { return std::optional(sampleCosineHemisphere(u)); },
                     [](Vec3f w) { return w.z > 0 ? 1 / (2 * kPi) : 0.0f; });
  EXPECT_FALSE(r.passed);
  EXPECT_LT(r.pValue, 1e-10);
}

TEST(Chi2Harness, SlightlyWrongPdfFails) {
  // A Phong-like cos^n lobe sampled with exponent 20 but described with exponent 21.
  auto lobe = [](Vec2f u, float) {
    const float c = std::pow(u.x, 1 / 21.0f), s = std::sqrt(std::max(0.0f, 1 - c * c));
    return std::optional(Vec3f{s * std::cos(2 * kPi * u.y), s * std::sin(2 * kPi * u.y), c});
  };
  test::Chi2Result right = test::chi2Test(
      lobe, [](Vec3f w) { return w.z > 0 ? 21 / (2 * kPi) * std::pow(w.z, 20.0f) : 0.0f; });
  EXPECT_TRUE(right.passed) << right.message;
  test::Chi2Result wrong = test::chi2Test(
      lobe, [](Vec3f w) { return w.z > 0 ? 22 / (2 * kPi) * std::pow(w.z, 21.0f) : 0.0f; });
  EXPECT_FALSE(wrong.passed);
}

TEST(Chi2Harness, UnnormalizedPdfAndUnclaimedFailuresFail) {
  auto sphere = [](Vec2f u, float) { return std::optional(uniformSphere(u)); };
  // The right shape, 2% too much mass.
  test::Chi2Result tooMuch =
      test::chi2Test(sphere, [](Vec3f) { return 1.02f * kUniformSpherePdf; });
  EXPECT_FALSE(tooMuch.passed);
  // The right shape, but the sampler drops 2% of its samples without the pdf saying so.
  test::Chi2Result drops = test::chi2Test(
      [](Vec2f u, float uLobe) -> std::optional<Vec3f> {
        if (uLobe < 0.02f) return std::nullopt;
        return uniformSphere(u);
      },
      [](Vec3f) { return kUniformSpherePdf; });
  EXPECT_FALSE(drops.passed);
  EXPECT_LT(drops.failurePValue, 1e-6);
}

TEST(Chi2Harness, SamplesWherePdfIsZeroFail) {
  // Uniform sphere, but the pdf claims only the upper hemisphere (and twice the density).
  test::Chi2Result r =
      test::chi2Test([](Vec2f u, float) { return std::optional(uniformSphere(u)); },
                     [](Vec3f w) { return w.z > 0 ? 2 * kUniformSpherePdf : 0.0f; });
  EXPECT_FALSE(r.passed);
  EXPECT_NE(r.message.find("pdf is zero"), std::string::npos) << r.message;
}

// ---------------------------------------------------------------------------------------------
// Materials
// ---------------------------------------------------------------------------------------------

SurfaceInteraction makeInteraction(Vec3f n, Vec3f woLocal) {
  SurfaceInteraction si;
  si.ng = si.ns = n;
  si.wo = normalize(Frame::fromZ(n).fromLocal(woLocal));
  return si;
}

Vec3f polar(double theta, double phi) {
  return {float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
          float(std::cos(theta))};
}

const std::vector<Vec3f> kNormals = {{0, 0, 1}, normalize(Vec3f{0.3f, -0.5f, 0.8f})};
// Views at normal incidence, 45 degrees and 75 degrees, in the normal's frame.
const std::vector<Vec3f> kViewsLocal = {polar(0, 0), polar(kPi / 4, 0.5), polar(1.31, 2.5)};

// Runs the chi-square test on a material's sample() against its pdf(), and checks that the
// pdf each sample reports is the one pdf() gives.
test::Chi2Result testMaterial(const Material& m, const SurfaceInteraction& si,
                              test::Chi2Options options) {
  options.binFrame = Frame::fromZ(si.ns);  // the horizon on a bin edge
  int mismatches = 0;
  test::Chi2Result r = test::chi2Test(
      [&](Vec2f u, float uLobe) -> std::optional<Vec3f> {
        std::optional<BsdfSample> s = m.bsdf(si).sample(u, uLobe);
        if (!s) return std::nullopt;
        const float p = m.bsdf(si).pdf(s->wi);
        if (!(std::abs(s->pdf - p) <= 1e-3f * p)) ++mismatches;
        return s->wi;
      },
      [&](Vec3f wi) { return m.bsdf(si).pdf(wi); }, options);
  EXPECT_EQ(mismatches, 0) << "samples whose reported pdf differs from pdf()";
  return r;
}

TEST(LambertChi2, SampleFollowsPdf) {
  constexpr int kSeeds = 3;
  const int testCount = int(kNormals.size() * kViewsLocal.size()) * kSeeds;
  LambertMaterial lambert(ColorParam{{0.5f, 0.5f, 0.5f}}, ColorParam{{0, 0, 0}});
  for (Vec3f n : kNormals)
    for (Vec3f wo : kViewsLocal)
      for (int seed = 1; seed <= kSeeds; ++seed) {
        test::Chi2Options options;
        options.seed = 100 * seed + uint64_t(10 * wo.z) + uint64_t(5 * n.x);
        options.testCount = testCount;
        options.sampleCount = 300'000;
        const SurfaceInteraction si = makeInteraction(n, wo);
        test::Chi2Result r = testMaterial(lambert, si, options);
        EXPECT_TRUE(r.passed) << "n.z " << n.z << " wo.z " << wo.z << " seed " << seed << ": "
                              << r.message;
        EXPECT_NEAR(r.pdfIntegral, 1, 1e-4);
      }
}

struct PhongCase {
  float kd, ks, shininess;
};

// Chi-square tests of Phong (or Blinn-Phong) for every case on both normals and all three
// views with `seeds` seeds, Šidák-corrected to 1% over all of them.
void testPhongCases(const std::vector<PhongCase>& cases, bool blinn, int seeds) {
  const int testCount = int(cases.size() * kNormals.size() * kViewsLocal.size()) * seeds;
  for (const PhongCase& c : cases) {
    PhongMaterial phong(ColorParam{{c.kd, c.kd, c.kd}}, Rgb{c.ks, c.ks, c.ks}, c.shininess,
                        ColorParam{{0, 0, 0}}, blinn);
    for (Vec3f n : kNormals)
      for (Vec3f wo : kViewsLocal)
        for (int seed = 1; seed <= seeds; ++seed) {
          test::Chi2Options options;
          options.seed = 7919 * seed + uint64_t(100 * wo.z) + uint64_t(c.shininess) +
                         uint64_t(10 * c.kd) + (blinn ? 31 : 0);
          options.testCount = testCount;
          options.sampleCount = 120'000;
          if (c.shininess >= 100) {
            // A narrow lobe: finer bins, and a cap around the normal when it holds the lobe.
            options.thetaBins = 48;
            options.phiBins = 96;
            if (wo.z > 0.95f) options.capCosTheta = std::cos(0.6f);
          }
          const SurfaceInteraction si = makeInteraction(n, wo);
          test::Chi2Result r = testMaterial(phong, si, options);
          EXPECT_TRUE(r.passed) << (blinn ? "Blinn-Phong" : "Phong") << " kd " << c.kd << " ks "
                                << c.ks << " n " << c.shininess << " normal.z " << n.z << " wo.z "
                                << wo.z << " seed " << seed << ": " << r.message;
        }
  }
}

// Shininess 1, 10 and 100 with a diffuse-heavy, a balanced and a purely specular split, each
// on two normals and three views with two seeds: 3 x 3 x 2 x 3 x 2 = 108 tests at 1% overall.
TEST(PhongChi2, SampleFollowsPdf) {
  std::vector<PhongCase> cases;
  for (float shininess : {1.0f, 10.0f, 100.0f})
    for (auto [kd, ks] : {std::pair{0.7f, 0.2f}, std::pair{0.4f, 0.5f}, std::pair{0.0f, 0.9f}})
      cases.push_back({kd, ks, shininess});
  testPhongCases(cases, /*blinn=*/false, 2);
}

// The same material's Blinn-Phong lobe (half vectors around the normal), on fewer splits:
// 3 x 1 x 2 x 3 x 2 = 36 tests at 1% overall.
TEST(BlinnPhongChi2, SampleFollowsPdf) {
  testPhongCases({{0.3f, 0.6f, 1}, {0.3f, 0.6f, 10}, {0.3f, 0.6f, 100}}, /*blinn=*/true, 2);
}

}  // namespace
}  // namespace glint
