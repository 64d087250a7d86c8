// glint — the scene loading entry point: a glTF file with its sidecar, or a glint .json scene.
#pragma once

#include <optional>
#include <string>

#include "scenes/description.h"

namespace glint {

// Loads SCENE: a .gltf/.glb or a .ply/.obj mesh (with `sidecar`, or NAME.glint.json next to it
// when that exists) or a glint .json scene that may reference glTF files. Throws SceneError.
SceneDescription loadScene(const std::string& path,
                           const std::optional<std::string>& sidecar = std::nullopt);

}  // namespace glint
