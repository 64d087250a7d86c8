// glint — SceneDescription helpers.
#include "scenes/description.h"

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
}

}  // namespace glint
