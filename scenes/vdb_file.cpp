// glint — OpenVDB files, through the OpenVDB plugin (scenes/openvdb/plugin.h).
#include "scenes/vdb_file.h"

#include "image/plugin_module.h"
#include "scenes/openvdb/plugin.h"

namespace glint {

namespace {

const openvdb_plugin::Plugin& plugin() {
  static constexpr PluginModule kModule{"libglint_openvdb.so",           "GLINT_OPENVDB_PLUGIN",
                                        openvdb_plugin::kEntryPoint,
#ifdef GLINT_OPENVDB_PLUGIN_BUILD_PATH
                                        GLINT_OPENVDB_PLUGIN_BUILD_PATH,
#else
      nullptr,
#endif
                                        "glint's OpenVDB plugin",        "needed for .vdb media"};
  return loadPlugin<openvdb_plugin::Plugin>(kModule);
}

template <class T>
T orThrow(T result, openvdb_plugin::Refusal& refusal) {
  if (!refusal.message.empty()) throw SceneError(refusal.where, refusal.message);
  return result;
}

}  // namespace

std::vector<VdbGridInfo> listVdbGrids(const std::string& path) {
  openvdb_plugin::Refusal refusal;
  return orThrow(plugin().listGrids(path, &refusal), refusal);
}

std::shared_ptr<VdbVolume> readVdbFile(const std::string& path, const VdbRequest& request) {
  openvdb_plugin::Refusal refusal;
  return orThrow(plugin().read(path, request, &refusal), refusal);
}

}  // namespace glint
