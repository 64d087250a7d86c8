// glint tests — fractal terrain: counts, watertightness, determinism, shape and normals.
#include "geometry/terrain.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

namespace glint {
namespace {

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

TerrainParams paramsWith(int depth, uint64_t seed = 1) {
  TerrainParams p;
  p.depth = depth;
  p.seed = seed;
  return p;
}

float maxHeight(const TriangleMesh& mesh) {
  float y = -kInfinity;
  for (Vec3f q : mesh.positions) y = std::max(y, q.y);
  return y;
}

Vec3f highestVertex(const TriangleMesh& mesh) {
  return *std::max_element(mesh.positions.begin(), mesh.positions.end(),
                           [](Vec3f a, Vec3f b) { return a.y < b.y; });
}

float distanceXZ(Vec3f q, Vec2f p) { return std::hypot(q.x - p.x, q.z - p.y); }

// ---------------------------------------------------------------------------------------------
// Topology
// ---------------------------------------------------------------------------------------------

TEST(Terrain, TriangleCountIsTwoTimesFourToTheDepth) {
  for (int depth = 0; depth <= 7; ++depth) {
    TriangleMesh mesh = makeFractalTerrain(paramsWith(depth));
    EXPECT_EQ(mesh.triangleCount(), size_t(2) << (2 * depth)) << "depth " << depth;
  }
  EXPECT_EQ(makeFractalTerrain(paramsWith(7)).triangleCount(), 32768u);
}

TEST(Terrain, VerticesFormTheGridWithoutDuplicates) {
  for (int depth = 0; depth <= 7; ++depth) {
    TriangleMesh mesh = makeFractalTerrain(paramsWith(depth));
    size_t side = (size_t(1) << depth) + 1;
    ASSERT_EQ(mesh.positions.size(), side * side) << "depth " << depth;
    EXPECT_EQ(mesh.normals.size(), mesh.positions.size());
    EXPECT_EQ(mesh.uvs.size(), mesh.positions.size());
    EXPECT_TRUE(mesh.colors.empty());
    // Every vertex is used and no two share an (x, z).
    std::vector<int> used(mesh.positions.size(), 0);
    for (uint32_t k : mesh.indices) {
      ASSERT_LT(k, mesh.positions.size());
      used[k] = 1;
    }
    EXPECT_EQ(std::count(used.begin(), used.end(), 1), long(used.size()));
    std::map<std::pair<float, float>, int> seen;
    for (Vec3f q : mesh.positions) EXPECT_EQ((seen[{q.x, q.z}]++), 0) << q.x << ", " << q.z;
  }
}

TEST(Terrain, IsWatertight) {
  TerrainParams p = paramsWith(6);
  TriangleMesh mesh = makeFractalTerrain(p);
  std::map<std::pair<uint32_t, uint32_t>, int> edgeUses;
  for (size_t t = 0; t < mesh.indices.size(); t += 3)
    for (int e = 0; e < 3; ++e) {
      uint32_t a = mesh.indices[t + e], b = mesh.indices[t + (e + 1) % 3];
      ASSERT_NE(a, b) << "degenerate triangle " << t / 3;
      ++edgeUses[{std::min(a, b), std::max(a, b)}];
    }
  float half = p.size / 2;
  auto onBoundary = [&](Vec3f q) { return std::abs(q.x) == half || std::abs(q.z) == half; };
  size_t boundaryEdges = 0;
  for (const auto& [edge, uses] : edgeUses) {
    Vec3f a = mesh.positions[edge.first], b = mesh.positions[edge.second];
    // A boundary edge runs along one side of the square: both ends share that side's x or z.
    bool boundary =
        onBoundary(a) && onBoundary(b) &&
        ((a.x == b.x && std::abs(a.x) == half) || (a.z == b.z && std::abs(a.z) == half));
    EXPECT_EQ(uses, boundary ? 1 : 2) << "edge " << edge.first << "-" << edge.second;
    boundaryEdges += boundary;
  }
  EXPECT_EQ(boundaryEdges, size_t(4) << p.depth);
  // Euler characteristic of a disk: V - E + F = 1.
  EXPECT_EQ(long(mesh.positions.size()) - long(edgeUses.size()) + long(mesh.triangleCount()), 1);
}

// ---------------------------------------------------------------------------------------------
// Determinism
// ---------------------------------------------------------------------------------------------

TEST(Terrain, SameParamsGiveTheIdenticalMesh) {
  TerrainParams p = paramsWith(7, 42);
  p.peak = {10, -20};
  TriangleMesh a = makeFractalTerrain(p), b = makeFractalTerrain(p);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.uvs, b.uvs);
  EXPECT_EQ(a.indices, b.indices);
}

TEST(Terrain, DifferentSeedsGiveDifferentHeights) {
  TriangleMesh a = makeFractalTerrain(paramsWith(5, 1)), b = makeFractalTerrain(paramsWith(5, 2));
  ASSERT_EQ(a.positions.size(), b.positions.size());
  size_t differ = 0;
  for (size_t k = 0; k < a.positions.size(); ++k) {
    EXPECT_EQ(a.positions[k].x, b.positions[k].x);
    EXPECT_EQ(a.positions[k].z, b.positions[k].z);
    differ += a.positions[k].y != b.positions[k].y;
  }
  // Only the four corners (the bare envelope) are certain to agree.
  EXPECT_GT(differ, a.positions.size() / 2);
  EXPECT_EQ(a.indices, b.indices);
}

// The random values depend on positions, not on the depth: adding levels only adds detail.
TEST(Terrain, DeeperTerrainRefinesTheShallowerOne) {
  TriangleMesh coarse = makeFractalTerrain(paramsWith(4, 9)),
               fine = makeFractalTerrain(paramsWith(6, 9));
  uint32_t coarseSide = (1u << 4) + 1, fineSide = (1u << 6) + 1;
  for (uint32_t j = 0; j < coarseSide; ++j)
    for (uint32_t i = 0; i < coarseSide; ++i)
      EXPECT_EQ(coarse.positions[j * coarseSide + i], fine.positions[4 * j * fineSide + 4 * i])
          << i << ", " << j;
}

// ---------------------------------------------------------------------------------------------
// Shape
// ---------------------------------------------------------------------------------------------

TEST(Terrain, CoversTheSquareWithMatchingUvs) {
  TerrainParams p = paramsWith(5);
  p.size = 40;
  TriangleMesh mesh = makeFractalTerrain(p);
  Bounds3f b = mesh.bounds();
  EXPECT_EQ(b.lower.x, -20);
  EXPECT_EQ(b.upper.x, 20);
  EXPECT_EQ(b.lower.z, -20);
  EXPECT_EQ(b.upper.z, 20);
  for (size_t k = 0; k < mesh.positions.size(); ++k) {
    EXPECT_FLOAT_EQ(mesh.uvs[k].x, mesh.positions[k].x / p.size + 0.5f);
    EXPECT_FLOAT_EQ(mesh.uvs[k].y, mesh.positions[k].z / p.size + 0.5f);
  }
}

TEST(Terrain, HeightsStayWithinTheDisplacementBoundOfTheEnvelope) {
  TerrainParams p = paramsWith(7, 5);
  p.peak = {-15, 25};
  float bound = terrainDisplacementBound(p);
  // Roughness 0.5: height / 4 * (1/2 + 1/4 + ... + 1/128).
  EXPECT_NEAR(bound, p.height * 0.25f * (1 - 1.0f / 128), 1e-4f);
  TriangleMesh mesh = makeFractalTerrain(p);
  for (Vec3f q : mesh.positions)
    EXPECT_LE(std::abs(q.y - terrainEnvelope(p, q.x, q.z)), bound * 1.0001f);
}

// Tolerance: the envelope peaks at `height` and the detail adds at most the displacement bound
// (~height / 4 at roughness 0.5); the vertex nearest the peak is within a cell of it, where the
// envelope is still above 0.99 * height.
TEST(Terrain, HighestPointIsAboutHeightAndNearThePeak) {
  for (uint64_t seed : {1, 2, 3, 77}) {
    TerrainParams p = paramsWith(7, seed);
    p.peak = {10, -20};
    TriangleMesh mesh = makeFractalTerrain(p);
    float bound = terrainDisplacementBound(p);
    float top = maxHeight(mesh);
    EXPECT_LE(top, p.height + bound) << "seed " << seed;
    EXPECT_GE(top, 0.99f * p.height - bound) << "seed " << seed;
    Vec3f highest = highestVertex(mesh);
    float toFarthestCorner = 0;
    for (Vec3f q : mesh.positions)
      if (std::abs(q.x) == p.size / 2 && std::abs(q.z) == p.size / 2)
        toFarthestCorner = std::max(toFarthestCorner, distanceXZ(q, {highest.x, highest.z}));
    EXPECT_LT(distanceXZ(highest, p.peak), toFarthestCorner) << "seed " << seed;
    // In practice the summit sits well inside the peak's quarter of the square.
    EXPECT_LT(distanceXZ(highest, p.peak), p.size / 4) << "seed " << seed;
  }
}

TEST(Terrain, ZeroRoughnessGivesTheSmoothEnvelope) {
  TerrainParams p = paramsWith(6, 123);
  p.roughness = 0;
  EXPECT_EQ(terrainDisplacementBound(p), 0);
  TriangleMesh mesh = makeFractalTerrain(p);
  for (Vec3f q : mesh.positions) EXPECT_EQ(q.y, terrainEnvelope(p, q.x, q.z));
  // Independently of the formula: with the peak at the centre the surface is symmetric and
  // falls steadily away from the top, which sits exactly at `height`.
  uint32_t side = (1u << p.depth) + 1;
  auto y = [&](uint32_t i, uint32_t j) { return mesh.positions[j * side + i].y; };
  for (uint32_t j = 0; j < side; ++j)
    for (uint32_t i = 0; i < side; ++i) {
      EXPECT_FLOAT_EQ(y(i, j), y(j, i));
      EXPECT_FLOAT_EQ(y(i, j), y(side - 1 - i, j));
      if (i + 1 < side && i >= side / 2) {
        EXPECT_GE(y(i, j), y(i + 1, j));
      }
    }
  EXPECT_EQ(maxHeight(mesh), p.height);
  EXPECT_EQ(highestVertex(mesh).x, 0);
  EXPECT_EQ(highestVertex(mesh).z, 0);
  // Another seed changes nothing without displacement.
  p.seed = 7;
  EXPECT_EQ(makeFractalTerrain(p).positions, mesh.positions);
}

TEST(Terrain, NonzeroRoughnessDisplacesTheEnvelope) {
  TerrainParams p = paramsWith(4);
  TriangleMesh mesh = makeFractalTerrain(p);
  size_t displaced = 0;
  for (Vec3f q : mesh.positions) displaced += q.y != terrainEnvelope(p, q.x, q.z);
  EXPECT_EQ(displaced, mesh.positions.size() - 4);  // all but the corners
}

// ---------------------------------------------------------------------------------------------
// Normals and winding
// ---------------------------------------------------------------------------------------------

TEST(Terrain, VertexNormalsAreUnitAndPointUp) {
  TerrainParams p = paramsWith(7, 3);
  p.roughness = 0.8f;  // steep slopes
  TriangleMesh mesh = makeFractalTerrain(p);
  for (Vec3f n : mesh.normals) {
    EXPECT_NEAR(length(n), 1, 1e-5f);
    EXPECT_GT(n.y, 0);
  }
}

TEST(Terrain, FacesAreWoundToPointUp) {
  TerrainParams p = paramsWith(7, 3);
  p.roughness = 0.8f;
  TriangleMesh mesh = makeFractalTerrain(p);
  for (size_t t = 0; t < mesh.indices.size(); t += 3) {
    Vec3f p0 = mesh.positions[mesh.indices[t]], p1 = mesh.positions[mesh.indices[t + 1]],
          p2 = mesh.positions[mesh.indices[t + 2]];
    ASSERT_GT(cross(p1 - p0, p2 - p0).y, 0) << "triangle " << t / 3;
  }
}

TEST(Terrain, VertexNormalOfAFlatTerrainIsStraightUp) {
  TerrainParams p = paramsWith(3);
  p.height = 0;
  TriangleMesh mesh = makeFractalTerrain(p);
  for (Vec3f q : mesh.positions) EXPECT_EQ(q.y, 0);
  for (Vec3f n : mesh.normals) EXPECT_EQ(n, (Vec3f{0, 1, 0}));
}

}  // namespace
}  // namespace glint
