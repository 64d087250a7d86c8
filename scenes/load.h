// glint — the scene loading entry point: a glTF file with its sidecar, or a glint .json scene.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "scenes/description.h"
#include "scenes/sidecar.h"

namespace glint {

// Loads a scene once and gives its description at any time, for sequences: the glTF files
// (and a bare mesh) are read and decoded once, in the constructor; the sidecar (or the glint
// .json scene's own keys), parsed once, is applied again for each time, so its keyframed
// values are evaluated at that time. Every item with a transformNode holds its placement at
// that time. Throws SceneError.
class SceneLoader {
 public:
  // SCENE: a .gltf/.glb or a .ply/.obj mesh (with `sidecar`, or NAME.glint.json next to it
  // when that exists) or a glint .json scene that may reference glTF files.
  explicit SceneLoader(const std::string& path,
                       const std::optional<std::string>& sidecar = std::nullopt);

  // The same with the JSON given as text instead of a file (the Python module's dicts):
  // `json.file` names it in messages, and relative paths in it resolve against its folder as
  // they would for a file there. With `scene`, the JSON is the sidecar of that .gltf/.glb or
  // .ply/.obj file; without, it is a glint .json scene.
  struct JsonText {
    std::string text;
    std::string file;
  };
  SceneLoader(const JsonText& json, const std::optional<std::string>& scene);

  // The scene at `time` seconds; unset: the file's render.time (0 when it gives none).
  // render.time of the result is the time used.
  SceneDescription at(std::optional<double> time = std::nullopt) const;

  // The sidecar that applies (given or found next to the scene), or the .json scene itself;
  // empty when there is none.
  const std::string& jsonFile() const { return jsonFile_; }

 private:
  // Reads the .gltf/.glb or mesh at `path` into base_.
  void loadBase(const std::string& path);

  SceneDescription base_;  // what the glTF files / mesh hold
  std::string jsonFile_;   // "" = no sidecar
  nlohmann::json json_;    // its parsed contents
  SceneJsonKind kind_ = SceneJsonKind::Sidecar;
};

// Loads SCENE at `time` (unset: the file's render.time, else 0): SceneLoader(path,
// sidecar).at(time). Throws SceneError.
SceneDescription loadScene(const std::string& path,
                           const std::optional<std::string>& sidecar = std::nullopt,
                           std::optional<double> time = std::nullopt);

}  // namespace glint
