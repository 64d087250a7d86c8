// glint — the OpenVDB plugin: every use glint makes of OpenVDB (reading .vdb files into
// NanoVDB grids, listing their grids), in one shared module (libglint_openvdb.so) that glint
// loads the first time a scene names a .vdb file (image/plugin_module.h).
//
// Why a plugin: libopenvdb and the ten libraries it pulls in (Boost.Iostreams, blosc,
// log4cplus, ...) cost every glint process about 35 ms of dynamic-loader symbol lookups and
// 29 MB of resident memory at start-up, VDB scene or not (`glint --version`: 0.05 s against
// 0.01 s). The module also keeps OpenVDB's headers out of glint's other objects.
//
// As for the OpenImageIO plugin, both sides are built together from this tree, so the
// interface is plain C++; what the module makes outlives no unloading (it stays loaded).
// A refusal comes back as data, and glint's side throws the SceneError (scenes/vdb_file.h).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "scenes/errors.h"
#include "scenes/vdb_file.h"

namespace glint::openvdb_plugin {

// Why a file or grid was refused, and which sidecar key (or file) it is about.
struct Refusal {
  SourceLocation where;
  std::string message;  // without the location: "cloud.vdb has no grid 'dens' (...)"
};

class Plugin {
 public:
  virtual ~Plugin() = default;
  // listVdbGrids and readVdbFile (scenes/vdb_file.h); on failure they return an empty
  // result and fill *refusal.
  virtual std::vector<VdbGridInfo> listGrids(const std::string& path, Refusal* refusal) const = 0;
  virtual std::shared_ptr<VdbVolume> read(const std::string& path, const VdbRequest& request,
                                          Refusal* refusal) const = 0;
};

// The entry point the module exports: a function returning its one Plugin.
inline constexpr const char* kEntryPoint = "glint_openvdb_plugin";

}  // namespace glint::openvdb_plugin
