// glint — mesh bounds and counts.
#include "geometry/mesh.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace glint {

void placeVertices(const Transform& world, std::vector<Vec3f>* positions,
                   std::vector<uint32_t>* indices) {
  for (Vec3f& p : *positions) p = world.point(p);
  if (world.swapsHandedness())
    for (size_t t = 0; t + 2 < indices->size(); t += 3) std::swap((*indices)[t + 1], (*indices)[t + 2]);
}

Bounds3f TriangleMesh::bounds() const {
  Bounds3f b;
  for (Vec3f p : positions) b.extend(p);
  for (const std::vector<Vec3f>& step : positionSteps)
    for (Vec3f p : step) b.extend(p);
  return b;
}

TriangleMesh::StepBlend timeStepBlend(float time, size_t stepCount) {
  const float segments = float(stepCount - 1);
  const float x = time * segments;
  const float k = std::clamp(std::floor(x), 0.0f, segments - 1);
  return {uint32_t(k), x - k};
}

TriangleMesh::StepBlend TriangleMesh::stepAt(float time) const {
  return timeStepBlend(time, positionSteps.size());
}

Bounds3f GeometryScene::bounds() const {
  std::vector<Bounds3f> meshBounds;
  meshBounds.reserve(meshes.size());
  for (const TriangleMesh& m : meshes) meshBounds.push_back(m.bounds());
  Bounds3f b;
  for (uint32_t i = 0; i < instances.size(); ++i) {
    const Instance& inst = instances[i];
    if (!inst.isShape()) {
      if (inst.moves())
        b.extend(inst.motion.motionBounds(meshBounds[inst.mesh]));
      else
        b.extend(inst.worldFromObject.bounds(meshBounds[inst.mesh]));
    } else if (inst.moves()) {
      Bounds3f sb = shapes[inst.shape]->bounds();
      if (!isUnbounded(sb)) b.extend(inst.motion.motionBounds(sb));
    } else {
      Bounds3f sb = placedShape(i).bounds();
      if (!isUnbounded(sb)) b.extend(sb);
    }
  }
  return b;
}

bool GeometryScene::hasMotion() const {
  for (const Instance& inst : instances)
    if (inst.moves()) return true;
  for (const TriangleMesh& m : meshes)
    if (m.deforms()) return true;
  return false;
}

size_t GeometryScene::uniqueTriangleCount() const {
  size_t n = 0;
  for (const TriangleMesh& m : meshes) n += m.triangleCount();
  return n;
}

size_t GeometryScene::instancedTriangleCount() const {
  size_t n = 0;
  for (const Instance& inst : instances)
    if (!inst.isShape()) n += meshes[inst.mesh].triangleCount();
  return n;
}

size_t GeometryScene::shapeInstanceCount() const {
  size_t n = 0;
  for (const Instance& inst : instances) n += inst.isShape();
  return n;
}

}  // namespace glint
