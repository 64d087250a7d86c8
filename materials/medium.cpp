// glint — density fields and the .vol grid format.
#include "materials/medium.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace glint {

// ---------------------------------------------------------------------------------------------
// Density fields
// ---------------------------------------------------------------------------------------------

GridDensity::GridDensity(int nx, int ny, int nz, std::vector<float> values,
                         const Bounds3f& bounds)
    : nx_(nx), ny_(ny), nz_(nz), values_(std::move(values)), bounds_(bounds) {
  if (nx < 1 || ny < 1 || nz < 1 || values_.size() != size_t(nx) * size_t(ny) * size_t(nz))
    throw std::logic_error("GridDensity: the value count does not match the resolution");
  for (float& v : values_) {
    if (!std::isfinite(v) || v < 0) v = 0;
    max_ = std::max(max_, v);
  }
}

float GridDensity::density(Vec3f p) const {
  const Vec3f extent = bounds_.diagonal();
  float c[3];
  int i0[3], i1[3];
  float f[3];
  const int res[3] = {nx_, ny_, nz_};
  for (int a = 0; a < 3; ++a) {
    c[a] = extent[a] > 0 ? (p[a] - bounds_.lower[a]) / extent[a] * float(res[a] - 1) : 0;
    c[a] = std::clamp(c[a], 0.0f, float(res[a] - 1));
    i0[a] = std::min(int(c[a]), res[a] - 1);
    i1[a] = std::min(i0[a] + 1, res[a] - 1);
    f[a] = c[a] - float(i0[a]);
  }
  auto lerp1 = [](float t, float a, float b) { return a + t * (b - a); };
  float x00 = lerp1(f[0], at(i0[0], i0[1], i0[2]), at(i1[0], i0[1], i0[2]));
  float x10 = lerp1(f[0], at(i0[0], i1[1], i0[2]), at(i1[0], i1[1], i0[2]));
  float x01 = lerp1(f[0], at(i0[0], i0[1], i1[2]), at(i1[0], i0[1], i1[2]));
  float x11 = lerp1(f[0], at(i0[0], i1[1], i1[2]), at(i1[0], i1[1], i1[2]));
  return lerp1(f[2], lerp1(f[1], x00, x10), lerp1(f[1], x01, x11));
}

NoiseDensity::NoiseDensity(float scale, int octaves, float threshold, uint64_t seed,
                           Vec3f offset)
    : noise_(seed),
      scale_(scale),
      offset_(offset),
      octaves_(octaves),
      threshold_(threshold),
      amplitudeSum_(octaveAmplitudeSum(octaves, 0.5f)) {}

float NoiseDensity::density(Vec3f p) const {
  const float n = std::clamp(0.5f + 0.5f * noise_.fbm((p - offset_) * scale_, octaves_) / amplitudeSum_,
                             0.0f, 1.0f);
  return std::max(0.0f, n - threshold_) / (1 - threshold_);
}

ExponentialDensity::ExponentialDensity(Vec3f up, float falloff, float h0)
    : up_(normalize(up)), falloff_(falloff), h0_(h0) {}

float ExponentialDensity::density(Vec3f p) const {
  return std::exp(std::min(60.0f, -falloff_ * (dot(p, up_) - h0_)));
}

float ExponentialDensity::maxDensity(const Bounds3f& region) const {
  // The exponent is linear in p, so its maximum over a box is at a corner.
  float best = 0;
  for (int i = 0; i < 8; ++i) {
    Vec3f corner{(i & 1) ? region.upper.x : region.lower.x,
                 (i & 2) ? region.upper.y : region.lower.y,
                 (i & 4) ? region.upper.z : region.lower.z};
    best = std::max(best, density(corner));
  }
  return best;
}

// ---------------------------------------------------------------------------------------------
// .vol files
// ---------------------------------------------------------------------------------------------

namespace {

template <class T>
bool readRaw(std::ifstream& in, T* out) {
  return bool(in.read(reinterpret_cast<char*>(out), sizeof(T)));
}

}  // namespace

VolumeGrid readVolFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + path);
  char magic[3];
  uint8_t version = 0;
  if (!in.read(magic, 3) || std::memcmp(magic, "VOL", 3) != 0)
    throw std::runtime_error(path + ": not a .vol grid (no 'VOL' header)");
  if (!readRaw(in, &version) || version != 3)
    throw std::runtime_error(path + ": unsupported .vol version " + std::to_string(version) +
                             " (expected 3)");
  int32_t encoding = 0, res[3] = {0, 0, 0}, channels = 0;
  if (!readRaw(in, &encoding) || encoding != 1)
    throw std::runtime_error(path + ": unsupported encoding " + std::to_string(encoding) +
                             " (expected 1, float32)");
  for (int32_t& r : res)
    if (!readRaw(in, &r) || r < 1 || r > 4096)
      throw std::runtime_error(path + ": bad resolution (each axis must be in 1..4096)");
  if (!readRaw(in, &channels) || channels != 1)
    throw std::runtime_error(path + ": " + std::to_string(channels) +
                             " channels (a density grid has 1)");
  float box[6];
  for (float& b : box)
    if (!readRaw(in, &b)) throw std::runtime_error(path + ": truncated header");
  VolumeGrid grid;
  grid.nx = res[0], grid.ny = res[1], grid.nz = res[2];
  grid.bounds = {{box[0], box[1], box[2]}, {box[3], box[4], box[5]}};
  grid.values.resize(size_t(res[0]) * size_t(res[1]) * size_t(res[2]));
  if (!in.read(reinterpret_cast<char*>(grid.values.data()),
               std::streamsize(grid.values.size() * sizeof(float))))
    throw std::runtime_error(path + ": truncated data (expected " +
                             std::to_string(grid.values.size()) + " values)");
  for (float v : grid.values)
    if (!std::isfinite(v) || v < 0)
      throw std::runtime_error(path + ": densities must be finite and >= 0");
  return grid;
}

void writeVolFile(const std::string& path, const VolumeGrid& grid) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error("cannot write " + path);
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
  if (!out) throw std::runtime_error("cannot write " + path);
}

}  // namespace glint
