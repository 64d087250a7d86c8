// glint tests — small meshes the geometry tests share.
#pragma once

#include "geometry/mesh.h"

namespace glint::test {

// The octahedron with vertices at +-1 on each axis, wound outwards: the smallest closed convex
// mesh, for tests that spawn rays from a surface and must never re-hit it.
inline TriangleMesh unitOctahedron() {
  TriangleMesh m;
  m.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  m.indices = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  return m;
}

}  // namespace glint::test
