// glint — colour management through OpenColorIO.
#include "image/color.h"

#include <OpenColorIO/OpenColorIO.h>
#include <fmt/format.h>

#include <cassert>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <set>
#include <string>

#include "image/install_layout.h"

namespace OCIO = OCIO_NAMESPACE;

namespace glint {

// ---- config loading --------------------------------------------------------------------------

namespace {

struct LoadedConfig {
  OCIO::ConstConfigRcPtr config;
  std::string path;
};

std::mutex configMutex;

// Configs are immutable once loaded, so each path is read once per process. $OCIO is looked up
// on every call: a test (or a long-lived tool) may change it.
OCIO::ConstConfigRcPtr loadCached(const std::string& path) {
  static std::map<std::string, OCIO::ConstConfigRcPtr> cache;
  if (auto it = cache.find(path); it != cache.end()) return it->second;
  OCIO::ConstConfigRcPtr config = OCIO::Config::CreateFromFile(path.c_str());
  config->validate();
  cache.emplace(path, config);
  return config;
}

// The config used without $OCIO: an installed glint's (PREFIX/share/glint/ocio, see
// image/install_layout.h), else the source tree's, whose path the build compiled in.
std::string defaultConfigPath() {
  static const std::string path = [] {
    const std::filesystem::path installed = installedFile(executableFolder(), kInstalledOcioConfig);
    return installed.empty() ? std::string(GLINT_DEFAULT_OCIO_CONFIG) : installed.string();
  }();
  return path;
}

LoadedConfig currentConfig() {
  std::lock_guard<std::mutex> lock(configMutex);
  std::string envError;
  const char* env = std::getenv("OCIO");
  if (env && *env) {
    try {
      return {loadCached(env), env};
    } catch (const OCIO::Exception& e) {
      envError = e.what();
      static std::set<std::string> warned;
      if (warned.insert(env).second)
        fmt::print(stderr, "glint: warning: cannot load $OCIO config '{}' ({}); using '{}'\n", env,
                   envError, defaultConfigPath());
    }
  }
  try {
    return {loadCached(defaultConfigPath()), defaultConfigPath()};
  } catch (const OCIO::Exception& e) {
    std::string message =
        fmt::format("cannot load the OpenColorIO config '{}': {}", defaultConfigPath(), e.what());
    if (!envError.empty()) message += fmt::format(" (nor $OCIO '{}': {})", env, envError);
    throw ColorError(message);
  }
}

std::string joinQuoted(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "'" : ", '") + n + "'";
  return out.empty() ? "none" : out;
}

std::vector<std::string> displaysOf(const OCIO::Config& config) {
  std::vector<std::string> names;
  for (int i = 0; i < config.getNumDisplays(); ++i) names.emplace_back(config.getDisplay(i));
  return names;
}

std::vector<std::string> viewsOf(const OCIO::Config& config, const std::string& display) {
  std::vector<std::string> names;
  for (int i = 0; i < config.getNumViews(display.c_str()); ++i)
    names.emplace_back(config.getView(display.c_str(), i));
  return names;
}

bool contains(const std::vector<std::string>& names, const std::string& name) {
  for (const std::string& n : names)
    if (n == name) return true;
  return false;
}

std::pair<std::string, std::string> resolve(const LoadedConfig& loaded, const std::string& display,
                                            const std::string& view) {
  const OCIO::Config& config = *loaded.config;
  std::string d = display.empty() ? config.getDefaultDisplay() : display;
  std::vector<std::string> displays = displaysOf(config);
  if (!contains(displays, d))
    throw ColorError(fmt::format("unknown OCIO display '{}' in config '{}'; available: {}", d,
                                 loaded.path, joinQuoted(displays)));
  std::string v = view.empty() ? config.getDefaultView(d.c_str()) : view;
  std::vector<std::string> views = viewsOf(config, d);
  if (!contains(views, v))
    throw ColorError(
        fmt::format("unknown OCIO view '{}' for display '{}' in config '{}'; "
                    "available: {}",
                    v, d, loaded.path, joinQuoted(views)));
  return {d, v};
}

}  // namespace

// ---- public API ------------------------------------------------------------------------------

std::string defaultOcioConfigPath() { return defaultConfigPath(); }

ColorConfigInfo colorConfigInfo() {
  LoadedConfig loaded = currentConfig();
  const OCIO::Config& config = *loaded.config;
  ColorConfigInfo info;
  info.path = loaded.path;
  info.defaultDisplay = config.getDefaultDisplay();
  for (const std::string& d : displaysOf(config))
    info.displays.push_back({d, viewsOf(config, d), config.getDefaultView(d.c_str())});
  return info;
}

std::pair<std::string, std::string> resolveDisplayView(const std::string& display,
                                                       const std::string& view) {
  return resolve(currentConfig(), display, view);
}

void applyDisplayView(std::span<float> rgb, const std::string& display, const std::string& view) {
  LoadedConfig loaded = currentConfig();
  auto [d, v] = resolve(loaded, display, view);
  assert(rgb.size() % 3 == 0);
  if (rgb.empty()) return;
  try {
    OCIO::ConstProcessorRcPtr processor = loaded.config->getProcessor(
        OCIO::ROLE_SCENE_LINEAR, d.c_str(), v.c_str(), OCIO::TRANSFORM_DIR_FORWARD);
    OCIO::ConstCPUProcessorRcPtr cpu = processor->getDefaultCPUProcessor();
    // One row of N pixels: the transform is per pixel, so the shape does not matter.
    OCIO::PackedImageDesc image(rgb.data(), long(rgb.size() / 3), 1, 3);
    cpu->apply(image);
  } catch (const OCIO::Exception& e) {
    throw ColorError(fmt::format("OCIO display '{}' / view '{}' (config '{}'): {}", d, v,
                                 loaded.path, e.what()));
  }
}

}  // namespace glint
