// glint — fractal terrain: a square subdivided by midpoint displacement into a mountain.
//
// The course's method (a MicroTrace competition entry): the square ABCD of side `size` in the
// XZ plane (y up), centred on the origin, is split into the triangles ABC and ACD; every
// triangle is divided into four by its edge midpoints, `depth` times, giving 2 * 4^depth
// triangles on a (2^depth + 1)^2 vertex grid.
//
// Height = a smooth envelope + a fractal detail:
//   envelope(x, z) = height * (1 - smoothstep(d / R)), d = distance from (x, z) to `peak`,
//                    R = distance from `peak` to the farthest corner of the square;
//   detail         = 0 at the corners; a new midpoint gets the average of its edge's end
//                    details + amplitude(level) * u, where u in [-1, 1) is a hash of the seed
//                    and the midpoint's integer grid coordinates at the finest resolution
//                    (2^kMaxTerrainDepth; they identify the edge), and amplitude(level) =
//                    height / 4 * roughness^(level + 1) (level 0 splits the two big triangles).
// So the highest region is near `peak`, the maximum height is `height` within
// terrainDisplacementBound(), roughness 0 gives the bare envelope, and the random values
// depend on where a midpoint is, not on traversal order: triangles sharing an edge agree on
// its midpoint (no cracks), and a deeper terrain refines a shallower one with the same seed
// (its shared vertices keep their heights).
#pragma once

#include <cstdint>

#include "geometry/math.h"
#include "geometry/mesh.h"

namespace glint {

struct TerrainParams {
  float size = 100;        // side of the square, > 0
  int depth = 7;           // subdivision levels, 0..kMaxTerrainDepth
  float roughness = 0.5f;  // ratio of displacement amplitude between levels, 0..1
  Vec2f peak{0, 0};        // (x, z) of the highest point (may lie outside the square)
  float height = 25;       // peak height of the envelope, >= 0
  uint64_t seed = 1;
};

// 2 * 4^12 = 33.5 M triangles: beyond that, memory (and 32-bit indices) run out.
inline constexpr int kMaxTerrainDepth = 12;

// The indexed terrain mesh: positions, area-weighted unit vertex normals (y > 0), uvs
// (x / size + 0.5, z / size + 0.5) and indices wound so that cross(p1 - p0, p2 - p0) points up.
// Vertex (i, j) of the grid (x from i, z from j) is at index j * (2^depth + 1) + i.
// Params must be valid (finite, in the ranges above): asserted, not reported.
TriangleMesh makeFractalTerrain(const TerrainParams& params);

// The smooth envelope's height at (x, z): the terrain without its fractal detail.
float terrainEnvelope(const TerrainParams& params, float x, float z);

// The most a vertex's height can differ from the envelope: the sum of the level amplitudes.
float terrainDisplacementBound(const TerrainParams& params);

}  // namespace glint
