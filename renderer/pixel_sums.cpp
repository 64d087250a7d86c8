// glint — a pixel's samples summed (see pixel_sums.h).
#include "renderer/pixel_sums.h"

#include <cmath>

namespace glint {

void PixelSums::writeTo(Film& film, size_t i) const {
  const uint32_t k = taken;
  film.samples[i] = k;
  if (k == 0) {
    film.color[i] = film.variance[i] = Rgb{};
    film.alpha[i] = 0;
    return;
  }
  const double invK = 1.0 / k;
  film.color[i] = moments.meanTimes(invK);
  film.variance[i] = k >= 2 ? moments.varianceOfMeanTimes(invK, 1.0 / (double(k - 1) * k)) : Rgb{};
  film.alpha[i] = float(double(hits) * invK);
  if (film.hasAovs) {
    film.albedo[i] = albedo / float(k);
    film.normal[i] = normal / float(k);
    film.depth[i] = hits > 0 ? float(depth / hits) : 0.0f;
  }
}

PixelSums PixelSums::readFrom(const Film& partial, size_t i) {
  PixelSums s;
  const uint32_t k = partial.samples[i];
  // Undo mean = sum / k and Var[mean] = (sumSq - sum² / k) / ((k - 1) k).
  for (int c = 0; c < 3; ++c) {
    const double mean = partial.color[i][c];
    s.moments.sum[c] = mean * k;
    s.moments.sumSq[c] = k >= 2
                             ? double(partial.variance[i][c]) * double(k - 1) * k + mean * mean * k
                             : mean * mean * k;
  }
  s.taken = k;
  s.hits = uint32_t(std::lround(double(partial.alpha[i]) * k));
  if (partial.hasAovs) {
    s.albedo = partial.albedo[i] * float(k);
    s.normal = partial.normal[i] * float(k);
    s.depth = double(partial.depth[i]) * s.hits;
  }
  return s;
}

void PixelSumsGrid::allocate(size_t pixels, bool aovs) {
  aovs_ = aovs;
  moments_.assign(pixels, PixelMoments{});
  taken_.assign(pixels, 0);
  hits_.assign(pixels, 0);
  if (aovs) {
    albedo_.assign(pixels, Rgb{});
    normal_.assign(pixels, Rgb{});
    depth_.assign(pixels, 0.0);
  }
}

}  // namespace glint
