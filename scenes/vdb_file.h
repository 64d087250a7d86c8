// glint — OpenVDB files (.vdb): reading the grids a sidecar medium names into a VdbVolume
// (materials/vdb_volume.h: NanoVDB grids, their bounds and majorant grid), and listing a
// file's grids for `glint info`. The reading is done by the OpenVDB plugin
// (scenes/openvdb/plugin.h), loaded the first time a scene names a .vdb file.
//
// What is accepted: float grids (density, temperature, flame) and a vec3s colour grid, each
// with a linear index-to-world transform (OpenVDB's affine maps; a frustum transform is
// refused), every active value (component) and the background finite and >= 0, the density grid
// with a background of 0 (a medium is bounded by its active voxels) and at least one active voxel.
// Anything else is a SceneError naming the sidecar's key and the file.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "geometry/math.h"
#include "materials/vdb_volume.h"
#include "scenes/errors.h"

namespace glint {

// One grid of a file, as `glint info` lists it.
struct VdbGridInfo {
  std::string name;
  std::string type;  // OpenVDB's value type name: "float", "vec3s", ...
  Vec3f voxelSize;
  uint64_t activeVoxels = 0;
  Bounds3f worldBounds;      // of the active voxels, in the file's world space (empty: none)
  uint64_t memoryBytes = 0;  // OpenVDB's in-memory size of the grid
};

// The grids of the .vdb file at `path`, in file order. Throws SceneError({path, ""}, reason).
std::vector<VdbGridInfo> listVdbGrids(const std::string& path);

// A grid the sidecar names, with where it names it.
struct VdbGridRequest {
  std::string name;
  SourceLocation where;
};

// How the temperature grid's values become kelvin, voxel by voxel: scale x value + offset,
// and 0 K (no emission) at or below the cutoff. Mapped before the grid is interpolated, so a
// flame's edge fades to 0 K across one voxel, as in Blender's rendering of its fluid domains
// (whose temperature is their flame grid mapped so).
struct VdbTemperatureMap {
  float scale = 1, offset = 0, cutoff = 0;
};

struct VdbRequest {
  SourceLocation where;  // where the sidecar names the file
  VdbGridRequest density;
  std::optional<VdbGridRequest> temperature, flame;
  VdbTemperatureMap kelvin;  // for the temperature grid
  // The colour grid: one vec3s grid, or three float grids (red, green, blue: Blender's fluid
  // caches), multiplying sigma_s per point.
  std::vector<VdbGridRequest> color;
  bool colorDensityWeighted = false;  // VdbVolume::colorDensityWeighted
  // Cells of the majorant grid along the box's longest axis (the others in proportion);
  // 1: no grid, a single majorant.
  int majorantCells = 16;
};

// Reads the requested grids of the .vdb file at `path`. Errors are SceneErrors at the
// request's locations, each message starting with the file's name:
// "scene.json: /media/0/density/grid: cloud.vdb has no grid 'dens' (its grids: density
// (float), temperature (float))".
std::shared_ptr<VdbVolume> readVdbFile(const std::string& path, const VdbRequest& request);

}  // namespace glint
