// glint — rays traced, by kind; summed over threads for --stats.
#pragma once

#include <cstdint>

namespace glint {

struct RayCounters {
  uint64_t camera = 0, shadow = 0, secondary = 0;
  RayCounters& operator+=(const RayCounters& o) {
    camera += o.camera, shadow += o.shadow, secondary += o.secondary;
    return *this;
  }
  uint64_t total() const { return camera + shadow + secondary; }
};

}  // namespace glint
