// glint — FLIP, a perceptual difference evaluator for rendered images: a per-pixel error map in
// [0, 1] that approximates what an observer sees when flipping between a reference and a test
// image at a given viewing distance.
//
// LDR-FLIP: P. Andersson, J. Nilsson, T. Akenine-Möller, M. Oskarsson, K. Åström and
// M. D. Fairchild, "FLIP: A Difference Evaluator for Alternating Images", Proc. ACM Comput.
// Graph. Interact. Tech. 3(2) (HPG 2020).
// HDR-FLIP: P. Andersson, J. Nilsson, P. Shirley and T. Akenine-Möller, "Visualizing Errors in
// Rendered High Dynamic Range Images", Eurographics 2021 short papers: LDR-FLIP of the two
// images tone-mapped at a range of exposures, the per-pixel maximum over the exposures.
//
// Written from the papers; constants and the order of the steps were checked against the
// description and public reference implementation of the authors (NVlabs/flip, v1.x), whose
// results this follows in float precision. Deviations, all small:
//  * The spatial filters are applied as separable 1-D passes (the CSF and feature kernels are
//    sums of products of 1-D Gaussians, so this is exact up to rounding), edges replicated.
//  * HDR-FLIP's stop exposure uses the true median of the reference luminance; when that median
//    is 0 (more than half the reference black), the median of the non-black pixels instead of
//    the reference implementations' infinite exposure. An all-black reference uses exposure 0.
//  * Non-finite input values count as 0 (as the FLIP tool does for NaN); LDR input is clamped
//    to [0, 1]; HDR +inf tone-maps to 1.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include "geometry/math.h"

namespace glint {

// Pixels per degree of visual angle for an observer `distanceMeters` from a monitor
// `monitorWidthMeters` wide that shows `monitorWidthPixels` across:
// distance · (pixels / width) · π / 180.
double flipPixelsPerDegree(double distanceMeters, double monitorWidthPixels,
                           double monitorWidthMeters);

// The papers' default observer: 0.7 m from a 0.7 m wide, 3840-pixel monitor (≈ 67.02 ppd).
inline constexpr double kFlipDefaultPixelsPerDegree =
    0.7 * (3840.0 / 0.7) * 3.14159265358979323846 / 180.0;

// Pooled values of an error map, as the FLIP tools report them.
struct FlipStats {
  double mean = 0;
  double weightedMedian = 0;                            // flipWeightedPercentile(·, 0.50)
  double weightedQuartile1 = 0, weightedQuartile3 = 0;  // … 0.25 and 0.75
  double percentile95 = 0;  // the plain 95th percentile of the pixels' errors (nearest rank)
  double min = 0, max = 0;
  int maxX = 0, maxY = 0;  // first pixel (row-major) holding `max`
};

// The exposure range HDR-FLIP evaluates: `count` exposures (stops, as 2^e multipliers) evenly
// spaced from `start` to `stop`.
struct FlipExposures {
  float start = 0, stop = 0;
  int count = 1;
};

struct FlipResult {
  int width = 0, height = 0;
  std::vector<float> error;  // width · height values in [0, 1], row-major, top row first
  FlipStats stats;
  FlipExposures exposures;  // HDR-FLIP: the exposures used; LDR-FLIP: {0, 0, 1}
};

// The two factors of LDR-FLIP's error ΔE = ΔE_c^(1 − ΔE_f), each width · height in [0, 1]:
// the re-mapped colour difference and the feature (edge / point) difference.
struct FlipComponents {
  int width = 0, height = 0;
  std::vector<float> color;    // ΔE_c
  std::vector<float> feature;  // ΔE_f
};

// ---- LDR-FLIP --------------------------------------------------------------------------------
//
// Images are interleaved RGB floats, width · height · 3, row-major: display-referred sRGB-encoded
// values in [0, 1]. Throws std::logic_error when a buffer's size is not width · height · 3, the
// size is not positive or pixelsPerDegree is not positive: callers check their input first
// (glint diff compares the sizes, CLI11 checks --ppd), so these are bugs. LDR-FLIP is symmetric
// in its two images.

// The LDR-FLIP error map of `test` against `reference`, and its pooled values.
FlipResult flipLdr(std::span<const float> reference, std::span<const float> test, int width,
                   int height, double pixelsPerDegree = kFlipDefaultPixelsPerDegree);

// ΔE_c and ΔE_f separately (flipLdr combines them), for inspection and tests.
FlipComponents flipLdrComponents(std::span<const float> reference, std::span<const float> test,
                                 int width, int height,
                                 double pixelsPerDegree = kFlipDefaultPixelsPerDegree);

// The colour pipeline's filtered image: `srgb` to YCxCz, each opponent channel convolved with
// its contrast-sensitivity filter, back to linear RGB and clamped to [0, 1]. Interleaved RGB.
std::vector<float> flipCsfFiltered(std::span<const float> srgb, int width, int height,
                                   double pixelsPerDegree = kFlipDefaultPixelsPerDegree);

// ---- HDR-FLIP --------------------------------------------------------------------------------

// The tone mappers HDR-FLIP can assume (ACES is the paper's default): Narkowicz's fit to ACES
// with its 0.6 pre-exposure cancelled, Hable's filmic curve (white 11.2, exposure bias 2), and
// Reinhard's x / (1 + luminance).
enum class FlipToneMapper { Aces, Hable, Reinhard };

// Exposure 2^exposure, then the tone mapper, clamped to [0, 1]: scene-linear → display-linear.
// Negative and NaN components count as 0.
Rgb flipToneMap(Rgb sceneLinear, float exposure, FlipToneMapper toneMapper);

// The paper's automatic range for a scene-linear reference: the start exposure maps the
// brightest luminance, the stop exposure the median luminance, to 0.85 after tone mapping;
// count = max(2, ⌈stop − start⌉), or 1 when start = stop.
FlipExposures flipExposureRange(std::span<const float> reference, int width, int height,
                                FlipToneMapper toneMapper = FlipToneMapper::Aces);

struct FlipHdrOptions {
  double pixelsPerDegree = kFlipDefaultPixelsPerDegree;
  FlipToneMapper toneMapper = FlipToneMapper::Aces;
  std::optional<float> startExposure, stopExposure;  // unset: from flipExposureRange
  int exposureCount = 0;  // 0: max(2, ⌈stop − start⌉) as the paper (1 when start = stop)
};

// The HDR-FLIP error map of two scene-linear images (interleaved RGB, as above): the per-pixel
// maximum of LDR-FLIP over the tone-mapped, sRGB-encoded exposures. Not symmetric: the exposure
// range comes from `reference`. Throws std::logic_error as flipLdr, and when the start exposure
// is after the stop exposure.
FlipResult flipHdr(std::span<const float> reference, std::span<const float> test, int width,
                   int height, const FlipHdrOptions& options = {});

// ---- pooling and display ---------------------------------------------------------------------

// The FLIP tools' weighted percentile: sorting the errors ascending, the first error at which
// the running sum exceeds `fraction` (in [0, 1]) of the total sum; 0 for an all-zero map.
double flipWeightedPercentile(std::span<const float> error, double fraction);

// Mean, weighted quartiles, min and max of a width-wide row-major error map.
FlipStats flipStatistics(std::span<const float> error, int width);

// The magma colour map (matplotlib's 256 entries, display-encoded sRGB) at t ∈ [0, 1]: entry
// round(255 · t), as the FLIP tools index it. t outside [0, 1] (or NaN) is clamped (NaN → 0).
Rgb flipMagma(float t);

// An error map as an interleaved RGB heat-map image (magma, display-encoded sRGB in [0, 1]).
std::vector<float> flipHeatMap(std::span<const float> error);

}  // namespace glint
