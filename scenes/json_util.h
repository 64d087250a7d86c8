// glint — JSON reading helpers shared by the glTF and sidecar loaders: syntax errors with
// line:column, and typed field access that reports the JSON pointer of a bad value.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "scenes/errors.h"

namespace glint {

// Parses `text` (the contents of `file`). A syntax error becomes a SceneError whose location
// is "file:LINE:COLUMN" and whose message names what was expected.
nlohmann::json parseJson(std::string_view text, const std::string& file);
// The same for glint's own scene and sidecar files, which must also not say a key twice in one
// object: nlohmann keeps the last value and the other would be ignored without a word, so it
// is a SceneError at the object's pointer ("scene.json: /objects/1: key 'transform' given
// twice"). glTF files go through parseJson: other tools read them, and glint reads what they do.
nlohmann::json parseSceneJson(std::string_view text, const std::string& file);

// Reads a whole file; a missing or unreadable file is a SceneError naming it.
std::string readTextFile(const std::string& path);

// The name of a JSON value's type as users know it ("number", "string", "object", ...).
std::string jsonTypeName(const nlohmann::json& value);

}  // namespace glint
