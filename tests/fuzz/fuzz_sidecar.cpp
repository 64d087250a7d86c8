// glint fuzzing — the glint JSON schema (scenes/sidecar.h) in memory, the way SceneLoader
// applies it: a document with a "gltf" list is a .json scene (its glTF files are loaded);
// anything else is a sidecar over tests/data/sidecar/triangle.gltf, whose camera, materials
// and nodes it can override. Relative file names resolve against tests/data/sidecar.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_support.h"
#include "scenes/gltf_loader.h"
#include "scenes/json_util.h"
#include "scenes/sidecar.h"

namespace {

const char* const kFile = GLINT_TEST_DATA "/sidecar/fuzz.json";

const glint::SceneDescription& baseScene() {
  static const glint::SceneDescription base = [] {
    glint::SceneDescription scene;
    glint::loadGltf(GLINT_TEST_DATA "/sidecar/triangle.gltf", &scene);
    return scene;
  }();
  return base;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string_view text(reinterpret_cast<const char*>(data), size);
  const glint::SceneDescription& base = baseScene();
  glint::fuzz::expectCleanResult([&] {
    nlohmann::json doc = glint::parseJson(text, kFile);
    bool isScene = doc.is_object() && doc.contains("gltf");
    glint::SceneDescription scene = isScene ? glint::SceneDescription() : base;
    glint::applySceneJson(
        doc, kFile, isScene ? glint::SceneJsonKind::Scene : glint::SceneJsonKind::Sidecar, &scene);
  });
  return 0;
}
