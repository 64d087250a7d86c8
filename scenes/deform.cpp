// glint — skinning and morph targets (see deform.h).
#include "scenes/deform.h"

#include <cmath>

namespace glint {

bool deforms(const SceneDescription& scene, const InstanceDesc& inst) {
  const MeshDesc& mesh = scene.meshes[size_t(inst.mesh)];
  return inst.skin >= 0 || !mesh.targets.empty();
}

bool deformationAnimated(const SceneDescription& scene, const InstanceDesc& inst) {
  for (const Track<float>& t : inst.weightTracks)
    if (!t.empty()) return true;
  if (inst.skin < 0) return false;
  for (const SkinDesc::Joint& j : scene.skins[size_t(inst.skin)].joints)
    if (j.node >= 0 && isAnimated(scene.nodes, j.node)) return true;
  return false;
}

std::vector<float> morphWeightsAt(const SceneDescription& scene, const InstanceDesc& inst,
                                  double time) {
  const MeshDesc& mesh = scene.meshes[size_t(inst.mesh)];
  std::vector<float> w(mesh.targets.size(), 0.0f);
  const std::vector<float>& rest = inst.morphWeights.empty() ? mesh.weights : inst.morphWeights;
  for (size_t i = 0; i < w.size() && i < rest.size(); ++i) w[i] = rest[i];
  for (size_t i = 0; i < w.size() && i < inst.weightTracks.size(); ++i)
    if (!inst.weightTracks[i].empty()) w[i] = evaluate(inst.weightTracks[i], time);
  return w;
}

namespace {

// An affine map as 3 rows of 4, blended cheaply per vertex.
struct Affine {
  float m[3][4] = {};
  void add(const Mat4& a, float w) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) m[r][c] += w * a.m[r][c];
  }
  Vec3f point(Vec3f p) const {
    return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
            m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
            m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
  }
  Vec3f vector(Vec3f v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
            m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
  }
  // The cofactor matrix of the linear part times n: det · M^-T n, whose rows are the cross
  // products of M's rows; for a mirroring blend it points the wrong way, and the sign of det
  // puts it back.
  Vec3f normal(Vec3f n) const {
    const Vec3f r0{m[0][0], m[0][1], m[0][2]}, r1{m[1][0], m[1][1], m[1][2]},
        r2{m[2][0], m[2][1], m[2][2]};
    const Vec3f c0 = cross(r1, r2), c1 = cross(r2, r0), c2 = cross(r0, r1);
    const float det = dot(r0, c0);
    const Vec3f out{dot(c0, n), dot(c1, n), dot(c2, n)};
    return det < 0 ? -out : out;
  }
};

Vec3f normalizedOr(Vec3f v, Vec3f fallback) {
  const float len = length(v);
  return len > 0 && std::isfinite(len) ? v / len : fallback;
}

}  // namespace

namespace {

// Poses the attributes the caller asks for (null: not wanted) of instance `inst`'s mesh at
// `time`; each must hold the mesh's own values on entry.
void pose(const SceneDescription& scene, const InstanceDesc& inst, double time,
          std::vector<Vec3f>* positions, std::vector<Vec3f>* normals,
          std::vector<Vec4f>* tangents) {
  const MeshDesc& mesh = scene.meshes[size_t(inst.mesh)];
  const size_t n = mesh.positions.size();
  if (!mesh.targets.empty()) {
    const std::vector<float> w = morphWeightsAt(scene, inst, time);
    for (size_t t = 0; t < mesh.targets.size(); ++t) {
      if (w[t] == 0) continue;
      const MorphTargetDesc& target = mesh.targets[t];
      for (size_t i = 0; i < target.positions.size(); ++i)
        (*positions)[i] += w[t] * target.positions[i];
      if (normals)
        for (size_t i = 0; i < target.normals.size() && i < normals->size(); ++i)
          (*normals)[i] += w[t] * target.normals[i];
      if (tangents)
        for (size_t i = 0; i < target.tangents.size() && i < tangents->size(); ++i) {
          const Vec3f d = w[t] * target.tangents[i];
          Vec4f& tv = (*tangents)[i];
          tv = {tv.x + d.x, tv.y + d.y, tv.z + d.z, tv.w};
        }
    }
    if (normals)
      for (Vec3f& nv : *normals) nv = normalizedOr(nv, {0, 0, 1});
    if (tangents)
      for (Vec4f& tv : *tangents) {
        const Vec3f t = normalizedOr({tv.x, tv.y, tv.z}, {1, 0, 0});
        tv = {t.x, t.y, t.z, tv.w};
      }
  }
  if (inst.skin < 0 || mesh.joints.empty()) return;
  const SkinDesc& skin = scene.skins[size_t(inst.skin)];
  std::vector<Mat4> joint(skin.joints.size());
  for (size_t j = 0; j < joint.size(); ++j) {
    const SkinDesc::Joint& sj = skin.joints[j];
    const Transform world = sj.node >= 0 ? worldFromNode(scene.nodes, sj.node, time) : sj.world;
    joint[j] = world.matrix() * skin.inverseBind[j].matrix();
  }
  for (size_t i = 0; i < n; ++i) {
    const Vec4f wv = mesh.jointWeights[i];
    const float w[4] = {wv.x, wv.y, wv.z, wv.w};
    const float sum = w[0] + w[1] + w[2] + w[3];
    if (!(sum > 0)) continue;  // no influence: the vertex stays where the file put it
    Affine blend;
    for (int k = 0; k < 4; ++k)
      if (w[k] > 0) blend.add(joint[mesh.joints[i][size_t(k)]], w[k] / sum);
    (*positions)[i] = blend.point((*positions)[i]);
    if (normals && !normals->empty())
      (*normals)[i] = normalizedOr(blend.normal((*normals)[i]), (*normals)[i]);
    if (tangents && !tangents->empty()) {
      const Vec4f tv = (*tangents)[i];
      const Vec3f t = normalizedOr(blend.vector({tv.x, tv.y, tv.z}), {tv.x, tv.y, tv.z});
      (*tangents)[i] = {t.x, t.y, t.z, tv.w};
    }
  }
}

}  // namespace

MeshDesc posedMesh(const SceneDescription& scene, const InstanceDesc& inst, double time) {
  MeshDesc mesh = scene.meshes[size_t(inst.mesh)];
  pose(scene, inst, time, &mesh.positions, &mesh.normals, &mesh.tangents);
  mesh.targets.clear();
  mesh.joints.clear();
  mesh.jointWeights.clear();
  return mesh;
}

std::vector<Vec3f> posedPositions(const SceneDescription& scene, const InstanceDesc& inst,
                                  double time) {
  std::vector<Vec3f> positions = scene.meshes[size_t(inst.mesh)].positions;
  pose(scene, inst, time, &positions, nullptr, nullptr);
  return positions;
}

void posedVertices(const SceneDescription& scene, const InstanceDesc& inst, double time,
                   std::vector<Vec3f>* positions, std::vector<Vec3f>* normals) {
  const MeshDesc& mesh = scene.meshes[size_t(inst.mesh)];
  *positions = mesh.positions;
  *normals = mesh.normals;
  pose(scene, inst, time, positions, normals, nullptr);
}

}  // namespace glint
