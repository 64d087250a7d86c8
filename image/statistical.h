// glint — statistical comparison of a Monte Carlo render against a reference that carries the
// variance of its per-pixel mean (glint writes it as variance.R/G/B with `--aovs`).
//
// Two renders of the same scene differ by noise even when both are right, so a fixed
// threshold on |a − b| is either too loose for the smooth pixels or too tight for the noisy
// ones. Instead, as in Mitsuba 3's render tests, every pixel channel is a z-test:
//
//   z = (a − b) / σ,   σ² = Var[b] + Var[a] + floor²,
//
// where Var[b] is the reference's variance of the mean and Var[a] is predicted from it:
// Var[b] · sppB / sppA (the reference's per-sample variance over the test's sample count).
// A low-spp render's own variance estimate is unreliable (a pixel that saw no rare path has an
// estimated variance of 0), the prediction is not; when the test image carries its own
// variance channels too, the larger of the two is used, so an estimator that is legitimately
// noisier than the reference's (another integrator) is not called biased. `floor` (1e-4 +
// 1e-3·|b|) keeps pixels whose samples all agree (flat backgrounds) from demanding equality
// to the last bit across CPUs.
//
// With N pixel channels tested at once, each test uses the Šidák-corrected significance
// 1 − (1 − α)^(1/N), so a correct render fails any single pixel with probability α overall.
// The model is approximate (heavy-tailed pixels, correlated samples), so the comparison passes
// when at least `minPassPercent` % of the pixels pass, as Mitsuba's tests do. Two more checks
// catch what a per-pixel test at low spp cannot:
//   - a global bias test per channel: Σ(a − b) / sqrt(Σσ²) (pixels are independent), which
//     finds a 2 % darkening of the whole image that no single noisy pixel shows;
//   - a hard cap on the error of the pixels that fail their z-test, |a − b| / max(1, |b|) ≤
//     maxError, so a handful of badly wrong pixels cannot hide inside the allowed fraction
//     (a large error that the pixel's noise explains is not capped: a firefly is not a bug).
//     NaN or Inf in either image fails.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "image/diff.h"

namespace glint {

struct StatisticalThresholds {
  double significance = 0.01;    // family-wise false-alarm rate α (per-pixel and global tests)
  double minPassPercent = 99.5;  // % of pixels that must pass their z-test
  double maxError = std::numeric_limits<double>::infinity();  // hard cap, see above
  int sppA = 0, sppB = 0;  // samples per pixel; 0: read from the images' glint:spp
};

struct StatisticalResult {
  int widthA = 0, heightA = 0, widthB = 0, heightB = 0;
  bool sizeMismatch = false;  // then nothing below was computed and verdict = Fail
  uint64_t pixels = 0;
  int sppA = 0, sppB = 0;     // as used (0: unknown)
  std::string varianceModel;  // "predicted", "own" or "max(own, predicted)": how Var[a] was set
  double pixelZ = 0;          // |z| above which a pixel channel fails (Šidák-corrected)
  uint64_t failPixels = 0;    // pixels with a channel over pixelZ (or non-finite)
  double passPercent = 100;
  double maxZ = 0;  // largest |z| and where
  int maxZX = 0, maxZY = 0;
  std::string maxZChannel;
  double meanZ2 = 0;  // mean z² over all tested channels: about 1 when the noise model fits
  std::array<double, 3> globalZ{};  // per channel R, G, B: Σ(a − b) / sqrt(Σσ²)
  double globalZLimit = 0;          // |globalZ| above which the image is biased
  bool biased = false;
  double maxError = 0;  // largest |a − b| / max(1, |b|) of a pixel failing its z-test, and where
  int maxErrorX = 0, maxErrorY = 0;
  bool errorCapExceeded = false;
  uint64_t nonFinite = 0;  // pixel channels with NaN or Inf in either image
  DiffVerdict verdict = DiffVerdict::Pass;
  std::vector<float> zMap;  // per pixel, the largest |z| over R, G, B (row-major)
};

// Compares render `a` against reference `b`; both need R, G, B; `b` needs variance.R/G/B.
// Throws ImageReadError for an unreadable image, a reference without variance channels, or an
// unknown sample count (neither given nor in the file's glint:spp) when `a` has no variance
// channels of its own.
StatisticalResult diffStatistical(const std::string& a, const std::string& b,
                                  const StatisticalThresholds& t);
// The same for images already read (`pathA`, `pathB` name them in errors), so that a caller
// that also runs FLIP reads each file once.
StatisticalResult diffStatistical(const Image& a, const std::string& pathA, const Image& b,
                                  const std::string& pathB, const StatisticalThresholds& t);

// The two-sided |z| whose tail probability is p: erfc(|z| / √2) = p.
double normalTwoSidedQuantile(double p);

// Writes a heat map of result.zMap (black → blue → yellow at the failure threshold → red →
// white at twice it) to a PNG/TIFF/EXR at `path`, atomically. Throws OutputError.
void writeZHeatMap(const std::string& path, const StatisticalResult& result);

}  // namespace glint
