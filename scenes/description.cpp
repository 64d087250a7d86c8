// glint — SceneDescription helpers.
#include "scenes/description.h"

#include <algorithm>

namespace glint {

Bounds3f sceneBounds(const SceneDescription& scene) {
  std::vector<Bounds3f> meshBounds(scene.meshes.size());
  for (size_t i = 0; i < scene.meshes.size(); ++i)
    for (Vec3f p : scene.meshes[i].positions) meshBounds[i].extend(p);
  Bounds3f b;
  for (const InstanceDesc& inst : scene.instances)
    if (inst.mesh >= 0 && size_t(inst.mesh) < meshBounds.size())
      b.extend(inst.worldFromObject.bounds(meshBounds[size_t(inst.mesh)]));
  return b;
}

std::pair<double, double> animationRange(const SceneDescription& scene) {
  auto [lo, hi] = animationRange(scene.nodes);
  bool any = hi > lo || [&] {
    for (const NodeDesc& n : scene.nodes)
      if (n.hasTracks()) return true;
    return false;
  }();
  for (const InstanceDesc& inst : scene.instances)
    for (const Track<float>& t : inst.weightTracks) {
      if (t.empty()) continue;
      lo = any ? std::min(lo, double(t.startTime())) : double(t.startTime());
      hi = any ? std::max(hi, double(t.endTime())) : double(t.endTime());
      any = true;
    }
  return {lo, hi};
}

void evaluatePlacements(SceneDescription* scene, double time) {
  auto at = [&](int node) { return worldFromNode(scene->nodes, node, time); };
  for (InstanceDesc& i : scene->instances)
    if (i.transformNode >= 0) i.worldFromObject = at(i.transformNode) * i.nodeFromObject;
  for (ObjectDesc& o : scene->objects)
    if (o.transformNode >= 0) o.worldFromObject = at(o.transformNode) * o.nodeFromObject;
  for (CameraDesc& c : scene->cameras)
    if (c.transformNode >= 0) c.worldFromCamera = at(c.transformNode) * c.nodeFromCamera;
  for (LightDesc& l : scene->lights)
    if (l.transformNode >= 0) l.worldFromLight = at(l.transformNode) * l.nodeFromLight;
  for (SkinDesc& s : scene->skins)
    for (SkinDesc::Joint& j : s.joints)
      if (j.node >= 0) j.world = at(j.node);
}

}  // namespace glint
