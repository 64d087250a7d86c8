// glint — VDB volumes in memory.
#include "materials/vdb_volume.h"

#include <nanovdb/util/SampleFromVoxels.h>

#include <algorithm>
#include <optional>
#include <type_traits>

#include "materials/blackbody.h"

namespace glint {

namespace {

// Per-thread trilinear samplers, kept from one lookup to the next. A NanoVDB read accessor caches
// the path from the root to the last leaf it read, and the sampler the eight voxels around the
// last point; successive lookups along a ray mostly fall in the same leaf (a leaf is 8 voxels
// wide, tracking's collisions a few voxels apart), so a kept accessor skips the descent from the
// root that a fresh one makes at every lookup. Slots are keyed by the grid's key, not its
// address, which a later grid may reuse; a few slots serve a fire's density, temperature and
// flame grids in turn.
struct CachedSampler {
  using Accessor = nanovdb::DefaultReadAccessor<float>;
  using Trilinear = nanovdb::SampleFromVoxels<Accessor, 1, true>;
  VdbGrid::Key key;  // none: an empty slot
  std::optional<Accessor> accessor;
  std::optional<Trilinear> trilinear;
};

CachedSampler& cachedSampler(const nanovdb::FloatGrid& grid, const VdbGrid::Key& key) {
  constexpr int kSlots = 4;
  thread_local CachedSampler slots[kSlots];
  thread_local int victim = 0;
  for (CachedSampler& s : slots)
    if (s.key == key) return s;
  CachedSampler& s = slots[victim];
  victim = (victim + 1) % kSlots;
  s.key = key;
  s.trilinear.reset();
  s.accessor.emplace(grid.getAccessor());
  s.trilinear.emplace(*s.accessor);
  return s;
}

}  // namespace

float VdbGrid::sample(Vec3f p) const {
  const nanovdb::FloatGrid* grid = handle.grid<float>();
  const nanovdb::Vec3f index = grid->worldToIndexF(nanovdb::Vec3f(p.x, p.y, p.z));
  CachedSampler& cache = cachedSampler(*grid, key);
  nanovdb::Vec3f uvw = index;
  const nanovdb::Coord ijk = nanovdb::Floor<nanovdb::Coord>(uvw);  // uvw: the fraction left
  // Most stencils (7 in 8 along each axis) lie inside one leaf: one cached leaf lookup and
  // eight loads instead of eight accessor lookups. The same interpolation as NanoVDB's sampler.
  if ((ijk[0] & 7) != 7 && (ijk[1] & 7) != 7 && (ijk[2] & 7) != 7) {
    if (const auto* leaf = cache.accessor->probeLeaf(ijk)) {
      using Leaf = std::remove_cv_t<std::remove_pointer_t<decltype(leaf)>>;
      const uint32_t n = Leaf::CoordToOffset(ijk);
      auto v = [&](uint32_t i, uint32_t j, uint32_t k) {
        return leaf->getValue(n + 64 * i + 8 * j + k);
      };
      const float stencil[2][2][2] = {{{v(0, 0, 0), v(0, 0, 1)}, {v(0, 1, 0), v(0, 1, 1)}},
                                      {{v(1, 0, 0), v(1, 0, 1)}, {v(1, 1, 0), v(1, 1, 1)}}};
      return CachedSampler::Trilinear::sample(uvw, stencil);
    }
  }
  return (*cache.trilinear)(index);
}

Rgb VdbGrid::sampleVec3(Vec3f p) const {
  // (No kept accessor: a colour is looked up once per real collision, not per tentative one.)
  const nanovdb::Vec3fGrid* grid = handle.grid<nanovdb::Vec3f>();
  const auto accessor = grid->getAccessor();
  const nanovdb::Vec3f index = grid->worldToIndexF(nanovdb::Vec3f(p.x, p.y, p.z));
  const nanovdb::Vec3f c = nanovdb::createSampler<1>(accessor)(index);
  return {c[0], c[1], c[2]};
}

Rgb VdbColor::color(Vec3f p, float density) const {
  const Rgb c = volume_->color->sampleVec3(p);
  if (!volume_->colorDensityWeighted) return c;
  // Where the density is nearly 0 the colour does not matter (it scales sigma_s x 0).
  const float d = densityScale_ > 0 ? density / densityScale_ : 0.0f;
  return d > 1e-6f ? min(c / d, volume_->maxColor) : c;
}

size_t VdbVolume::bytes() const {
  size_t n = density.bytes() + (majorants ? majorants->bytes() : 0);
  if (color) n += color->bytes();
  if (temperature) n += temperature->bytes();
  if (flame) n += flame->bytes();
  if (temperatureMaxima) n += temperatureMaxima->bytes();
  if (flameMaxima) n += flameMaxima->bytes();
  return n;
}

VdbDensity::VdbDensity(std::shared_ptr<const VdbVolume> volume, float scale)
    : volume_(std::move(volume)), scale_(scale) {
  if (volume_->majorants) {
    majorants_ = *volume_->majorants;
    majorants_->scale(scale_);
    max_ = majorants_->maxValue();
  } else {
    max_ = scale_ * volume_->maxDensity;
  }
}

VdbEmission::VdbEmission(std::shared_ptr<const VdbVolume> volume, const VdbEmissionParams& params)
    : volume_(std::move(volume)), params_(params) {
  const bool blackbody = volume_->temperature && params_.blackbodyIntensity > 0;
  const bool flame = volume_->flame && params_.flameStrength > 0;
  if (!volume_->majorants || (blackbody && !volume_->temperatureMaxima) ||
      (flame && !volume_->flameMaxima))
    return;
  // Blackbody luminance grows with the temperature (as T^4), so a cell's hottest voxel bounds
  // it; the flame's is its largest value times the colour's luminance.
  const MajorantGrid& cells = *volume_->majorants;
  bound_.emplace(cells.bounds(), cells.res(0), cells.res(1), cells.res(2));
  for (int z = 0; z < cells.res(2); ++z)
    for (int y = 0; y < cells.res(1); ++y)
      for (int x = 0; x < cells.res(0); ++x) {
        float L = 0;
        if (blackbody) {
          const float T = volume_->temperatureMaxima->at(x, y, z);
          L += luminance(blackbodyEmission(T)) * params_.blackbodyIntensity;
        }
        if (flame)
          L += luminance(params_.flameColor) * params_.flameStrength *
               std::max(0.0f, volume_->flameMaxima->at(x, y, z));
        bound_->set(x, y, z, L);
      }
}

Rgb VdbEmission::emission(Vec3f p) const {
  Rgb L{0, 0, 0};
  if (volume_->temperature && params_.blackbodyIntensity > 0) {
    L += blackbodyEmission(volume_->temperature->sample(p)) * params_.blackbodyIntensity;
  }
  if (volume_->flame && params_.flameStrength > 0)
    L += params_.flameColor * (params_.flameStrength * std::max(0.0f, volume_->flame->sample(p)));
  return L;
}

}  // namespace glint
