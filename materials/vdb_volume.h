// glint — VDB volumes in memory: the grids of an OpenVDB file that a medium samples (density,
// temperature, flame), each flattened to a NanoVDB grid, and the density and emission fields
// that read them (scenes/vdb_file.h reads the file and builds a VdbVolume).
//
// Why NanoVDB for rendering (as pbrt-v4 and Mitsuba 3 do): a NanoVDB grid is one contiguous,
// read-only buffer whose lookups need no locks, no registered accessors and no allocation, so
// every thread samples it directly; an OpenVDB tree is built for editing. OpenVDB stays in
// scenes/, where the file is read, and materials/ only includes NanoVDB's header-only library.
//
// Spaces: a medium's object space is the file's world space (each grid's own index-to-world
// transform is kept); the sidecar's transform places that space in the scene.
#pragma once

#include <nanovdb/NanoVDB.h>
#include <nanovdb/util/GridHandle.h>
#include <nanovdb/util/HostBuffer.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "materials/majorant_grid.h"
#include "materials/medium.h"

namespace glint {

// One grid, flattened.
struct VdbGrid {
  std::string name;
  nanovdb::GridHandle<nanovdb::HostBuffer> handle;
  // Unique per grid made (moves keep it): the key of the per-thread lookup caches.
  struct Key {
    const void* origin = nullptr;  // the counter that numbered it
    uint64_t count = 0;
    bool operator==(const Key&) const = default;
  };
  Key key = newKey();

  // Trilinear interpolation at the object-space point p of a float grid (voxel values sit at
  // integer index coordinates, OpenVDB's convention); the background outside active voxels.
  float sample(Vec3f p) const;
  // The same for a vec3 grid (the colour grid).
  Rgb sampleVec3(Vec3f p) const;
  size_t bytes() const { return handle.size(); }

 private:
  // Inline, because grids are made in the OpenVDB plugin (scenes/openvdb/) as well as in glint,
  // and each has its own copy of the counter: the key pairs the count with the counter's
  // address, so the two never give the same key.
  static Key newKey() {
    static std::atomic<uint64_t> counter{0};
    return {&counter, counter.fetch_add(1, std::memory_order_relaxed) + 1};
  }
};

struct VdbVolume {
  std::string file;
  VdbGrid density;                            // float, required
  std::optional<VdbGrid> temperature, flame;  // float, optional
  std::optional<VdbGrid> color;               // vec3, optional: multiplies sigma_s per point
  Rgb maxColor{1, 1, 1};                      // of the colour grid's values, per component
  // The colour interpolated weighted by the density: the grid holds colour x density (the
  // reader multiplies them) and color() divides by the interpolated density, as Blender
  // renders a fluid domain's colour. Every interpolated colour is then a weighted mean of the
  // file's colours, so maxColor still bounds it.
  bool colorDensityWeighted = false;
  // Object-space box outside which every grid's lookups give the background: the active
  // voxels (and tiles) of the grids, grown by one voxel for the trilinear lookups' reach.
  Bounds3f bounds;
  float maxDensity = 0;  // of the density grid's values (active and background)
  // Density maxima over `bounds` (materials/majorant_grid.h); absent: one majorant.
  std::optional<MajorantGrid> majorants;
  // The temperature and flame grids' maxima over the same cells (where those grids are read
  // and `majorants` is there), background included: VdbEmission's bound, cell by cell.
  std::optional<MajorantGrid> temperatureMaxima, flameMaxima;

  size_t bytes() const;
};

// density = scale x the density grid, trilinear.
class VdbDensity final : public DensityField {
 public:
  VdbDensity(std::shared_ptr<const VdbVolume> volume, float scale);
  float density(Vec3f p) const override { return scale_ * volume_->density.sample(p); }
  float maxDensity(const Bounds3f&) const override { return max_; }
  const MajorantGrid* majorantGrid() const override { return majorants_ ? &*majorants_ : nullptr; }

 private:
  std::shared_ptr<const VdbVolume> volume_;
  float scale_;
  float max_ = 0;
  std::optional<MajorantGrid> majorants_;  // the volume's, times scale
};

// The scattering colour per point from the colour grid (as Cycles' Principled Volume "Color":
// sigma_s(p) = sigma_s x colour(p) x density(p)), bounded by the grid's largest components.
// `densityScale` is the medium's VdbDensity scale: color()'s density over it is the density
// grid's own value, by which a density-weighted colour is divided.
class VdbColor final : public ColorField {
 public:
  VdbColor(std::shared_ptr<const VdbVolume> volume, float densityScale)
      : volume_(std::move(volume)), densityScale_(densityScale) {}
  Rgb color(Vec3f p, float density) const override;
  Rgb maxColor() const override { return volume_->maxColor; }

 private:
  std::shared_ptr<const VdbVolume> volume_;
  float densityScale_;
};

// Fire: blackbody radiation of the temperature grid (in kelvin: the reader maps its voxels,
// scenes/vdb_file.h's VdbTemperatureMap; materials/blackbody.h, times blackbody_intensity)
// plus the flame grid times flame_strength x flame_color. Per unit length, independent of
// density (as Cycles' Principled Volume).
struct VdbEmissionParams {
  float blackbodyIntensity = 0;
  float flameStrength = 0;
  Rgb flameColor{1, 1, 1};
};

class VdbEmission final : public EmissionField {
 public:
  VdbEmission(std::shared_ptr<const VdbVolume> volume, const VdbEmissionParams& params);
  Rgb emission(Vec3f p) const override;
  const MajorantGrid* luminanceBound() const override { return bound_ ? &*bound_ : nullptr; }

 private:
  std::shared_ptr<const VdbVolume> volume_;
  VdbEmissionParams params_;
  // The luminance of the emission's bound per cell of the density's majorant grid, from the
  // grids' maxima (absent without them).
  std::optional<MajorantGrid> bound_;
};

}  // namespace glint
