// glint — the render loop: tiles over threads, samples per pixel, statistics.
#pragma once

#include <cstdint>
#include <optional>

#include "renderer/film.h"
#include "renderer/integrator.h"
#include "renderer/scene.h"
#include "renderer/settings.h"

namespace glint {

// The sampler dimensions of one camera path, the same for every scene so that switching depth
// of field or motion blur on or off changes the camera ray and nothing else (an aperture of 0
// renders the pinhole image exactly). The lens pair and the time are drawn only when the scene
// needs them (a camera with an aperture; Feature::MotionBlur), otherwise the lens centre and
// time 0 are used and the dimensions stay unused.
inline constexpr uint32_t kFilmDimension = 0;        // 0-1: position in the pixel (filter)
inline constexpr uint32_t kLensDimension = 2;        // 2-3: point on the aperture
inline constexpr uint32_t kTimeDimension = 4;        // 4: shutter time, stratified per pixel
inline constexpr uint32_t kIntegratorDimension = 5;  // 5-: the integrator's

struct RenderStats {
  double renderSeconds = 0;
  int threads = 0;
  RayCounters rays;
  uint64_t nonfiniteSamples = 0;  // NaN/Inf radiance samples: counted, replaced by zero
  double meanSpp = 0;             // samples a pixel took on average (< spp when adaptive)
};

// A rectangle of pixels [x0, x1) x [y0, y1) of the image.
struct PixelWindow {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
  friend bool operator==(const PixelWindow&, const PixelWindow&) = default;
};

// The I-th of N horizontal bands of a width x height image (0 <= index < count <= height):
// rows [floor(I H / N), floor((I + 1) H / N)). A fixed layout, so N tasks rendering tiles 0..N-1
// cover the frame exactly once. Throws InputError for an index or count outside those bounds.
PixelWindow tileWindow(int width, int height, int index, int count);

struct RenderOptions {
  int threads = 0;        // 0 = all hardware threads
  bool progress = false;  // draw a progress bar on stderr
  int tileSize = 16;
  // Render only these pixels (inside the image; not empty). Samples are keyed by the pixel's
  // place in the whole image, so each pixel is exactly what a whole-frame render gives.
  std::optional<PixelWindow> crop;
};

// Renders `scene` with `integrator` at the camera's resolution (or its options.crop window: a
// film of that size at that origin). Each pixel's samples are addressed by (pixel, sample,
// seed), so the result does not depend on thread count, tile order or cropping. NaN/Inf
// samples never reach the film. Throws InputError for a crop outside the image.
Film render(const RenderScene& scene, const Integrator& integrator, const RenderSettings& settings,
            const RenderOptions& options, RenderStats* stats);

}  // namespace glint
