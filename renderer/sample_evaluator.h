// glint — a pixel's samples evaluated: each sample's camera ray (its place in the pixel, and
// the lens point and shutter time where the scene has them), the ray's hit, the integrator's
// radiance, and the pixel's sums it goes into.
//
// The render loop's innermost step, pbrt-v4's RayIntegrator::EvaluatePixelSample, for a batch
// of a pixel's consecutive samples rather than one: their camera rays go to the accelerator
// together, which may trace them as a packet (they are coherent), and each hit is then shaded
// on its own. Which camera rays a scene needs (a plain pinhole batch, or per-sample rays with
// a lens, a shutter time, both) is decided once, when the evaluator is made.
#pragma once

#include <cstdint>

#include "renderer/filter.h"
#include "renderer/pixel_sums.h"
#include "renderer/render.h"
#include "renderer/sampler.h"
#include "renderer/stopping.h"

namespace glint {

// What a worker thread counts, merged at the end of a pass.
struct SampleTally {
  RayCounters rays;
  SampleChecks checks;
  uint64_t samples = 0;  // samples its pixels took, where the render keeps no sums
};

// The keys of one pixel's samples: its place (x, y) in the whole image, which keys them, and
// the seeds of the dimension pairs that depend on the pixel only (the film position, the lens
// point), computed once per pixel instead of once per sample.
struct PixelKeys {
  int x = 0, y = 0;
  uint64_t key = 0;  // pixelSampleKey
  DimensionSeeds film, lens;
};

class SampleEvaluator {
 public:
  // Throws InputError for a bad filter (PixelFilter).
  SampleEvaluator(const RenderScene& scene, const Integrator& integrator,
                  const RenderSettings& settings);

  PixelKeys keys(int x, int y) const;

  // A batch of camera rays and their hits: made once per tile by the caller (their default
  // initialisation per pixel was a fifth of the loop's own time at 4 spp). Every element a
  // batch reads it writes first (closestHits overwrites each hit whole).
  struct Batch {
    Ray rays[kCameraBatch];
    Hit found[kCameraBatch];
  };

  // Samples sums.taken .. sums.taken + n - 1 (n <= kCameraBatch) of the pixel, added to `sums`.
  // `centre`: they are the pixel's centre look (anti-aliasing by contrast), through the middle
  // of the pixel instead of the filter's place. NaN/Inf radiance is counted in tally.checks and
  // added as zero.
  void evaluate(const PixelKeys& pixel, uint32_t n, bool centre, Batch& batch, PixelSums& sums,
                SampleTally& tally) const;

 private:
  // How the camera rays are made, from the camera and the scene's features.
  enum class CameraRays {
    Pinhole,       // a static pinhole: a batch at once, lanes side by side (pinholeRays)
    Generic,       // one at a time (a moving camera the scene does not blur)
    Lens,          // with a point on the aperture
    Motion,        // at a shutter time
    LensAndMotion  // both
  };
  // The batch's hits shaded and added to the sums, with or without AOVs.
  template <bool kAovs>
  void shade(const PixelKeys& pixel, uint32_t n, const Batch& batch, PixelSums& sums,
             SampleTally& tally) const;
  template <bool kLens, bool kMotion>
  void sampledRays(const PixelKeys& pixel, uint32_t first, uint32_t n, const float* filmX,
                   const float* filmY, Ray* rays) const;

  const RenderScene& scene_;
  const Integrator& integrator_;
  PixelFilter filter_;
  uint64_t seed_;
  bool aovs_;
  CameraRays cameraRays_;
};

}  // namespace glint
