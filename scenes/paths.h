// glint — where the files a scene names are: relative to the JSON file that names them, or in
// the shared asset folder.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "scenes/errors.h"

namespace glint {

// The shared asset folder (the Stanford meshes, Khronos samples): $GLINT_ASSETS when set and
// not empty, else the folder CMake was configured with (GLINT_ASSETS, by default
// ../shared/assets beside the source tree).
std::string sharedAssetsFolder();

// The file a scene names as `written`, in the JSON file `jsonFile`:
// - "$GLINT_ASSETS/rest" (or "${GLINT_ASSETS}/rest"): rest inside sharedAssetsFolder(), so
//   scenes that need the Stanford meshes name them without knowing where a machine keeps them;
// - an absolute path as it is;
// - anything else relative to the folder of `jsonFile`.
std::filesystem::path resolveScenePath(const std::string& written, const std::string& jsonFile);

// resolveScenePath, and the file must exist: otherwise a SceneError at `at`, "file not found:
// PATH", which for $GLINT_ASSETS paths also says how to point glint at the assets.
std::filesystem::path existingScenePath(const std::string& written, const std::string& jsonFile,
                                        const SourceLocation& at);

// Collects, while alive, every file resolveScenePath gives on this thread: the files a scene
// names (glTF files, meshes, images, environment maps, .csg trees), which `glint preview`
// watches for edits. Nests: an inner recorder's files reach the outer one too.
class NamedFileRecorder {
 public:
  NamedFileRecorder();
  ~NamedFileRecorder();
  NamedFileRecorder(const NamedFileRecorder&) = delete;
  NamedFileRecorder& operator=(const NamedFileRecorder&) = delete;
  const std::vector<std::string>& files() const { return files_; }

 private:
  friend std::filesystem::path resolveScenePath(const std::string&, const std::string&);
  std::vector<std::string> files_;
  NamedFileRecorder* outer_;
};

}  // namespace glint
