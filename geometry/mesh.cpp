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
    for (size_t t = 0; t + 2 < indices->size(); t += 3)
      std::swap((*indices)[t + 1], (*indices)[t + 2]);
}

std::vector<Vec4f> vertexTangents(const std::vector<Vec3f>& positions,
                                  const std::vector<Vec3f>& normals, const std::vector<Vec2f>& uvs,
                                  const std::vector<uint32_t>& indices) {
  const size_t n = positions.size();
  // Per vertex, the weighted sums of the right-handed and the mirrored triangles' tangents.
  std::vector<Vec3f> sum[2] = {std::vector<Vec3f>(n), std::vector<Vec3f>(n)};
  std::vector<float> weight[2] = {std::vector<float>(n), std::vector<float>(n)};
  for (size_t t = 0; t + 2 < indices.size(); t += 3) {
    const uint32_t v[3] = {indices[t], indices[t + 1], indices[t + 2]};
    const Vec3f dp1 = positions[v[1]] - positions[v[0]], dp2 = positions[v[2]] - positions[v[0]];
    const Vec2f duv1 = uvs[v[1]] - uvs[v[0]], duv2 = uvs[v[2]] - uvs[v[0]];
    const float det = duv1.x * duv2.y - duv1.y * duv2.x;
    if (!(std::abs(det) > 0)) continue;
    const Vec3f dpdu = (dp1 * duv2.y - dp2 * duv1.y) / det;
    const Vec3f dpdv = (dp2 * duv1.x - dp1 * duv2.x) / det;
    const Vec3f face = cross(dp1, dp2);
    if (!isFinite(dpdu) || !isFinite(dpdv) || !(lengthSquared(face) > 0)) continue;
    const int side = uvHandedness(normalize(face), dpdu, dpdv) > 0 ? 0 : 1;
    for (int k = 0; k < 3; ++k) {
      const Vec3f nv = normals[v[k]];
      const Vec3f projected = dpdu - nv * dot(nv, dpdu);
      const float len = length(projected);
      if (!(len > 0)) continue;
      // The triangle's angle at this corner.
      const Vec3f a = positions[v[(k + 1) % 3]] - positions[v[k]];
      const Vec3f b = positions[v[(k + 2) % 3]] - positions[v[k]];
      const float la = length(a), lb = length(b);
      if (!(la > 0) || !(lb > 0)) continue;
      const float angle = std::acos(std::clamp(dot(a, b) / (la * lb), -1.0f, 1.0f));
      sum[side][v[k]] += projected * (angle / len);
      weight[side][v[k]] += angle;
    }
  }
  std::vector<Vec4f> tangents(n);
  for (size_t i = 0; i < n; ++i) {
    const int side = weight[1][i] > weight[0][i] ? 1 : 0;
    const Vec3f nv = normals[i];
    Vec3f t = sum[side][i] - nv * dot(nv, sum[side][i]);
    const float len = length(t);
    t = len > 0 && std::isfinite(len) ? t / len : Frame::fromZ(nv).s;
    tangents[i] = {t.x, t.y, t.z, side == 0 ? 1.0f : -1.0f};
  }
  return tangents;
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
