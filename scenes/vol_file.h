// glint — Mitsuba's binary grid volumes (.vol): the density grids a sidecar's media name
// (scenes/sidecar_media.cpp reads them; materials/medium.h's GridDensity holds one in memory).
//
// Format
// ------
// Mitsuba's documented gridvolume format, all little-endian: the bytes "VOL", version byte 3,
// int32 encoding (1 = float32), int32 xres, yres, zres (each 1..4096), int32 channels (1: a
// density grid), 6 float32 bounding box (xmin, ymin, zmin, xmax, ymax, zmax), then
// xres*yres*zres float32 values, x fastest, each finite and >= 0. 48 bytes of header.
#pragma once

#include <string>
#include <vector>

#include "geometry/math.h"

namespace glint {

struct VolumeGrid {
  int nx = 0, ny = 0, nz = 0;
  std::vector<float> values;  // x fastest, then y, then z
  Bounds3f bounds;            // the box the file gives (informational: regions place grids)
};

// Reads a .vol file. Throws SceneError naming the file (no JSON pointer) with the reason:
// "smoke.vol: truncated data (the header's 8x8x8 grid needs 2048 bytes of values, the file has
// 100)". The file's size is checked against the header before anything is allocated.
VolumeGrid readVolFile(const std::string& path);
// Writes a grid in that format (tests, generated grids). Throws OutputError (image/io.h:
// exit code 1) when the file cannot be written.
void writeVolFile(const std::string& path, const VolumeGrid& grid);

}  // namespace glint
