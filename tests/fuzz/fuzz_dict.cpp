// glint fuzzing — the Python module's dict loader (python/scene_handle.h): what glint.load(dict),
// Scene.update(patch) and Scene.render(**options) do with a JSON structure, in memory.
//
// The input is a JSON document. An array [load, patch, options] is the three calls' arguments
// (a missing or null one is skipped); anything else is the load dict alone. A load dict with a
// "gltf" list is a scene dict; anything else a sidecar dict over tests/data/sidecar/triangle.gltf.
// Relative file names resolve against tests/data/sidecar, as fuzz_sidecar's do.
//
// With a patch, the scene is rendered before and after it, and the image after it must equal
// the one a second scene, loaded and patched before its first render, gives to the last bit:
// what a change refreshes in a kept render scene (camera, lights, materials) is what a build of
// the changed scene makes. Renders are 4x4 pixels at 1 spp on one thread, whatever the options
// say, so that an input's time is the loader's and the build's.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "python/scene_handle.h"
#include "scenes/errors.h"
#include "scenes/json_util.h"

namespace {

const char* const kFile = GLINT_TEST_DATA "/sidecar/fuzz.json";
const char* const kTriangle = GLINT_TEST_DATA "/sidecar/triangle.gltf";

// The module's answer to bad input is glint.InputError, carrying the file: a SceneError that
// names one, or an InputError whose message starts with it (namingFile). Anything else
// escapes (std::terminate) or aborts here: a finding.
template <class Work>
void expectInputErrorOrNothing(Work&& work) {
  try {
    work();
  } catch (const glint::SceneError& e) {
    if (e.where().file.empty()) {
      std::fprintf(stderr, "SceneError without a file: %s\n", e.what());
      std::abort();
    }
  } catch (const glint::InputError& e) {
    if (std::strstr(e.what(), "fuzz.json") == nullptr && std::strstr(e.what(), "()") == nullptr) {
      std::fprintf(stderr, "InputError naming neither the dict nor the call: %s\n", e.what());
      std::abort();
    }
  }
}

// The options with the render kept tiny (the other keys as given).
std::string tinyRender(nlohmann::json options) {
  if (!options.is_object()) options = nlohmann::json::object();
  for (const char* key : {"time_limit", "noise_target", "adaptive", "crop"}) options.erase(key);
  options["width"] = 4;
  options["height"] = 4;
  options["spp"] = 1;
  options["threads"] = 1;
  return options.dump();
}

std::unique_ptr<glint::python::SceneHandle> load(const nlohmann::json& dict) {
  const bool isScene = dict.is_object() && dict.contains("gltf");
  return std::make_unique<glint::python::SceneHandle>(
      glint::SceneLoader::JsonText{dict.dump(), kFile},
      isScene ? std::nullopt : std::optional<std::string>(kTriangle), std::nullopt);
}

void run(std::string_view text) {
  const nlohmann::json doc = glint::parseJson(text, kFile);
  const bool calls = doc.is_array() && !doc.empty() && doc.size() <= 3;
  const nlohmann::json dict = calls ? doc[0] : doc;
  const nlohmann::json patch = calls && doc.size() > 1 ? doc[1] : nlohmann::json();
  const std::string options = tinyRender(calls && doc.size() > 2 ? doc[2] : nlohmann::json());
  auto scene = load(dict);
  if (patch.is_null()) {
    scene->render(options, nullptr);
    return;
  }
  scene->render(options, nullptr);  // the render scene the patch then changes
  scene->update(patch.dump());
  const auto changed = scene->render(options, nullptr);
  auto fresh = load(dict);
  fresh->update(patch.dump());
  const auto expected = fresh->render(options, nullptr);
  const auto& a = changed->film->color;
  const auto& b = expected->film->color;
  // Bit for bit (a NaN pixel equals the same NaN).
  if (a.size() != b.size() || std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) != 0) {
    std::fprintf(stderr,
                 "the patched scene renders unlike a fresh load of the patch (%d builds, %d "
                 "refreshes)\n",
                 scene->builds(), scene->refreshes());
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  expectInputErrorOrNothing([&] { run(text); });
  return 0;
}
