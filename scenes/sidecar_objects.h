// glint — the sidecar's "objects" section: analytic primitives, CSG trees and fractal terrain.
// (Internal to scenes/: sidecar.cpp calls it after the materials, which objects name.)
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "geometry/shapes/registry.h"
#include "scenes/description.h"
#include "scenes/json_reader.h"

namespace glint {

// Reads root["objects"] into scene->objects. `file` is the JSON file (for .csg paths, which
// are relative to it). Material names must exist in scene->materials.
void readObjects(JsonReader& root, const std::string& file, SceneDescription* scene);

// The registered shape keywords (geometry/shapes/registry.h), for "type" keys.
std::vector<std::string> shapeNames();
// One primitive of `kind` from its keys (the caller reads "type" itself).
ShapeRef readShape(JsonReader& r, const ShapeKind& kind);

// The optional "animation" of an object, camera or light: translation, rotation and scale
// keyframes (T(t) · R(t) · S(t), applied after the item's own transform), as a NodeDesc
// without parent. Empty when `item` has no "animation".
std::optional<NodeDesc> readAnimation(JsonReader& item, const std::string& name);

// Resolves the material names a .csg file gave its leaves (CsgNodeDesc::materialName) against
// scene.materials (errors are located at the leaf's file:line).
void resolveCsgMaterials(CsgTreeDesc* tree, const SceneDescription& scene);

}  // namespace glint
