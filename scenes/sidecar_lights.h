// glint — the sidecar's area and projective lights and its "environment". (Internal to
// scenes/: sidecar.cpp calls them.)
#pragma once

#include <initializer_list>
#include <string>

#include "scenes/description.h"
#include "scenes/json_reader.h"

namespace glint {

// True when the object has a "transform"; rejects `others` then, so a frame is never given
// twice.
bool usesTransform(const JsonReader& r, std::initializer_list<const char*> others);
// Whether `type` is read by readSidecarLight (quad, disk, sphere, projective).
bool isSidecarOnlyLight(LightType type);
// Reads the shape and placement of a quad, disk, sphere or projective light into `light`
// (whose type, colour and intensity are already read); textures must be read first.
void readSidecarLight(JsonReader& r, const SceneDescription& scene, LightDesc* light);
// Reads root["environment"] (image paths relative to `file`'s folder).
void readEnvironment(JsonReader& root, const std::string& file, SceneDescription* scene);
// Whether `path` names an image an environment can be read from: scene-linear, OpenEXR (.exr)
// or Radiance (.hdr), by its extension.
bool isEnvironmentImagePath(const std::string& path);

}  // namespace glint
