// glint — the scene as the renderer sees it: its accelerator and placed shapes.
#include "renderer/scene.h"

namespace glint {

void RenderScene::buildAccelerator(const std::string& name) {
  accel = makeAccelerator(name, geometry);
  placedShapes.clear();
  placedShapeOf.clear();
  for (uint32_t i = 0; i < geometry.instances.size(); ++i) {
    const Instance& inst = geometry.instances[i];
    if (!inst.isShape() || inst.moves()) continue;
    // Only now that there is one: a scene of meshes alone keeps no per-instance table.
    if (placedShapeOf.empty()) placedShapeOf.assign(geometry.instances.size(), kNoPlacement);
    placedShapeOf[i] = uint32_t(placedShapes.size());
    placedShapes.push_back(geometry.placedShape(i));
  }
}

}  // namespace glint
