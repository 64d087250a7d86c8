// glint — fractal terrain by recursive triangle subdivision with midpoint displacement.
#include "geometry/terrain.h"

#include <cassert>
#include <cmath>
#include <vector>

namespace glint {

namespace {

// Share of `height` given to the first level's displacement: with roughness 0.5 the detail
// stays within height / 4 of the envelope, so the peak keeps its place and about its height.
constexpr float kAmplitude = 0.25f;

// splitmix64's finalizer: every input bit affects every output bit.
uint64_t mix64(uint64_t z) {
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// A uniform value in [-1, 1) for one grid position: a pure function of where the midpoint is,
// so every triangle sharing the edge, in any traversal order, computes the same one.
float hashUnit(uint64_t seed, uint32_t i, uint32_t j) {
  uint64_t h = mix64(seed ^ mix64((uint64_t(i) << 32) | j));
  return float(h >> 40) * 0x1p-23f - 1;  // 24 bits: exact in a float
}

[[maybe_unused]] bool validParams(const TerrainParams& p) {
  return std::isfinite(p.size) && p.size > 0 && p.depth >= 0 && p.depth <= kMaxTerrainDepth &&
         p.roughness >= 0 && p.roughness <= 1 && std::isfinite(p.peak.x) &&
         std::isfinite(p.peak.y) && std::isfinite(p.height) && p.height >= 0;
}

float levelAmplitude(const TerrainParams& p, int level) {
  return p.height * kAmplitude * std::pow(p.roughness, float(level + 1));
}

struct GridPoint {
  uint32_t i, j;
};

// Subdivides the triangles and computes the detail (height over the envelope) of every vertex
// as it is created; emits the leaf triangles' indices.
class TerrainBuilder {
 public:
  explicit TerrainBuilder(const TerrainParams& p)
      : p_(p),
        n_(1u << p.depth),
        detail_(size_t(n_ + 1) * (n_ + 1), 0.0f),
        known_(detail_.size(), 0) {
    for (int level = 0; level < p.depth; ++level) amplitude_.push_back(levelAmplitude(p, level));
    indices_.reserve(size_t(6) << (2 * p.depth));
  }

  void build() {
    GridPoint a{0, 0}, b{n_, 0}, c{n_, n_}, d{0, n_};
    for (GridPoint q : {a, b, c, d}) known_[index(q)] = 1;  // corners: the bare envelope
    // ABC and ACD, wound so that cross(p1 - p0, p2 - p0) points up (+Y).
    subdivide(a, c, b, 0);
    subdivide(a, d, c, 0);
  }

  uint32_t index(GridPoint q) const { return q.j * (n_ + 1) + q.i; }
  uint32_t n() const { return n_; }
  const std::vector<float>& detail() const { return detail_; }
  std::vector<uint32_t>& indices() { return indices_; }

 private:
  // The midpoint of edge ab, split at `level`; its detail is computed once, on first visit.
  GridPoint midpoint(GridPoint a, GridPoint b, int level) {
    GridPoint m{(a.i + b.i) / 2, (a.j + b.j) / 2};
    uint32_t k = index(m);
    if (!known_[k]) {
      // Hash the position at the finest resolution, so a deeper terrain refines this one.
      uint32_t shift = kMaxTerrainDepth - p_.depth;
      float u = hashUnit(p_.seed, m.i << shift, m.j << shift);
      detail_[k] = 0.5f * (detail_[index(a)] + detail_[index(b)]) + amplitude_[level] * u;
      known_[k] = 1;
    }
    return m;
  }

  // Orientation is inherited: each child lists its corners in the parent's order.
  void subdivide(GridPoint a, GridPoint b, GridPoint c, int level) {
    if (level == p_.depth) {
      indices_.insert(indices_.end(), {index(a), index(b), index(c)});
      return;
    }
    GridPoint ab = midpoint(a, b, level), bc = midpoint(b, c, level), ca = midpoint(c, a, level);
    subdivide(a, ab, ca, level + 1);
    subdivide(ab, b, bc, level + 1);
    subdivide(ca, bc, c, level + 1);
    subdivide(ab, bc, ca, level + 1);
  }

  const TerrainParams& p_;
  uint32_t n_;
  std::vector<float> amplitude_;
  std::vector<float> detail_;
  std::vector<uint8_t> known_;
  std::vector<uint32_t> indices_;
};

}  // namespace

float terrainEnvelope(const TerrainParams& p, float x, float z) {
  float half = 0.5f * p.size;
  float reach = 0;  // distance from the peak to the farthest corner
  for (float cx : {-half, half})
    for (float cz : {-half, half})
      reach = std::max(reach, std::hypot(cx - p.peak.x, cz - p.peak.y));
  float t = std::min(std::hypot(x - p.peak.x, z - p.peak.y) / reach, 1.0f);
  return p.height * (1 - t * t * (3 - 2 * t));  // 1 - smoothstep: flat at the top and the foot
}

float terrainDisplacementBound(const TerrainParams& p) {
  float bound = 0;
  for (int level = 0; level < p.depth; ++level) bound += levelAmplitude(p, level);
  return bound;
}

TriangleMesh makeFractalTerrain(const TerrainParams& p) {
  assert(validParams(p));

  TerrainBuilder builder(p);
  builder.build();
  uint32_t n = builder.n();

  TriangleMesh mesh;
  size_t vertexCount = size_t(n + 1) * (n + 1);
  mesh.positions.resize(vertexCount);
  mesh.uvs.resize(vertexCount);
  for (uint32_t j = 0; j <= n; ++j) {
    for (uint32_t i = 0; i <= n; ++i) {
      uint32_t k = j * (n + 1) + i;
      // i / n is exact (n is a power of two), so the edges sit exactly at +-size/2.
      Vec2f uv{float(i) / float(n), float(j) / float(n)};
      float x = p.size * (uv.x - 0.5f), z = p.size * (uv.y - 0.5f);
      mesh.positions[k] = {x, terrainEnvelope(p, x, z) + builder.detail()[k], z};
      mesh.uvs[k] = uv;
    }
  }
  mesh.indices = std::move(builder.indices());

  // Area-weighted vertex normals: the unnormalized face normal's length is twice the area.
  // Every face normal points up (its y is the projected XZ area), so their sum does too.
  mesh.normals.assign(vertexCount, Vec3f{0, 0, 0});
  for (size_t t = 0; t < mesh.indices.size(); t += 3) {
    uint32_t i0 = mesh.indices[t], i1 = mesh.indices[t + 1], i2 = mesh.indices[t + 2];
    const Vec3f &p0 = mesh.positions[i0], &p1 = mesh.positions[i1], &p2 = mesh.positions[i2];
    Vec3f faceNormal = cross(p1 - p0, p2 - p0);
    mesh.normals[i0] += faceNormal, mesh.normals[i1] += faceNormal, mesh.normals[i2] += faceNormal;
  }
  for (Vec3f& normal : mesh.normals) normal = normalize(normal);
  return mesh;
}

}  // namespace glint
