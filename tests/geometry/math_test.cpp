// Tests for geometry/math.h: transforms, inverses, normals, error bounds.
#include "geometry/math.h"

#include <gtest/gtest.h>

#include <random>

namespace glint {
namespace {

void expectNear(Vec3f a, Vec3f b, float tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(MeantTransform, NumbersShorterThanSevenDigitsMeanWhatTheySay) {
  for (float v : {0.5f, 10.0f, 3.0f, 0.1f, 37.25f, -1.5f, 123456.0f, 0.0f})
    EXPECT_EQ(writtenPrecision(v), 0) << v;
  for (float v : {0.3333333f, 1.428571f, 0.6666667f, -2.718282f})
    EXPECT_EQ(writtenPrecision(v), kWrittenPrecision * std::abs(v)) << v;
}

TEST(MeantTransform, ARotationUndoneIsExactAsMeant) {
  // rotate 37 about a skew axis, then -37: the float matrix is off the identity by the
  // rounding of sines, cosines and products, which errorOf measures (not bounds).
  const Vec3f axis{0.3f, -0.8f, 0.52f};
  const Transform t = Transform::rotate(-37, axis) * Transform::rotate(37, axis);
  const MeantTransform m = MeantTransform::rotation(-37, axis) * MeantTransform::rotation(37, axis);
  const TransformError e = m.errorOf(t.matrix());
  float worst = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) {
      const float exact = i == j ? 1.0f : 0.0f;
      EXPECT_GE(e.e[i][j], std::abs(t.matrix().m[i][j] - exact)) << i << j;
      worst = std::max(worst, e.e[i][j]);
    }
  EXPECT_LT(worst, 8 * kMachineEpsilon);  // a few ulps: nothing from the written angle
}

TEST(MeantTransform, AThirdWrittenOutCoversItsDistanceFromAThird) {
  // scale 3 then 0.3333333: the written 0.3333333 may mean 1/3, so the product may mean 1.
  const Transform t = Transform::scale({0.3333333f, 1, 1}) * Transform::scale({3, 1, 1});
  const MeantTransform m = MeantTransform::written(Transform::scale({0.3333333f, 1, 1}).matrix()) *
                           MeantTransform::written(Transform::scale({3, 1, 1}).matrix());
  const TransformError e = m.errorOf(t.matrix());
  EXPECT_GE(e.e[0][0], std::abs(t.matrix().m[0][0] - 1.0f));
  EXPECT_GT(std::abs(t.matrix().m[0][0] - 1.0f), 0);  // the float product is not 1
  EXPECT_LT(e.e[0][0], 1e-6f);
  EXPECT_LT(e.e[1][1], 1e-11f);  // 1 * 1 is exact (up to the double products' allowance)
  // A translation and its negative, both short numbers: exact.
  const Transform tt = Transform::translate({-0.25f, 0, 0}) * Transform::translate({0.25f, 0, 0});
  const MeantTransform mt = MeantTransform::written(Transform::translate({-0.25f, 0, 0}).matrix()) *
                            MeantTransform::written(Transform::translate({0.25f, 0, 0}).matrix());
  EXPECT_LT(mt.errorOf(tt.matrix()).e[0][3], 1e-11f);
}

TEST(Transform, ComposesDestinationFromSource) {
  Transform worldFromObject = Transform::translate({1, 2, 3}) * Transform::scale({2, 2, 2});
  expectNear(worldFromObject.point({1, 0, 0}), {3, 2, 3}, 1e-6f);
  expectNear(worldFromObject.vector({1, 0, 0}), {2, 0, 0}, 1e-6f);
  expectNear(worldFromObject.inverse().point({3, 2, 3}), {1, 0, 0}, 1e-6f);
}

TEST(Transform, InverseOfRandomAffineMatricesRoundTrips) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-2, 2);
  for (int i = 0; i < 100; ++i) {
    Mat4 m;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) m.m[r][c] = u(rng);
    Mat4 inv;
    if (!invert(m, &inv)) continue;
    Transform t(m);
    Vec3f p{u(rng), u(rng), u(rng)};
    Vec3f back = t.inverse().point(t.point(p));
    // Tolerance scales with the conditioning; random matrices are usually tame.
    expectNear(back, p, 1e-3f);
  }
}

TEST(Transform, SingularMatrixIsReported) {
  Mat4 m;
  m.m[1][1] = 0;
  Mat4 inv;
  EXPECT_FALSE(invert(m, &inv));
  m.m[1][1] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(invert(m, &inv));
}

TEST(Transform, NormalsStayPerpendicularUnderShearAndNonUniformScale) {
  Mat4 shear;
  shear.m[0][1] = 0.7f;  // x += 0.7 y
  Transform t = Transform(shear) * Transform::scale({3, 0.5f, 2});
  Vec3f a{1, 0, 0}, b{0, 0, 1};  // tangents of the plane y = 0
  Vec3f n = cross(a, b);
  Vec3f tn = t.normal(n);
  EXPECT_NEAR(dot(tn, t.vector(a)), 0, 1e-5f);
  EXPECT_NEAR(dot(tn, t.vector(b)), 0, 1e-5f);
}

TEST(Transform, QuaternionRotationMatchesAxisAngle) {
  // 90 degrees about +Y maps +X to -Z.
  Transform r = Transform::rotate(90, {0, 1, 0});
  expectNear(r.vector({1, 0, 0}), {0, 0, -1}, 1e-6f);
  Transform q = Transform::rotateQuaternion({0, std::sqrt(0.5f), 0, std::sqrt(0.5f)});
  expectNear(q.vector({1, 0, 0}), {0, 0, -1}, 1e-6f);
  EXPECT_FALSE(q.swapsHandedness());
  EXPECT_TRUE(Transform::scale({-1, 1, 1}).swapsHandedness());
}

TEST(Transform, LookAtLooksDownMinusZ) {
  Transform c = Transform::lookAt({0, 0, 5}, {0, 0, 0}, {0, 1, 0});
  expectNear(c.point({0, 0, 0}), {0, 0, 5}, 1e-6f);
  expectNear(c.vector({0, 0, -1}), {0, 0, -1}, 1e-6f);
  expectNear(c.vector({0, 1, 0}), {0, 1, 0}, 1e-6f);
  // Up parallel to the view direction still gives an orthonormal frame.
  Transform d = Transform::lookAt({0, 10, 0}, {0, 0, 0}, {0, 1, 0});
  expectNear(d.vector({0, 0, -1}), {0, -1, 0}, 1e-6f);
  EXPECT_NEAR(dot(d.vector({1, 0, 0}), d.vector({0, 1, 0})), 0, 1e-6f);
}

TEST(Transform, PointErrorBoundCoversDoublePrecisionResult) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1000, 1000);
  for (int i = 0; i < 1000; ++i) {
    Transform t = Transform::translate({u(rng), u(rng), u(rng)}) *
                  Transform::rotate(u(rng), {u(rng), u(rng), u(rng) + 2000}) *
                  Transform::scale({1.5f, 0.25f, 3});
    Vec3f p{u(rng), u(rng), u(rng)};
    Vec3f err;
    Vec3f q = t.point(p, &err);
    const auto& m = t.matrix().m;
    for (int r = 0; r < 3; ++r) {
      double exact =
          double(m[r][0]) * p.x + double(m[r][1]) * p.y + double(m[r][2]) * p.z + double(m[r][3]);
      EXPECT_LE(std::abs(exact - double(q[r])), double(err[r])) << "row " << r;
    }
  }
}

// Far from the origin the bound is the result's own rounding to float, not three roundings of
// the terms: a hit on an object placed at 1e6 keeps its offset to one float step there (0.0625)
// where pbrt-v4's gamma(3) sum gave 0.18 whatever the point. Covered exactly, as above.
TEST(Transform, PointErrorFarFromTheOriginIsOneFloatStep) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1, 1);
  for (float offset : {1e3f, 1e6f}) {
    for (int i = 0; i < 1000; ++i) {
      Transform t = Transform::translate(Vec3f{u(rng), u(rng), u(rng)} * 0.2f * offset) *
                    Transform::translate({offset, offset, -offset}) *
                    Transform::rotate(180 * u(rng), {u(rng), u(rng), u(rng) + 2});
      const Vec3f p = Vec3f{u(rng), u(rng), u(rng)} * 3.0f;
      Vec3f err;
      const Vec3f q = t.point(p, &err);
      const auto& m = t.matrix().m;
      for (int r = 0; r < 3; ++r) {
        const double exact =
            double(m[r][0]) * p.x + double(m[r][1]) * p.y + double(m[r][2]) * p.z + double(m[r][3]);
        EXPECT_LE(std::abs(exact - double(q[r])), double(err[r]));
        const float a = std::abs(q[r]), step = std::nextafter(a, 2 * a) - a;  // at the result
        EXPECT_LE(err[r], step) << "offset " << offset << " row " << r;
      }
    }
  }
}

TEST(Frame, IsOrthonormalForAnyNormal) {
  std::mt19937 rng(11);
  std::normal_distribution<float> g;
  for (int i = 0; i < 1000; ++i) {
    Vec3f n = normalize(Vec3f{g(rng), g(rng), g(rng)});
    if (i == 0) n = {0, 0, -1};
    if (i == 1) n = {0, 0, 1};
    Frame f = Frame::fromZ(n);
    EXPECT_NEAR(length(f.s), 1, 1e-5f);
    EXPECT_NEAR(length(f.t), 1, 1e-5f);
    EXPECT_NEAR(dot(f.s, f.t), 0, 1e-5f);
    EXPECT_NEAR(dot(f.s, n), 0, 1e-5f);
    EXPECT_NEAR(dot(f.t, n), 0, 1e-5f);
  }
}

TEST(FloatRounding, NextFloatStepsOneUlp) {
  EXPECT_GT(nextFloatUp(1.0f), 1.0f);
  EXPECT_EQ(nextFloatDown(nextFloatUp(1.0f)), 1.0f);
  EXPECT_GT(nextFloatUp(-0.0f), 0.0f);
  EXPECT_LT(nextFloatDown(0.0f), 0.0f);
  EXPECT_EQ(nextFloatUp(kInfinity), kInfinity);
}

}  // namespace
}  // namespace glint
