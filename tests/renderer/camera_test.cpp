// Tests for camera ray generation.
#include "renderer/camera.h"

#include <gtest/gtest.h>

#include <random>

#include "geometry/error.h"

namespace glint {
namespace {

TEST(Camera, PerspectiveCentreRayLooksForward) {
  Transform worldFromCamera = Transform::lookAt({1, 2, 3}, {1, 2, 0}, {0, 1, 0});
  Camera c = Camera::perspective(worldFromCamera, 0.8f, 200, 100, 0, kInfinity);
  Ray r = c.generateRay({100, 50}, 0);
  EXPECT_NEAR(r.o.x, 1, 1e-6f);
  EXPECT_NEAR(r.d.z, -1, 1e-6f);
  EXPECT_NEAR(length(r.d), 1, 1e-6f);
}

TEST(Camera, PerspectiveEdgesSpanTheFieldOfView) {
  const float yfov = 1.0f;
  Camera c = Camera::perspective(Transform(), yfov, 300, 100, 0, kInfinity);
  Ray top = c.generateRay({150, 0}, 0);
  EXPECT_NEAR(std::atan2(top.d.y, -top.d.z), yfov / 2, 1e-5f);
  Ray right = c.generateRay({300, 50}, 0);
  // The horizontal extent follows the 3:1 image aspect.
  EXPECT_NEAR(right.d.x / -right.d.z, 3 * std::tan(yfov / 2), 1e-5f);
  // Image y grows downwards.
  EXPECT_LT(c.generateRay({150, 100}, 0).d.y, 0);
}

TEST(Camera, NearAndFarClipAlongTheViewAxis) {
  Camera c = Camera::perspective(Transform(), 1.0f, 100, 100, 2, 10);
  Ray r = c.generateRay({0, 0}, 0);  // a corner ray, oblique
  EXPECT_NEAR(r.at(r.tMin).z, -2, 1e-5f);
  EXPECT_NEAR(r.at(r.tMax).z, -10, 1e-4f);
}

TEST(Camera, OrthographicRaysAreParallelAndSpanTheMagnification) {
  Transform worldFromCamera = Transform::lookAt({0, 10, 0}, {0, 0, 0}, {0, 0, -1});
  Camera c = Camera::orthographic(worldFromCamera, 1.0f, 64, 64, 0, kInfinity);
  Ray a = c.generateRay({0, 0}, 0), b = c.generateRay({64, 64}, 0);
  EXPECT_NEAR(dot(a.d, b.d), 1, 1e-6f);
  EXPECT_NEAR(a.d.y, -1, 1e-6f);
  EXPECT_NEAR(distance(a.o, b.o), 2 * std::sqrt(2.0f), 1e-5f);
  // Top of the image is camera +Y = world -Z.
  EXPECT_NEAR(a.o.z, -1, 1e-5f);
  EXPECT_NEAR(a.o.x, -1, 1e-5f);
}

// ---- thin lens -------------------------------------------------------------------------------

void expectSameRay(const Ray& a, const Ray& b) {
  EXPECT_EQ(a.o, b.o);
  EXPECT_EQ(a.d, b.d);
  EXPECT_EQ(a.tMin, b.tMin);
  EXPECT_EQ(a.tMax, b.tMax);
  EXPECT_EQ(a.time, b.time);
}

std::vector<Vec2f> someLensSamples() {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Vec2f> v = {{0, 0}, {0.5f, 0.5f}, {0.999f, 0.001f}};
  for (int i = 0; i < 200; ++i) v.push_back({u(rng), u(rng)});
  return v;
}

// The render loop's batch of pinhole rays is the one-ray path, vectorised: the same bits.
TEST(Camera, PinholeRayBatchEqualsOneRayAtATime) {
  const Transform placement = Transform::lookAt({0.3f, -2, 7}, {1, 0.5f, -1}, {0, 1, 0.2f});
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> film(-2.0f, 642.0f);
  const Camera cameras[] = {Camera::perspective(placement, 0.9f, 640, 480, 0, kInfinity),
                            Camera::perspective(placement, 0.4f, 640, 480, 0.25f, 30.0f),
                            Camera::orthographic(placement, 3.0f, 640, 480, 0.5f, 12.0f)};
  for (const Camera& camera : cameras)
    for (int n = 1; n <= Camera::kMaxRayBatch; ++n) {
      float x[Camera::kMaxRayBatch], y[Camera::kMaxRayBatch];
      for (int i = 0; i < n; ++i) x[i] = film(rng), y[i] = film(rng) * 0.75f;
      Ray batch[Camera::kMaxRayBatch];
      camera.pinholeRays(x, y, n, batch);
      for (int i = 0; i < n; ++i) {
        const Ray one = camera.pinholeRay({x[i], y[i]}, 0.0f);
        for (int k = 0; k < 3; ++k) {
          EXPECT_EQ(batch[i].o[k], one.o[k]);
          EXPECT_EQ(batch[i].d[k], one.d[k]);
        }
        EXPECT_EQ(batch[i].tMin, one.tMin);
        EXPECT_EQ(batch[i].tMax, one.tMax);
        EXPECT_EQ(batch[i].time, 0.0f);
      }
    }
}

TEST(Camera, ZeroApertureGivesThePinholeRayBitForBit) {
  Transform xf = Transform::lookAt({1, 2, 3}, {0, 0.5f, -1}, {0, 1, 0});
  for (bool ortho : {false, true}) {
    Camera pinhole = ortho ? Camera::orthographic(xf, 2, 64, 48, 0.5f, 40)
                           : Camera::perspective(xf, 0.9f, 64, 48, 0.5f, 40);
    Camera lens = pinhole;
    lens.setLens({0.0f, 3.0f, 6, 0.2f});
    EXPECT_FALSE(lens.hasLens());
    for (Vec2f pLens : someLensSamples()) {
      Vec2f pFilm{pLens.x * 64, pLens.y * 48};
      expectSameRay(lens.generateRay({pFilm, pLens, 0.25f}), pinhole.generateRay(pFilm, 0.25f));
    }
  }
}

// With znear at the focus distance, a ray's first point is where it crosses the focus plane.
TEST(Camera, LensRaysOfAFilmPointMeetOnTheFocusPlane) {
  Transform xf = Transform::lookAt({1, 2, 3}, {0, 0.5f, -1}, {0, 1, 0});
  const float f = 4, radius = 0.3f;
  for (bool ortho : {false, true}) {
    Camera pinhole = ortho ? Camera::orthographic(xf, 2, 64, 48, f, 10 * f)
                           : Camera::perspective(xf, 0.9f, 64, 48, f, 10 * f);
    for (int blades : {0, 5}) {
      Camera lens = pinhole;
      lens.setLens({radius, f, blades, 0.0f});
      ASSERT_TRUE(lens.hasLens());
      for (Vec2f pFilm : {Vec2f{32, 24}, Vec2f{0, 0}, Vec2f{63.5f, 7}}) {
        Ray p = pinhole.generateRay(pFilm, 0);
        Vec3f focus = p.at(p.tMin);
        double spreadAtLens = 0;
        for (Vec2f pLens : someLensSamples()) {
          Ray r = lens.generateRay({pFilm, pLens, 0});
          EXPECT_NEAR(length(r.d), 1, 1e-6f);
          EXPECT_LT(distance(r.at(r.tMin), focus), 2e-5f * f) << ortho << " " << blades;
          // The origin lies on the aperture, in the lens plane through the camera (or the film
          // point, orthographic).
          Vec3f local = xf.inverse().point(r.o) - xf.inverse().point(p.o);
          EXPECT_NEAR(local.z, 0, 1e-5f);
          EXPECT_LE(std::hypot(local.x, local.y), radius * (1 + 1e-5f));
          spreadAtLens = std::max(spreadAtLens, double(std::hypot(local.x, local.y)));
          // The far clip is a view depth too.
          Vec3f far = xf.inverse().point(r.at(r.tMax));
          EXPECT_NEAR(far.z, -10 * f, 1e-4f * f);
        }
        EXPECT_GT(spreadAtLens, 0.9 * radius);  // the samples do cover the aperture
      }
    }
  }
}

TEST(Camera, PolygonalApertureHasItsVertexUpAndTurnsWithRotation) {
  Camera c = Camera::perspective(Transform(), 0.8f, 32, 32, 0, kInfinity);
  const float radius = 0.5f;
  for (float rotation : {0.0f, kPi / 5}) {
    c.setLens({radius, 3.0f, 5, rotation});
    float top = -1, bottom = 1;
    for (int j = 0; j <= 64; ++j)
      for (int i = 0; i <= 64; ++i) {
        Ray r = c.generateRay({{16, 16}, {i / 64.0f, j / 64.0f}, 0});
        top = std::max(top, r.o.y), bottom = std::min(bottom, r.o.y);
      }
    if (rotation == 0) {
      // A vertex on top; an edge at the bottom, at the inradius.
      EXPECT_NEAR(top, radius, 1e-5f);
      EXPECT_NEAR(bottom, -radius * std::cos(kPi / 5), 1e-5f);
    } else {
      // Half a sector further: the pentagon stands on a vertex.
      EXPECT_NEAR(top, radius * std::cos(kPi / 5), 1e-5f);
      EXPECT_NEAR(bottom, -radius, 1e-5f);
    }
  }
}

TEST(Camera, InvalidLensIsRejected) {
  Camera c = Camera::perspective(Transform(), 0.8f, 32, 32, 0, kInfinity);
  EXPECT_THROW(c.setLens({-0.1f, 2, 0, 0}), InputError);
  EXPECT_THROW(c.setLens({0.1f, 0, 0, 0}), InputError);
  EXPECT_THROW(c.setLens({0.1f, kInfinity, 0, 0}), InputError);
  EXPECT_THROW(c.setLens({0.1f, 2, 2, 0}), InputError);
  EXPECT_THROW(c.setLens({std::nanf(""), 2, 0, 0}), InputError);
  EXPECT_FALSE(c.hasLens());
  c.setLens({0.1f, 2, 3, 0});
  EXPECT_TRUE(c.hasLens());
  c.setLens({});
  EXPECT_FALSE(c.hasLens());
}

// ---- moving camera ---------------------------------------------------------------------------

TEST(Camera, MovingCameraRayFollowsTheInterpolatedPlacement) {
  AnimatedTransform slide({Transform::translate({0, 0, 0}), Transform::translate({1, 0, 0})});
  Camera c = Camera::perspective(slide, 0.8f, 32, 32, 0.1f, 100);
  ASSERT_TRUE(c.isMoving());
  for (float time : {0.0f, 0.25f, 0.5f, 1.0f}) {
    Camera still = Camera::perspective(slide.at(time), 0.8f, 32, 32, 0.1f, 100);
    EXPECT_FALSE(still.isMoving());
    for (Vec2f pFilm : {Vec2f{16, 16}, Vec2f{0, 3}, Vec2f{31, 31}}) {
      Ray r = c.generateRay(pFilm, time);
      expectSameRay(r, still.generateRay(pFilm, time));
      EXPECT_NEAR(r.o.x, time, 1e-6f);
      EXPECT_EQ(r.time, time);
    }
  }
  // Shutter open: the first key, which is also what position() and forward() report.
  EXPECT_EQ(c.position(), (Vec3f{0, 0, 0}));
  // A turning and moving camera with a lens: still the placement at the ray's time.
  AnimatedTransform turn({Transform::lookAt({0, 0, 5}, {0, 0, 0}, {0, 1, 0}),
                          Transform::lookAt({5, 1, 0}, {0, 0, 0}, {0, 1, 0})});
  Camera t = Camera::perspective(turn, 0.8f, 32, 32, 0, kInfinity);
  t.setLens({0.2f, 5, 0, 0});
  Camera still = Camera::perspective(turn.at(0.5f), 0.8f, 32, 32, 0, kInfinity);
  still.setLens({0.2f, 5, 0, 0});
  for (Vec2f pLens : someLensSamples())
    expectSameRay(t.generateRay({{5, 9}, pLens, 0.5f}), still.generateRay({{5, 9}, pLens, 0.5f}));
  // Times outside the shutter clamp to it.
  expectSameRay(c.generateRay({1, 1}, 1.0f), [&] {
    Ray r = c.generateRay({1, 1}, 7.0f);
    r.time = 1.0f;
    return r;
  }());
}

TEST(Camera, StaticPlacementTakesATransformOrAnAnimatedTransform) {
  Transform xf = Transform::lookAt({1, 2, 3}, {0, 0, 0}, {0, 1, 0});
  Camera a = Camera::perspective(xf, 0.8f, 32, 32, 0, kInfinity);
  Camera b = Camera::perspective(AnimatedTransform({xf, xf}), 0.8f, 32, 32, 0, kInfinity);
  EXPECT_FALSE(b.isMoving());  // equal keys: no motion
  for (float time : {0.0f, 0.7f})
    expectSameRay(a.generateRay({3, 4}, time), b.generateRay({3, 4}, time));
}

}  // namespace
}  // namespace glint
