// glint — glTF 2.0 loading (.gltf with external or embedded data, .glb) into a
// SceneDescription.
#pragma once

#include <string>

#include "scenes/description.h"

namespace glint {

// Appends the file's default scene (or scene 0, or all root nodes when there is no scene)
// to `scene`, placed under `rootTransform`: meshes, materials, textures, images, cameras,
// KHR_lights_punctual lights and one instance per (node, primitive). Throws SceneError naming
// the file and the JSON pointer of anything malformed.
void loadGltf(const std::string& path, SceneDescription* scene,
              const Transform& rootTransform = Transform());

}  // namespace glint
