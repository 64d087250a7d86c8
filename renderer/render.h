// glint — the render loop: tiles over threads, samples per pixel, statistics.
#pragma once

#include <cstdint>

#include "renderer/film.h"
#include "renderer/integrator.h"
#include "renderer/scene.h"
#include "renderer/settings.h"

namespace glint {

struct RenderStats {
  double renderSeconds = 0;
  int threads = 0;
  RayCounters rays;
  uint64_t nonfiniteSamples = 0;  // NaN/Inf radiance samples: counted, replaced by zero
};

struct RenderOptions {
  int threads = 0;         // 0 = all hardware threads
  bool progress = false;   // draw a progress bar on stderr
  int tileSize = 16;
};

// Renders `scene` with `integrator` at the camera's resolution. Each pixel's samples are
// addressed by (pixel, sample, seed), so the result does not depend on thread count or tile
// order. NaN/Inf samples never reach the film.
Film render(const RenderScene& scene, const Integrator& integrator,
            const RenderSettings& settings, const RenderOptions& options, RenderStats* stats);

}  // namespace glint
