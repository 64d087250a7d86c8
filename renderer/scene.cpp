// glint — feature detection over a built scene.
#include "renderer/scene.h"

#include "geometry/csg.h"

namespace glint {

SceneFeatures detectFeatures(const RenderScene& scene) {
  SceneFeatures f;
  std::vector<uint32_t> uses(scene.geometry.meshes.size(), 0);
  bool anyLit = false;
  for (const Instance& inst : scene.geometry.instances) {
    if (!inst.isShape()) {
      ++uses[inst.mesh];
      continue;
    }
    f.set(Feature::Analytic);
    if (dynamic_cast<const CsgShape*>(scene.geometry.shapes[inst.shape].get()))
      f.set(Feature::Csg);
    for (uint32_t m : scene.shapeMaterials[inst.shape]) {
      const Material& mat = *scene.materials[m];
      if (mat.usesTextures()) f.set(Feature::Textures);
      if (mat.emits()) f.set(Feature::Emission);
      if (!(mat.flags() & kBsdfUnlit)) anyLit = true;
    }
  }
  for (size_t m = 0; m < scene.geometry.meshes.size(); ++m) {
    if (uses[m] == 0) continue;
    if (uses[m] > 1) f.set(Feature::Instancing);
    const Material& mat = scene.materialOf(uint32_t(m));
    if (mat.usesTextures()) f.set(Feature::Textures);
    if (mat.usesVertexColors()) f.set(Feature::VertexColors);
    if (mat.emits()) f.set(Feature::Emission);
    if (!(mat.flags() & kBsdfUnlit)) anyLit = true;
  }
  for (const auto& light : scene.lights)
    if (light->castsShadows() && anyLit) f.set(Feature::Shadows);
  return f;
}

}  // namespace glint
