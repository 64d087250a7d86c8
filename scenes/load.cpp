// glint — loadScene: picks the loader by extension and applies the sidecar.
#include "scenes/load.h"

#include <cctype>
#include <filesystem>

#include "scenes/gltf_loader.h"
#include "scenes/json_util.h"
#include "scenes/mesh_import.h"
#include "scenes/sidecar.h"

namespace glint {

namespace fs = std::filesystem;

namespace {

std::string lowerExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

void requireFile(const std::string& path, const std::string& what) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw SceneError({path, ""}, what + " not found");
  if (!fs::is_regular_file(path, ec)) throw SceneError({path, ""}, what + " is not a file");
}

bool isModelFile(const std::string& path) {
  const std::string ext = lowerExtension(path);
  return ext == ".gltf" || ext == ".glb" || isMeshFile(path);
}

}  // namespace

void SceneLoader::loadBase(const std::string& path) {
  // A bare mesh takes a sidecar like a glTF file does: it has no camera, lights or materials of
  // its own, and the sidecar is where they come from.
  if (isMeshFile(path))
    loadMeshFile(path, &base_);
  else
    loadGltf(path, &base_);
}

SceneLoader::SceneLoader(const std::string& path, const std::optional<std::string>& sidecar) {
  requireFile(path, "scene file");
  base_.file = path;
  std::string ext = lowerExtension(path);
  if (isModelFile(path)) {
    loadBase(path);
    if (sidecar) {
      requireFile(*sidecar, "sidecar file");
      jsonFile_ = *sidecar;
    } else {
      std::string automatic = defaultSidecarPath(path);
      std::error_code ec;
      if (fs::is_regular_file(automatic, ec)) jsonFile_ = automatic;
    }
    kind_ = SceneJsonKind::Sidecar;
    if (!jsonFile_.empty()) json_ = parseSceneJson(readTextFile(jsonFile_), jsonFile_);
  } else if (ext == ".json") {
    if (sidecar)
      throw SceneError({*sidecar, ""},
                       "a sidecar applies to a .gltf/.glb scene; put its settings in " + path);
    jsonFile_ = path;
    kind_ = SceneJsonKind::Scene;
    json_ = parseSceneJson(readTextFile(path), path);
    loadSceneGltfList(json_, path, &base_);
  } else {
    throw SceneError({path, ""}, "unknown scene format '" + ext +
                                     "'; expected a .gltf, .glb, .ply, .obj or glint .json file");
  }
  // The first frame is checked here, so that a bad file fails at construction.
  at();
}

SceneLoader::SceneLoader(const JsonText& json, const std::optional<std::string>& scene) {
  jsonFile_ = json.file;
  if (scene) {
    requireFile(*scene, "scene file");
    if (!isModelFile(*scene))
      throw SceneError({*scene, ""}, "a sidecar applies to a .gltf, .glb, .ply or .obj scene");
    base_.file = *scene;
    loadBase(*scene);
    kind_ = SceneJsonKind::Sidecar;
    json_ = parseSceneJson(json.text, json.file);
  } else {
    base_.file = json.file;
    kind_ = SceneJsonKind::Scene;
    json_ = parseSceneJson(json.text, json.file);
    loadSceneGltfList(json_, json.file, &base_);
  }
  at();
}

SceneDescription SceneLoader::at(std::optional<double> time) const {
  SceneDescription scene = base_;
  if (jsonFile_.empty()) {
    if (time) scene.render.time = *time;
    evaluatePlacements(&scene, scene.render.time);
    return scene;
  }
  SceneJsonOptions options;
  options.time = time;
  options.loadGltf = false;
  applySceneJson(json_, jsonFile_, kind_, &scene, options);
  return scene;
}

SceneDescription loadScene(const std::string& path, const std::optional<std::string>& sidecar,
                           std::optional<double> time) {
  return SceneLoader(path, sidecar).at(time);
}

}  // namespace glint
