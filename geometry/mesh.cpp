// glint — mesh bounds and counts.
#include "geometry/mesh.h"

namespace glint {

Bounds3f TriangleMesh::bounds() const {
  Bounds3f b;
  for (Vec3f p : positions) b.extend(p);
  return b;
}

Bounds3f GeometryScene::bounds() const {
  std::vector<Bounds3f> meshBounds;
  meshBounds.reserve(meshes.size());
  for (const TriangleMesh& m : meshes) meshBounds.push_back(m.bounds());
  Bounds3f b;
  for (const Instance& inst : instances)
    b.extend(inst.worldFromObject.bounds(meshBounds[inst.mesh]));
  return b;
}

size_t GeometryScene::uniqueTriangleCount() const {
  size_t n = 0;
  for (const TriangleMesh& m : meshes) n += m.triangleCount();
  return n;
}

size_t GeometryScene::instancedTriangleCount() const {
  size_t n = 0;
  for (const Instance& inst : instances) n += meshes[inst.mesh].triangleCount();
  return n;
}

}  // namespace glint
