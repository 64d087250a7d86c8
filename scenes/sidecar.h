// glint — the glint JSON schema: a sidecar (NAME.glint.json next to NAME.gltf, or --sidecar)
// and a glint .json scene, which may also list glTF files to load. scenes/README.md documents
// the schema.
#pragma once

#include <string>
#include <string_view>

#include "scenes/description.h"

namespace glint {

enum class SceneJsonKind {
  Sidecar,  // settings and overrides for an already loaded glTF scene; no "gltf" list
  Scene,    // a whole scene: its "gltf" files are loaded first, then the rest applies
};

// Reads the JSON file at `path` and applies it to `scene`. Throws SceneError with the file and
// JSON pointer of the first problem (or file:line:col for a syntax error).
void applySceneJsonFile(const std::string& path, SceneJsonKind kind, SceneDescription* scene);

// Same for JSON text already in memory; `file` names it in messages, and relative glTF paths
// resolve against its folder.
void applySceneJsonText(std::string_view text, const std::string& file, SceneJsonKind kind,
                        SceneDescription* scene);

// The sidecar that belongs to a glTF file: "dir/NAME.gltf" -> "dir/NAME.glint.json".
std::string defaultSidecarPath(const std::string& gltfPath);

}  // namespace glint
