// glint — where the files a scene names are.
#include "scenes/paths.h"

#include <cstdlib>
#include <string_view>
#include <system_error>

namespace fs = std::filesystem;

namespace glint {

namespace {

// The part after a "$GLINT_ASSETS/" or "${GLINT_ASSETS}/" prefix; false without one.
bool assetsRelative(const std::string& written, std::string* rest) {
  for (std::string_view prefix : {"$GLINT_ASSETS/", "${GLINT_ASSETS}/"}) {
    if (written.compare(0, prefix.size(), prefix) == 0) {
      *rest = written.substr(prefix.size());
      return true;
    }
  }
  return false;
}

thread_local NamedFileRecorder* activeRecorder = nullptr;

}  // namespace

NamedFileRecorder::NamedFileRecorder() : outer_(activeRecorder) { activeRecorder = this; }
NamedFileRecorder::~NamedFileRecorder() { activeRecorder = outer_; }

std::string sharedAssetsFolder() {
  if (const char* env = std::getenv("GLINT_ASSETS"); env && *env) return env;
  return GLINT_DEFAULT_ASSETS;
}

fs::path resolveScenePath(const std::string& written, const std::string& jsonFile) {
  std::string rest;
  fs::path path;
  if (assetsRelative(written, &rest))
    path = (fs::path(sharedAssetsFolder()) / rest).lexically_normal();
  else
    path = fs::path(written).is_absolute() ? fs::path(written)
                                           : fs::path(jsonFile).parent_path() / written;
  for (NamedFileRecorder* r = activeRecorder; r; r = r->outer_) r->files_.push_back(path.string());
  return path;
}

fs::path existingScenePath(const std::string& written, const std::string& jsonFile,
                           const SourceLocation& at) {
  const fs::path path = resolveScenePath(written, jsonFile);
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) return path;
  std::string rest;
  if (assetsRelative(written, &rest))
    throw SceneError(at, "file not found: " + path.string() +
                             " (this scene needs the shared assets: set GLINT_ASSETS to the "
                             "folder that holds them; benchmarks/get_assets.sh fetches them)");
  throw SceneError(at, "file not found: " + path.string());
}

}  // namespace glint
