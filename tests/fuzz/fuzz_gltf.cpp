// glint fuzzing — the glTF loader (scenes/gltf_loader.h) on a .gltf or .glb file in memory: the
// GLB magic selects the binary container. Relative URIs resolve against tests/data/gltf, so
// mutated inputs can still reach the real no_scenes.bin there.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "scenes/gltf_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string bytes(reinterpret_cast<const char*>(data), size);
  glint::fuzz::expectCleanResult([&] {
    glint::SceneDescription scene;
    glint::loadGltfFromMemory(bytes, GLINT_TEST_DATA "/gltf/fuzz.gltf", &scene);
  });
  return 0;
}
