// Per-vertex tangents derived from uvs (vertexTangents) for glTF files without TANGENT: the
// handedness of as-drawn and mirrored layouts, smoothness over a smooth mesh, and the frame's
// orthogonality.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "geometry/mesh.h"

namespace glint {
namespace {

// A unit quad in the XY plane facing +Z, uv as glTF draws an image on it: u to the right,
// v down (the image's top row at +y). `mirrored` flips u (the image seen in a mirror).
struct Quad {
  std::vector<Vec3f> positions{{-1, 1, 0}, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}};
  std::vector<Vec3f> normals{4, Vec3f{0, 0, 1}};
  std::vector<Vec2f> uvs;
  std::vector<uint32_t> indices{0, 1, 2, 0, 2, 3};
  explicit Quad(bool mirrored) {
    for (Vec3f p : positions)
      uvs.push_back({mirrored ? (1 - p.x) / 2 : (p.x + 1) / 2, (1 - p.y) / 2});
  }
};

TEST(VertexTangents, AsDrawnLayoutIsRightHandedAlongU) {
  const Quad q(false);
  const std::vector<Vec4f> t = vertexTangents(q.positions, q.normals, q.uvs, q.indices);
  ASSERT_EQ(t.size(), 4u);
  for (const Vec4f& v : t) {
    EXPECT_NEAR(v.x, 1, 1e-6f);
    EXPECT_NEAR(v.y, 0, 1e-6f);
    EXPECT_EQ(v.w, 1);
    // The bitangent cross(n, t) w points up the image: +y.
    const Vec3f b = cross(Vec3f{0, 0, 1}, Vec3f{v.x, v.y, v.z}) * v.w;
    EXPECT_NEAR(b.y, 1, 1e-6f);
  }
  // The same rule as a single triangle's (uvHandedness).
  EXPECT_EQ(uvHandedness({0, 0, 1}, {1, 0, 0}, {0, -1, 0}), 1);
}

TEST(VertexTangents, MirroredLayoutFlipsTheHandednessNotTheImagesUp) {
  const Quad q(true);
  const std::vector<Vec4f> t = vertexTangents(q.positions, q.normals, q.uvs, q.indices);
  for (const Vec4f& v : t) {
    EXPECT_NEAR(v.x, -1, 1e-6f);  // u runs to -x now
    EXPECT_EQ(v.w, -1);
    const Vec3f b = cross(Vec3f{0, 0, 1}, Vec3f{v.x, v.y, v.z}) * v.w;
    EXPECT_NEAR(b.y, 1, 1e-6f);  // still up the image
  }
  EXPECT_EQ(uvHandedness({0, 0, 1}, {-1, 0, 0}, {0, -1, 0}), -1);
}

// A smooth cylinder (u around, v along the axis): every vertex's tangent is perpendicular to
// its normal and follows the circle, where one frame per triangle would turn in steps.
TEST(VertexTangents, SmoothMeshGetsSmoothOrthogonalTangents) {
  const int n = 24;
  std::vector<Vec3f> positions, normals;
  std::vector<Vec2f> uvs;
  std::vector<uint32_t> indices;
  for (int i = 0; i <= n; ++i) {
    const float a = 2 * kPi * float(i) / n;
    for (float y : {0.0f, 1.0f}) {
      positions.push_back({std::cos(a), y, std::sin(a)});
      normals.push_back({std::cos(a), 0, std::sin(a)});
      uvs.push_back({float(i) / n, 1 - y});
    }
  }
  for (uint32_t i = 0; i < uint32_t(n); ++i) {
    const uint32_t a = 2 * i, b = a + 1, c = a + 2, d = a + 3;
    indices.insert(indices.end(), {a, c, b, b, c, d});
  }
  const std::vector<Vec4f> t = vertexTangents(positions, normals, uvs, indices);
  for (size_t k = 0; k < t.size(); ++k) {
    const Vec3f tv{t[k].x, t[k].y, t[k].z};
    EXPECT_NEAR(length(tv), 1, 1e-5f);
    EXPECT_NEAR(dot(tv, normals[k]), 0, 1e-5f);
    // The circle's direction of increasing angle at this vertex, exactly.
    const Vec3f around{-normals[k].z, 0, normals[k].x};
    EXPECT_NEAR(dot(tv, around), 1, 1e-5f) << k;
  }
}

// Triangles without a uv area give no direction: any unit tangent perpendicular to the normal.
TEST(VertexTangents, DegenerateUvsGiveAPerpendicularTangent) {
  Quad q(false);
  for (Vec2f& uv : q.uvs) uv = {0.5f, 0.5f};
  const std::vector<Vec4f> t = vertexTangents(q.positions, q.normals, q.uvs, q.indices);
  for (const Vec4f& v : t) {
    EXPECT_NEAR(length(Vec3f{v.x, v.y, v.z}), 1, 1e-6f);
    EXPECT_NEAR(v.z, 0, 1e-6f);
  }
}

}  // namespace
}  // namespace glint
