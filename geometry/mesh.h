// glint — triangle meshes and their placements: the geometry every accelerator is built from.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/math.h"

namespace glint {

// An indexed triangle mesh in object space. Per-vertex attributes are empty or have one entry
// per position. Embree's convention for barycentrics: p = (1-u-v) p0 + u p1 + v p2.
struct TriangleMesh {
  std::vector<Vec3f> positions;
  std::vector<Vec3f> normals;
  std::vector<Vec2f> uvs;
  std::vector<Vec4f> colors;
  std::vector<uint32_t> indices;  // 3 per triangle

  size_t triangleCount() const { return indices.size() / 3; }
  Bounds3f bounds() const;
};

// One placement of a mesh. Meshes placed several times are built once and instanced.
struct Instance {
  uint32_t mesh = 0;
  Transform worldFromObject;
};

// Everything an accelerator needs: meshes and their placements. Materials live elsewhere and
// are looked up by mesh index: geometry knows nothing of shading.
struct GeometryScene {
  std::vector<TriangleMesh> meshes;
  std::vector<Instance> instances;

  Bounds3f bounds() const;
  size_t uniqueTriangleCount() const;    // triangles stored
  size_t instancedTriangleCount() const; // triangles in the world (instances counted)
};

}  // namespace glint
