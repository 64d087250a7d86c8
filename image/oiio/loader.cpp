// glint — finding and loading the OpenImageIO plugin (see plugin.h).
#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include "image/install_layout.h"
#include "image/oiio/plugin.h"

namespace glint::oiio {

namespace {

constexpr const char* kModuleName = "libglint_oiio.so";

// The places plugin() tries, in order.
std::vector<std::string> candidates() {
  std::vector<std::string> paths;
  if (const char* env = std::getenv("GLINT_OIIO_PLUGIN"); env && *env) {
    paths.emplace_back(env);
    return paths;  // an explicit choice: nothing else
  }
  const std::filesystem::path exe = executableFolder();
  if (!exe.empty()) {
    paths.push_back((exe / kModuleName).string());
    paths.push_back(installedPath(exe, kInstalledPlugin).string());
  }
#ifdef GLINT_OIIO_PLUGIN_BUILD_PATH
  paths.emplace_back(GLINT_OIIO_PLUGIN_BUILD_PATH);
#endif
  return paths;
}

const Plugin* load() {
  std::string tried;
  for (const std::string& path : candidates()) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
      tried += "\n  " + path + ": no such file";
      continue;
    }
    // RTLD_LOCAL: OpenImageIO's libraries stay out of the global symbol scope. RTLD_LAZY: the
    // module's own calls bind on first use (most of its libraries bind everything at load).
    void* handle = ::dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL);
    if (!handle) {
      const char* why = ::dlerror();
      tried += "\n  " + path + ": " + (why ? why : "cannot be loaded");
      continue;
    }
    auto entry = reinterpret_cast<EntryPoint>(::dlsym(handle, kEntryPoint));
    if (!entry) {
      tried += "\n  " + path + ": has no " + kEntryPoint;
      ::dlclose(handle);
      continue;
    }
    return entry();  // the module stays loaded for the life of the process
  }
  throw FailureError("cannot load glint's OpenImageIO plugin (" + std::string(kModuleName) +
                     "), needed for image formats other than OpenEXR and for image textures; "
                     "tried:" +
                     tried);
}

}  // namespace

const Plugin& plugin() {
  // Not a function-local static: a failed load throws, and the next call tries again.
  static std::mutex mutex;
  static const Plugin* loaded = nullptr;
  std::lock_guard lock(mutex);
  if (!loaded) loaded = load();
  return *loaded;
}

}  // namespace glint::oiio
