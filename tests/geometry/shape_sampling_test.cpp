// Shape sampling (Shape::area/sample/pdf, PlacedShape's world-space versions): sampled points
// lie on the surface with the surface's own uv and normal; uniform densities are 1/area; the
// densities for a receiver integrate to one, cover everything the receiver sees and nothing
// it cannot, and agree with the points they drew.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "geometry/shape.h"
#include "geometry/shapes/box.h"
#include "geometry/shapes/cone.h"
#include "geometry/shapes/cylinder.h"
#include "geometry/shapes/disk.h"
#include "geometry/shapes/plane.h"
#include "geometry/shapes/quad.h"
#include "geometry/shapes/sphere.h"

namespace glint {
namespace {

struct SampledShape {
  std::string name;
  std::unique_ptr<Shape> shape;
  float area;           // closed form
  bool closed;          // a convex solid: only its visible part is sampled from outside
  bool wrapsU = false;  // u is an angle: 0 and 1 are the same place
};

std::vector<SampledShape> shapes() {
  const float r = 0.6f, h = 1.3f, L = std::sqrt(r * r + h * h);
  std::vector<SampledShape> s;
  s.push_back(
      {"quad",
       std::make_unique<Quad>(Vec3f{-0.5f, 0.2f, 0.1f}, Vec3f{1.2f, 0, 0.3f}, Vec3f{0.1f, 0.9f, 0}),
       length(cross(Vec3f{1.2f, 0, 0.3f}, Vec3f{0.1f, 0.9f, 0})), false});
  s.push_back({"disk", std::make_unique<Disk>(r), kPi * r * r, false});
  s.push_back({"sphere", std::make_unique<Sphere>(Vec3f{0.2f, -0.1f, 0.3f}, r), 4 * kPi * r * r,
               true, true});
  s.push_back({"box", std::make_unique<Box>(Vec3f{-0.4f, -0.2f, -0.7f}, Vec3f{0.5f, 0.9f, 0.3f}),
               2 * (0.9f * 1.1f + 1.1f * 1.0f + 0.9f * 1.0f), true});
  s.push_back({"cylinder", std::make_unique<Cylinder>(r, h, true),
               2 * kPi * r * h + 2 * kPi * r * r, true, true});
  s.push_back(
      {"open cylinder", std::make_unique<Cylinder>(r, h, false), 2 * kPi * r * h, false, true});
  s.push_back({"cone", std::make_unique<Cone>(r, h, true), kPi * r * L + kPi * r * r, true, true});
  s.push_back({"open cone", std::make_unique<Cone>(r, h, false), kPi * r * L, false, true});
  return s;
}

// Placements the world-space tests run under: none, a similarity, and non-uniform scale with
// shear (which turns a sphere into an ellipsoid).
std::vector<Transform> placements() {
  return {Transform(),
          Transform::translate({3, -1, 2}) * Transform::rotate(70, {0.3f, 1, 0.2f}) *
              Transform::scale({2.5f, 2.5f, 2.5f}),
          Transform::translate({-1, 2, 0.5f}) * Transform::scale({1.0f, 0.5f, 1.7f}) *
              Transform::rotate(35, {1, 1, 0.3f}) * Transform::scale({0.8f, 1.3f, 1})};
}

// The first hit of the placed shape from `o` along `d`, with its surface details.
std::optional<ShapeSurface> trace(const PlacedShape& s, Vec3f o, Vec3f d) {
  Ray ray{o, d, 0, kInfinity, 0};
  ShapeHit hit;
  if (!s.intersect(ray, &hit)) return std::nullopt;
  return s.surface(ray, hit, {});
}

float uDistance(float a, float b, bool wraps) {
  const float d = std::abs(a - b);
  return wraps ? std::min(d, 1 - d) : d;
}

TEST(ShapeSampling, AreaMatchesClosedForms) {
  for (const SampledShape& s : shapes()) {
    SCOPED_TRACE(s.name);
    EXPECT_NEAR(s.shape->area(), s.area, 1e-5f * s.area);
  }
  // Shapes that cannot be sampled say so.
  Plane plane({0, 0, 0}, {0, 1, 0}, 1);
  EXPECT_EQ(plane.area(), 0);
  EXPECT_FALSE(plane.sample({0.5f, 0.5f}).has_value());
}

// Uniform points lie on the surface where a ray from just outside along -n meets it, with the
// uv and normal surface() reports there, and density 1 / area.
TEST(ShapeSampling, UniformPointsLieOnTheSurfaceWithItsUv) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> uni(0.0f, 0.999999f);
  for (const SampledShape& s : shapes())
    for (size_t w = 0; w < placements().size(); ++w) {
      SCOPED_TRACE(s.name);
      const Transform world = placements()[w];
      const bool similarity = w < 2;
      const PlacedShape placed(s.shape.get(), world);
      const float area = placed.area();
      const float scale = std::sqrt(area);  // a typical length
      for (int i = 0; i < 2000; ++i) {
        const Vec2f u{uni(rng), uni(rng)};
        auto p = placed.sample(u);
        ASSERT_TRUE(p.has_value());
        EXPECT_NEAR(length(p->n), 1.0f, 1e-5f);
        // A little way out along the normal, then back: the first hit is the point itself.
        const float back = 1e-2f * scale;
        auto hit = trace(placed, p->p + p->n * back, -p->n);
        ASSERT_TRUE(hit.has_value()) << "a sampled point that rays cannot find";
        EXPECT_LT(length(hit->p - p->p), 2e-4f * scale);
        EXPECT_GT(dot(hit->n, p->n), 0.999f);
        // Near the seams (the poles, the apex, box edges) uv is ill-conditioned; elsewhere it
        // must be surface()'s.
        if (p->uv.y > 0.01f && p->uv.y < 0.99f && p->uv.x > 0.01f && p->uv.x < 0.99f) {
          EXPECT_LT(uDistance(hit->uv.x, p->uv.x, s.wrapsU), 2e-3f) << p->uv.x << " " << hit->uv.x;
          EXPECT_NEAR(hit->uv.y, p->uv.y, 2e-3f);
        }
        // Uniform in object space: uniform in the world too under a similarity (J constant).
        if (similarity) {
          EXPECT_NEAR(p->pdf, 1 / area, 1e-3f / area);
        }
      }
    }
}

// Receivers around (and inside) each shape, in the shape's world space.
std::vector<Vec3f> receiversAround(const PlacedShape& s) {
  const Bounds3f b = s.bounds();
  const Vec3f c = b.center(), e = (b.upper - b.lower) * 0.5f;
  const float m = std::max({e.x, e.y, e.z});  // flat shapes have a zero extent
  return {c + m * Vec3f{3, 0.2f, 0.1f}, c + m * Vec3f{-0.3f, 2.5f, 0.4f},
          c + m * Vec3f{1.5f, -1.8f, 1.7f}, c + m * Vec3f{0.1f, 0.3f, -6},
          c + m * Vec3f{0.05f, -0.02f, 0.03f}};  // inside the solids
}

// Calls check(shape, placed, receiver) for every sampled shape, placement and receiver.
template <class Check>
void forEachReceiver(Check&& check) {
  for (const SampledShape& s : shapes())
    for (const Transform& world : placements()) {
      SCOPED_TRACE(s.name);
      const PlacedShape placed(s.shape.get(), world);
      for (Vec3f ref : receiversAround(placed)) {
        SCOPED_TRACE(ref.x);
        check(s, placed, ref);
      }
    }
}

// For a receiver, the density integrates to one over the surface (checked with uniform points:
// A E[pdf]), every drawn point has the density pdf() reports there, and for closed shapes every
// drawn point is visible from the receiver.
TEST(ShapeSampling, ReceiverDensityIsNormalisedAndMatchesItsPoints) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> uni(0.0f, 0.999999f);
  forEachReceiver([&](const SampledShape& s, const PlacedShape& placed, Vec3f ref) {
    // Stratified uniform points: sum of pdf(ref, p) / pdf_uniform(p) / N -> 1.
    constexpr int kGrid = 200;
    double integral = 0;
    for (int j = 0; j < kGrid; ++j)
      for (int i = 0; i < kGrid; ++i) {
        auto p = placed.sample({(i + uni(rng)) / kGrid, (j + uni(rng)) / kGrid});
        integral += placed.pdf(ref, p->p, p->n) / p->pdf;
      }
    EXPECT_NEAR(integral / (kGrid * kGrid), 1.0, 0.01);
    int hidden = 0;
    for (int i = 0; i < 2000; ++i) {
      auto p = placed.sample(ref, {uni(rng), uni(rng)});
      ASSERT_TRUE(p.has_value());
      ASSERT_GT(p->pdf, 0);
      EXPECT_NEAR(placed.pdf(ref, p->p, p->n), p->pdf, 1e-3f * p->pdf);
      // Hidden: the shape is met well before the point on the way from the receiver.
      auto hit = trace(placed, ref, p->p - ref);
      hidden += s.closed && (!hit || length(hit->p - p->p) > 1e-3f * length(p->p - ref));
    }
    EXPECT_LE(hidden, 10);  // silhouette rounding only
  });
}

// Unbiasedness: every point a ray from the receiver can reach first has a non-zero density,
// so next-event estimation and BSDF sampling cover the same points.
TEST(ShapeSampling, EveryVisiblePointCanBeDrawn) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> uni(0.0f, 0.999999f);
  forEachReceiver([&](const SampledShape&, const PlacedShape& placed, Vec3f ref) {
    int hits = 0, missed = 0;
    for (int i = 0; i < 4000; ++i) {
      // Directions towards the shape's bounds, jittered over them.
      const Bounds3f b = placed.bounds();
      const Vec3f target{b.lower.x + uni(rng) * (b.upper.x - b.lower.x),
                         b.lower.y + uni(rng) * (b.upper.y - b.lower.y),
                         b.lower.z + uni(rng) * (b.upper.z - b.lower.z)};
      auto hit = trace(placed, ref, target - ref);
      if (!hit) continue;
      ++hits;
      missed += !(placed.pdf(ref, hit->p, hit->n) > 0);
    }
    EXPECT_GT(hits, 100);
    EXPECT_LE(missed, hits / 500);  // edges and silhouettes only
  });
}

// The sphere seen from outside: uniform in the subtended cone, so the solid-angle density
// pdf_area d^2 / cos is the constant 1 / (2 pi (1 - cos theta_max)).
TEST(ShapeSampling, SphereFromOutsideIsUniformInItsCone) {
  const Sphere sphere({0, 5, 0}, 1);
  const Vec3f ref{0.3f, -1, 0.2f};
  const float d2 = lengthSquared(Vec3f{0, 5, 0} - ref);
  const float cosMax = std::sqrt(1 - 1 / d2);
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> uni(0.0f, 0.999999f);
  for (int i = 0; i < 1000; ++i) {
    auto p = sphere.sample(ref, {uni(rng), uni(rng)});
    ASSERT_TRUE(p.has_value());
    const Vec3f w = p->p - ref;
    const float cosLight = std::abs(dot(p->n, normalize(w)));
    EXPECT_NEAR(p->pdf * lengthSquared(w) / cosLight, 1 / (2 * kPi * (1 - cosMax)),
                2e-3f / (2 * kPi * (1 - cosMax)));
  }
}

}  // namespace
}  // namespace glint
