// glint — opening glint's plugin modules: shared modules that keep a heavy library and its
// start-up out of every process that does not need it (image/oiio/plugin.h: OpenImageIO,
// scenes/openvdb/plugin.h: OpenVDB). Each is loaded the first time it is needed and stays
// loaded for the life of the process (objects it made, such as a VDB volume's grids, may hold
// its code).
// Header-only: the OpenImageIO plugin's loader sits below the image room (see install_layout.h).
#pragma once

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <string>
#include <system_error>
#include <vector>

#include "geometry/error.h"
#include "image/install_layout.h"

namespace glint {

// One plugin: its file and where glint looks for it.
struct PluginModule {
  const char* fileName;     // "libglint_oiio.so"
  const char* environment;  // the variable naming another file: "GLINT_OIIO_PLUGIN"
  const char* entryPoint;   // the extern "C" function it exports, returning its plugin object
  const char* buildPath;    // the module in the build tree glint was built in; may be null
  const char* description;  // for the failure's message: "glint's OpenImageIO plugin"
  const char* neededFor;    // the same: "needed for image formats other than OpenEXR"
};

// The places tried, in order: $environment alone when it is set; else beside the running
// executable, in PREFIX/lib/glint (install_layout.h), and in the build tree.
inline std::vector<std::string> pluginCandidates(const PluginModule& m) {
  std::vector<std::string> paths;
  if (const char* env = std::getenv(m.environment); env && *env) {
    paths.emplace_back(env);
    return paths;  // an explicit choice: nothing else
  }
  const std::filesystem::path exe = executableFolder();
  if (!exe.empty()) {
    paths.push_back((exe / m.fileName).string());
    paths.push_back(
        installedPath(exe, std::filesystem::path(kInstalledPluginFolder) / m.fileName).string());
  }
  if (m.buildPath) paths.emplace_back(m.buildPath);
  return paths;
}

// Opens the first candidate that loads and exports the entry point, and returns the entry
// point's address. Throws FailureError (exit code 1) naming the places tried.
inline void* openPluginModule(const PluginModule& m) {
  std::string tried;
  for (const std::string& path : pluginCandidates(m)) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
      tried += "\n  " + path + ": no such file";
      continue;
    }
    // RTLD_LOCAL: the library's own dependencies stay out of the global symbol scope.
    // RTLD_LAZY: the module's calls bind on first use.
    void* handle = ::dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL);
    if (!handle) {
      const char* why = ::dlerror();
      tried += "\n  " + path + ": " + (why ? why : "cannot be loaded");
      continue;
    }
    if (void* entry = ::dlsym(handle, m.entryPoint)) return entry;
    tried += "\n  " + path + ": has no " + m.entryPoint;
    ::dlclose(handle);
  }
  throw FailureError("cannot load " + std::string(m.description) + " (" + m.fileName + "), " +
                     m.neededFor + "; tried:" + tried);
}

// The plugin object of `m`'s module (its entry point: `const Plugin* entry()`), loaded on the
// first call; thread-safe. Not a function-local static: a failed load throws, and the next
// call tries again.
template <class Plugin>
const Plugin& loadPlugin(const PluginModule& m) {
  static std::mutex mutex;
  static const Plugin* loaded = nullptr;
  std::lock_guard lock(mutex);
  if (!loaded) {
    using Entry = const Plugin* (*)();
    loaded = reinterpret_cast<Entry>(openPluginModule(m))();
  }
  return *loaded;
}

}  // namespace glint
