// glint — reading and writing Mitsuba's .vol grids.
#include "scenes/vol_file.h"

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "image/io.h"
#include "scenes/errors.h"

namespace glint {

namespace {

constexpr uint64_t kHeaderBytes = 48;  // "VOL", version, encoding, 3 sizes, channels, box

template <class T>
bool readRaw(std::ifstream& in, T* out) {
  return bool(in.read(reinterpret_cast<char*>(out), sizeof(T)));
}

}  // namespace

VolumeGrid readVolFile(const std::string& path) {
  const SourceLocation where{path, ""};
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(where, std::string("cannot open: ") + std::strerror(errno));
  char magic[3];
  uint8_t version = 0;
  if (!in.read(magic, 3) || std::memcmp(magic, "VOL", 3) != 0)
    throw SceneError(where, "not a .vol grid (no 'VOL' header)");
  if (!readRaw(in, &version) || version != 3)
    throw SceneError(
        where, "header: unsupported .vol version " + std::to_string(version) + " (expected 3)");
  int32_t encoding = 0, res[3] = {0, 0, 0}, channels = 0;
  if (!readRaw(in, &encoding) || encoding != 1)
    throw SceneError(where, "header: unsupported encoding " + std::to_string(encoding) +
                                " (expected 1, float32)");
  for (int32_t& r : res)
    if (!readRaw(in, &r) || r < 1 || r > 4096)
      throw SceneError(where, "header: bad resolution (each axis must be in 1..4096)");
  if (!readRaw(in, &channels) || channels != 1)
    throw SceneError(where,
                     "header: " + std::to_string(channels) + " channels (a density grid has 1)");
  float box[6];
  for (float& b : box)
    if (!readRaw(in, &b)) throw SceneError(where, "truncated header");
  // The values the header promises must be in the file before they are allocated: a damaged
  // header could otherwise ask for 4096^3 floats.
  const uint64_t count = uint64_t(res[0]) * uint64_t(res[1]) * uint64_t(res[2]);
  std::error_code ec;
  const uint64_t size = std::filesystem::file_size(path, ec);
  if (ec || size < kHeaderBytes + count * sizeof(float))
    throw SceneError(where,
                     "truncated data (the header's " + std::to_string(res[0]) + "x" +
                         std::to_string(res[1]) + "x" + std::to_string(res[2]) + " grid needs " +
                         std::to_string(count * sizeof(float)) + " bytes of values, the file has " +
                         std::to_string(ec || size < kHeaderBytes ? 0 : size - kHeaderBytes) + ")");
  VolumeGrid grid;
  grid.nx = res[0], grid.ny = res[1], grid.nz = res[2];
  grid.bounds = {{box[0], box[1], box[2]}, {box[3], box[4], box[5]}};
  grid.values.resize(count);
  if (!in.read(reinterpret_cast<char*>(grid.values.data()),
               std::streamsize(grid.values.size() * sizeof(float))))
    throw SceneError(where, "truncated data (expected " + std::to_string(count) + " values)");
  for (size_t i = 0; i < grid.values.size(); ++i)
    if (!std::isfinite(grid.values[i]) || grid.values[i] < 0)
      throw SceneError(where, "value " + std::to_string(i) + ": densities must be finite and >= 0");
  return grid;
}

void writeVolFile(const std::string& path, const VolumeGrid& grid) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw OutputError("cannot write '" + path + "': " + std::strerror(errno));
  const uint8_t version = 3;
  const int32_t header[5] = {1, grid.nx, grid.ny, grid.nz, 1};
  const float box[6] = {grid.bounds.lower.x, grid.bounds.lower.y, grid.bounds.lower.z,
                        grid.bounds.upper.x, grid.bounds.upper.y, grid.bounds.upper.z};
  out.write("VOL", 3);
  out.write(reinterpret_cast<const char*>(&version), 1);
  out.write(reinterpret_cast<const char*>(header), sizeof(header));
  out.write(reinterpret_cast<const char*>(box), sizeof(box));
  out.write(reinterpret_cast<const char*>(grid.values.data()),
            std::streamsize(grid.values.size() * sizeof(float)));
  out.close();
  if (!out) throw OutputError("cannot write '" + path + "': the write failed");
}

}  // namespace glint
