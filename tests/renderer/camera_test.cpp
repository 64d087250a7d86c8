// Tests for camera ray generation.
#include <gtest/gtest.h>

#include "renderer/camera.h"

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

}  // namespace
}  // namespace glint
