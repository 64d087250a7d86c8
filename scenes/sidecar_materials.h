// glint — the sidecar's "textures" and "materials" sections. (Internal to scenes/:
// sidecar.cpp calls them, textures first, since materials name textures.)
#pragma once

#include <string>

#include "scenes/description.h"
#include "scenes/json_reader.h"

namespace glint {

// Reads root["textures"]: images from files (paths relative to `file`'s folder), checkers,
// Perlin patterns and random colours, each with a unique name.
void readTextures(JsonReader& root, const std::string& file, SceneDescription* scene);

// Reads root["materials"]: overrides of glTF materials by name and new materials, with their
// texture references, bump / normal map / snow, and node assignments.
void readMaterials(JsonReader& root, SceneDescription* scene);

}  // namespace glint
