// glint — Film: the rendered image as per-pixel mean, variance and optional AOVs.
//
// Every pixel is estimated from its own samples only (the filter is importance-sampled), so
// the renderer writes each pixel once with its final statistics; no splatting between pixels.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "geometry/math.h"

namespace glint {

struct Film {
  int width = 0, height = 0;
  // Where the film lies in the whole image: a crop of a larger frame (glint render --crop /
  // --tile) starts at (originX, originY) of a fullWidth x fullHeight image; a whole frame has
  // origin 0 and its own size. EXR output writes it as the data window.
  int originX = 0, originY = 0;
  int fullWidth = 0, fullHeight = 0;
  std::vector<Rgb> color;     // mean scene-linear radiance
  std::vector<Rgb> variance;  // variance of the mean (sample variance / n), per channel
  std::vector<float> alpha;   // fraction of samples whose camera ray hit geometry
  // Samples each pixel took: the render's spp, or fewer where adaptive sampling stopped a
  // pixel early. What the mean and variance above are over, so a render can be continued.
  std::vector<uint32_t> samples;
  bool hasAovs = false;
  std::vector<Rgb> albedo;    // AOVs (filled when hasAovs): mean first-hit albedo,
  std::vector<Vec3f> normal;  // mean world shading normal,
  std::vector<float> depth;   // mean camera-ray distance (0 where nothing was hit)

  Film() = default;
  Film(int w, int h, bool aovs);
  size_t index(int x, int y) const { return size_t(y) * size_t(width) + size_t(x); }
};

// x / (1 + x): scene-linear radiance squeezed into [0, 1), like a displayed value; where
// anti-aliasing compares contrast.
inline float squeezedRadiance(float x) { return x > 0 ? x / (1 + x) : 0.0f; }

}  // namespace glint
