// glint — VDB volumes in memory.
#include "materials/vdb_volume.h"

#include <nanovdb/util/SampleFromVoxels.h>

#include <algorithm>

#include "materials/blackbody.h"

namespace glint {

float VdbGrid::sample(Vec3f p) const {
  const nanovdb::FloatGrid* grid = handle.grid<float>();
  // A read accessor per lookup: it caches the path to the last leaf, and costs a few words.
  const auto accessor = grid->getAccessor();
  const nanovdb::Vec3f index = grid->worldToIndexF(nanovdb::Vec3f(p.x, p.y, p.z));
  return nanovdb::createSampler<1>(accessor)(index);
}

size_t VdbVolume::bytes() const {
  size_t n = density.bytes() + (majorants ? majorants->bytes() : 0);
  if (temperature) n += temperature->bytes();
  if (flame) n += flame->bytes();
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
    : volume_(std::move(volume)), params_(params) {}

Rgb VdbEmission::emission(Vec3f p) const {
  Rgb L{0, 0, 0};
  if (volume_->temperature && params_.blackbodyIntensity > 0) {
    const float T =
        params_.temperatureScale * volume_->temperature->sample(p) + params_.temperatureOffset;
    L += blackbodyEmission(T) * params_.blackbodyIntensity;
  }
  if (volume_->flame && params_.flameStrength > 0)
    L += params_.flameColor * (params_.flameStrength * std::max(0.0f, volume_->flame->sample(p)));
  return L;
}

}  // namespace glint
