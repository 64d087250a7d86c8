// glint — the sidecar's "media" section: participating media in regions.
// (Internal to scenes/: sidecar.cpp calls it after the objects, which regions may name.)
#pragma once

#include <string>

#include "scenes/description.h"
#include "scenes/json_reader.h"

namespace glint {

// Reads root["media"] into scene->media. `file` is the JSON file (.vol paths are relative to
// it). Object names must exist in scene->objects.
void readMedia(JsonReader& root, const std::string& file, SceneDescription* scene);

// The sidecar's name for a density type ("constant", "grid", "noise", "exponential", "vdb").
const std::string& densityTypeName(DensityType type);

}  // namespace glint
