// glint — loadScene: picks the loader by extension and applies the sidecar.
#include "scenes/load.h"

#include <cctype>
#include <filesystem>

#include "scenes/gltf_loader.h"
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

}  // namespace

SceneDescription loadScene(const std::string& path, const std::optional<std::string>& sidecar) {
  requireFile(path, "scene file");
  SceneDescription scene;
  scene.file = path;
  std::string ext = lowerExtension(path);
  if (ext == ".gltf" || ext == ".glb" || isMeshFile(path)) {
    // A bare mesh takes a sidecar like a glTF file does: it has no camera, lights or
    // materials of its own, and the sidecar is where they come from.
    if (isMeshFile(path))
      loadMeshFile(path, &scene);
    else
      loadGltf(path, &scene);
    if (sidecar) {
      requireFile(*sidecar, "sidecar file");
      applySceneJsonFile(*sidecar, SceneJsonKind::Sidecar, &scene);
    } else {
      std::string automatic = defaultSidecarPath(path);
      std::error_code ec;
      if (fs::is_regular_file(automatic, ec))
        applySceneJsonFile(automatic, SceneJsonKind::Sidecar, &scene);
    }
  } else if (ext == ".json") {
    if (sidecar)
      throw SceneError({*sidecar, ""},
                       "a sidecar applies to a .gltf/.glb scene; put its settings in " + path);
    applySceneJsonFile(path, SceneJsonKind::Scene, &scene);
  } else {
    throw SceneError({path, ""}, "unknown scene format '" + ext +
                                     "'; expected a .gltf, .glb, .ply, .obj or glint .json file");
  }
  return scene;
}

}  // namespace glint
