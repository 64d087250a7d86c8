// glint — where an installed glint finds its files. `cmake --install` lays them out under one
// prefix (CMakeLists.txt, "Installing"):
//
//   PREFIX/bin/glint                          the executable
//   PREFIX/lib/glint/libglint_oiio.so         the OpenImageIO plugin (image/oiio/plugin.h)
//   PREFIX/lib/glint/libglint_openvdb.so      the OpenVDB plugin (scenes/openvdb/plugin.h)
//   PREFIX/share/glint/ocio/config.ocio       the default OpenColorIO config (image/color.h)
//
// so each is found from the running executable's own folder; a glint run from its build folder
// falls back to the paths compiled in (the build's plugin, the source tree's config).
// Header-only: both the plugin's loader and the image room use it, and the loader sits below
// the image room.
#pragma once

#include <filesystem>
#include <system_error>

namespace glint {

// The folder of the running executable (/proc/self/exe); empty when it cannot be read.
inline std::filesystem::path executableFolder() {
  std::error_code ec;
  std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path() : exe.parent_path();
}

// Where `cmake --install` puts each file, relative to the prefix.
inline constexpr const char* kInstalledPluginFolder = "lib/glint";
inline constexpr const char* kInstalledOcioConfig = "share/glint/ocio/config.ocio";

// `relative` (e.g. kInstalledOcioConfig) under the prefix an executable in `binFolder` was
// installed to (binFolder/..), whether or not the file is there.
inline std::filesystem::path installedPath(const std::filesystem::path& binFolder,
                                           const std::filesystem::path& relative) {
  return (binFolder / ".." / relative).lexically_normal();
}

// The same, or empty when no such file is there (or binFolder is empty).
inline std::filesystem::path installedFile(const std::filesystem::path& binFolder,
                                           const std::filesystem::path& relative) {
  if (binFolder.empty()) return {};
  const std::filesystem::path p = installedPath(binFolder, relative);
  std::error_code ec;
  return std::filesystem::is_regular_file(p, ec) ? p : std::filesystem::path();
}

}  // namespace glint
