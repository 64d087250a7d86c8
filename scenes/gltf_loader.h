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
//
// Animations: all animations of the file play together on one clock (a property driven by two
// animations takes the first, with a warning; morph target weights are ignored with a
// warning). Nodes whose placement can change (animated, below an animated node, or an
// ancestor of one) are appended to scene->nodes (under a node holding `rootTransform` when that
// is not the identity); instances, cameras and lights below an animated node get its
// transformNode with an identity nodeFrom*, and their static transforms hold the placement at
// time 0.
void loadGltf(const std::string& path, SceneDescription* scene,
              const Transform& rootTransform = Transform());

// Same for the contents of a .gltf or .glb file already in memory: `path` names it in messages,
// its folder is where relative URIs resolve, and a ".glb" extension (or the GLB magic at the
// start of `bytes`) selects the binary container.
void loadGltfFromMemory(const std::string& bytes, const std::string& path, SceneDescription* scene,
                        const Transform& rootTransform = Transform());

}  // namespace glint
