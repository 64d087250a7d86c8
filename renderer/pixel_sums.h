// glint — a pixel's samples summed: what the render loop keeps of a pixel between passes, the
// film pixel written from it, and the sums rebuilt from a film to continue a render.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "renderer/film.h"
#include "renderer/integrator.h"

namespace glint {

// Per-pixel sums of radiance and squared radiance, in double: a pixel has at most a few
// thousand samples of bounded magnitude, so sum/sum-of-squares is accurate here and cheaper
// than Welford's update (no division per sample). Kept across passes: adding a pass's samples
// in sample order gives the sums a single run gives.
struct PixelMoments {
  double sum[3] = {0, 0, 0}, sumSq[3] = {0, 0, 0};
  void add(Rgb v) {
    for (int c = 0; c < 3; ++c) {
      sum[c] += v[c];
      sumSq[c] += double(v[c]) * v[c];
    }
  }
  Rgb mean(double n) const { return {float(sum[0] / n), float(sum[1] / n), float(sum[2] / n)}; }
  // The adaptive stopping rule (AdaptiveSettings): every channel's Var[mean] within
  // threshold² · (mean² + 0.01).
  bool converged(double n, double threshold2) const {
    for (int c = 0; c < 3; ++c) {
      const double mean = sum[c] / n;
      const double var = std::max(0.0, (sumSq[c] - sum[c] * mean) / ((n - 1) * n));
      if (var > threshold2 * (mean * mean + 0.01)) return false;
    }
    return true;
  }
  // The mean, and the variance of the mean (sumSq - sum² / n) / ((n - 1) n), from 1/n and
  // 1/((n - 1) n): the film update's form, two divisions a pixel instead of seven.
  Rgb meanTimes(double invN) const {
    return {float(sum[0] * invN), float(sum[1] * invN), float(sum[2] * invN)};
  }
  Rgb varianceOfMeanTimes(double invN, double invNN1) const {
    Rgb v;
    for (int c = 0; c < 3; ++c)
      v[c] = float(std::max(0.0, (sumSq[c] - sum[c] * sum[c] * invN) * invNN1));
    return v;
  }
};

// Everything a pixel's samples add up to: radiance moments, how many samples and how many of
// them hit geometry, and the AOV sums (float, as a single pass adds them).
struct PixelSums {
  PixelMoments moments;
  uint32_t taken = 0;  // samples in the sums
  uint32_t hits = 0;   // of them, camera rays that hit geometry
  Rgb albedo, normal;
  double depth = 0;

  // A sample of radiance L whose camera ray hit geometry or not.
  void add(Rgb L, bool hit) {
    moments.add(L);
    ++taken;
    hits += hit ? 1 : 0;
  }
  // The same with the first hit's AOVs.
  void add(Rgb L, const PathAovs& aovs) {
    add(L, aovs.hit);
    if (aovs.hit) {
      albedo += aovs.albedo;
      normal += aovs.normal;
      depth += aovs.depth;
    }
  }
  // Film pixel i from these sums: mean, variance of the mean, alpha, the sample count and, when
  // the film has them, the AOVs.
  void writeTo(Film& film, size_t i) const;
  // What writeTo(partial, i) was given, up to the rounding of the stored floats: the sums of a
  // render to continue.
  static PixelSums readFrom(const Film& partial, size_t i);
};

// The sums of every pixel of a region, kept across passes, a field per array (the AOV arrays
// only with AOVs): a pass reads and writes each pixel's, and their memory traffic is a visible
// share of a short render.
class PixelSumsGrid {
 public:
  // `pixels` pixels of zero sums; none until then.
  void allocate(size_t pixels, bool aovs);
  bool empty() const { return moments_.empty(); }
  PixelSums load(size_t i) const {
    PixelSums s;
    s.moments = moments_[i];
    s.taken = taken_[i];
    s.hits = hits_[i];
    if (aovs_) {
      s.albedo = albedo_[i];
      s.normal = normal_[i];
      s.depth = depth_[i];
    }
    return s;
  }
  void store(size_t i, const PixelSums& s) {
    moments_[i] = s.moments;
    taken_[i] = s.taken;
    hits_[i] = s.hits;
    if (aovs_) {
      albedo_[i] = s.albedo;
      normal_[i] = s.normal;
      depth_[i] = s.depth;
    }
  }
  uint32_t taken(size_t i) const { return taken_[i]; }
  const PixelMoments& moments(size_t i) const { return moments_[i]; }

 private:
  bool aovs_ = false;
  std::vector<PixelMoments> moments_;
  std::vector<uint32_t> taken_, hits_;
  std::vector<Rgb> albedo_, normal_;
  std::vector<double> depth_;
};

}  // namespace glint
