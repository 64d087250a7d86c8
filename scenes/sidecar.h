// glint — the glint JSON schema: a sidecar (NAME.glint.json next to NAME.gltf, or --sidecar)
// and a glint .json scene, which may also list glTF files to load. scenes/README.md documents
// the schema.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "scenes/description.h"

namespace glint {

enum class SceneJsonKind {
  Sidecar,  // settings and overrides for an already loaded glTF scene; no "gltf" list
  Scene,    // a whole scene: its "gltf" files are loaded first, then the rest applies
};

struct SceneJsonOptions {
  // The scene time (seconds) at which keyframed values are evaluated, and render.time of the
  // result. Unset: the file's render.time when it gives one, else scene->render.time.
  std::optional<double> time;
  // false: the .json scene's glTF files are already in the scene (SceneLoader loads them once
  // with loadSceneGltfList); the list is still checked.
  bool loadGltf = true;
};

// Reads the JSON file at `path` and applies it to `scene`. Throws SceneError with the file and
// JSON pointer of the first problem (or file:line:col for a syntax error). Afterwards every
// item with a transformNode holds its placement at the scene time (evaluatePlacements).
void applySceneJsonFile(const std::string& path, SceneJsonKind kind, SceneDescription* scene,
                        const SceneJsonOptions& options = {});

// Same for JSON text already in memory; `file` names it in messages, and relative glTF paths
// resolve against its folder.
void applySceneJsonText(std::string_view text, const std::string& file, SceneJsonKind kind,
                        SceneDescription* scene, const SceneJsonOptions& options = {});

// Same for parsed JSON (SceneLoader parses once and applies per frame).
void applySceneJson(const nlohmann::json& doc, const std::string& file, SceneJsonKind kind,
                    SceneDescription* scene, const SceneJsonOptions& options = {});

class JsonReader;

// Reads the keys of a "render" block that `r` holds (the sidecar's schema: spp, seed, camera,
// integrator, ...) into scene->render, a missing key keeping the value there, and checks that
// the camera it names is one of the scene's. Throws SceneError at the key's pointer. Unknown
// keys are the caller's to reject (r.finish()): it may read keys of its own from the same
// object (the Python module's render options).
void readRenderBlock(JsonReader& r, SceneDescription* scene);

// Loads only the glTF files a .json scene lists (no checks of the rest of the file).
void loadSceneGltfList(const nlohmann::json& doc, const std::string& file, SceneDescription* scene);

// The sidecar that belongs to a glTF file: "dir/NAME.gltf" -> "dir/NAME.glint.json".
std::string defaultSidecarPath(const std::string& gltfPath);

}  // namespace glint
