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

}  // namespace glint
