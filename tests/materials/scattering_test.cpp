// Smooth dielectric scattering: exact Fresnel values at the points the issue names, Snell's
// law over many angles, total internal reflection, and refraction undone by refracting back.
#include "materials/scattering.h"

#include <gtest/gtest.h>

#include <random>

namespace glint {
namespace {

TEST(Fresnel, NormalIncidenceOnGlassReflectsFourPercent) {
  const float expected = ((1 - 1.5f) / (1 + 1.5f)) * ((1 - 1.5f) / (1 + 1.5f));  // 0.04
  EXPECT_NEAR(fresnelDielectric(1, 1.5f), expected, 1e-6f);
  EXPECT_NEAR(fresnelDielectric(1, 1.5f), 0.04f, 1e-6f);
  // The same from inside the glass.
  EXPECT_NEAR(fresnelDielectric(-1, 1.5f), expected, 1e-6f);
}

TEST(Fresnel, GrazingIncidenceReflectsEverything) {
  EXPECT_NEAR(fresnelDielectric(0, 1.5f), 1.0f, 1e-6f);
  EXPECT_GT(fresnelDielectric(1e-3f, 1.5f), 0.99f);
}

TEST(Fresnel, PastTheCriticalAngleIsTotalInternalReflection) {
  // From glass (1.5) into air: the critical angle is asin(1 / 1.5) = 41.8 degrees.
  const float critical = std::asin(1 / 1.5f);
  for (float degrees = 42; degrees < 90; degrees += 1) {
    float cosTheta = std::cos(degrees * kPi / 180);
    EXPECT_EQ(fresnelDielectric(-cosTheta, 1.5f), 1.0f) << degrees;  // arriving from inside
  }
  EXPECT_LT(fresnelDielectric(-std::cos(critical - 0.01f), 1.5f), 1.0f);
}

TEST(Fresnel, NoInterfaceReflectsNothingExactly) {
  for (float c : {-1.0f, -0.3f, 0.0f, 0.5f, 1.0f}) EXPECT_EQ(fresnelDielectric(c, 1.0f), 0.0f);
}

TEST(Fresnel, StaysInTheUnitIntervalAndMatchesTheOtherSide) {
  for (float eta : {1.1f, 1.33f, 1.5f, 2.4f})
    for (int i = 0; i <= 100; ++i) {
      float c = float(i) / 100;
      float f = fresnelDielectric(c, eta);
      EXPECT_GE(f, 0.0f);
      EXPECT_LE(f, 1.0f);
      // Reciprocity: the reflectance seen from outside at theta_i equals the one seen from
      // inside at the refracted angle theta_t.
      float sinT = std::sqrt(std::max(0.0f, 1 - c * c)) / eta;
      float cT = std::sqrt(1 - sinT * sinT);
      // Float rounding near grazing (where F changes fastest) allows 1e-4.
      EXPECT_NEAR(f, fresnelDielectric(-cT, eta), 1e-4f) << "eta " << eta << " cos " << c;
    }
}

Vec3f randomUnitAbove(std::mt19937& rng, Vec3f n) {
  std::normal_distribution<float> g;
  Vec3f v;
  do v = Vec3f{g(rng), g(rng), g(rng)};
  while (lengthSquared(v) < 1e-6f);
  v = normalize(v);
  return dot(v, n) < 0 ? -v : v;
}

TEST(Snell, HoldsOverManyAnglesAndRefractingBackReturns) {
  std::mt19937 rng(3);
  const Vec3f n = normalize(Vec3f{0.2f, 1, -0.3f});
  for (float eta : {1.33f, 1.5f, 2.4f, 1 / 1.5f})
    for (int i = 0; i < 2000; ++i) {
      Vec3f wi = randomUnitAbove(rng, n);
      float etaUsed = 0;
      Vec3f wt;
      float sinI = length(cross(wi, n));
      bool ok = refract(wi, n, eta, &etaUsed, &wt);
      ASSERT_EQ(ok, sinI / eta < 1) << "TIR exactly when sin(theta_i) > 1 / eta";
      if (!ok) continue;
      EXPECT_NEAR(length(wt), 1.0f, 1e-5f);
      EXPECT_LT(dot(wt, n), 0.0f);  // crossed to the other side
      float sinT = length(cross(wt, n));
      EXPECT_NEAR(sinI, eta * sinT, 1e-5f);  // n_i sin_i = n_t sin_t with n_i = 1, n_t = eta
      // wi, n and wt lie in one plane.
      EXPECT_NEAR(dot(cross(wi, n), wt), 0.0f, 1e-5f);
      // The reversed path (light arriving from the inside along -wt) leaves along wi.
      Vec3f back;
      if (!refract(wt, n, eta, &etaUsed, &back)) {
        // Only a path at the edge of total internal reflection may fail to return: a grazing
        // wi (then wt is at the critical angle) or a grazing wt.
        EXPECT_LT(std::min(std::abs(dot(wi, n)), std::abs(dot(wt, n))), 1e-3f);
        continue;
      }
      EXPECT_NEAR(etaUsed, 1 / eta, 1e-6f);
      // Near grazing incidence the way back is ill-conditioned (d theta_i / d theta_t =
      // eta cos theta_t / cos theta_i grows without bound), so float rounding in wt is
      // amplified by 1 / cos theta_i: the tolerance follows it.
      const float tol = 1e-5f + 1e-6f / dot(wi, n);
      EXPECT_NEAR(back.x, wi.x, tol);
      EXPECT_NEAR(back.y, wi.y, tol);
      EXPECT_NEAR(back.z, wi.z, tol);
    }
}

TEST(Snell, NormalIncidencePassesStraightThrough) {
  Vec3f wt;
  ASSERT_TRUE(refract({0, 0, 1}, {0, 0, 1}, 1.5f, nullptr, &wt));
  EXPECT_NEAR(wt.z, -1.0f, 1e-6f);
  EXPECT_NEAR(wt.x, 0.0f, 1e-6f);
}

}  // namespace
}  // namespace glint
