// glint — exposure and tone mapping: scene-linear radiance → display-relative linear values
// (1.0 = the display's maximum), which the OCIO display/view transform then encodes.
//
// Ward's operator needs one statistic of the image, the log-average world luminance. It is
// gathered separately from applying the scale, so an animation can gather it over every frame
// and map all frames with one factor (no flicker).
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "geometry/math.h"
#include "renderer/settings.h"

namespace glint {

// Added to every world luminance before the log so black pixels do not send the log-average to
// zero (Ward 1994 and Reinhard et al. 2002 use such a δ). In cd/m²: far below any visible level.
inline constexpr double kWardLogDelta = 1e-4;

// True for the operators ToneMapSettings::op accepts ("none", "ward").
bool isKnownToneMapOperator(const std::string& op);

// 2^stops.
float exposureScale(float stops);

// Log-average world luminance, accumulated over any number of images (frames) and merged across
// threads. World luminance Lw = luminance(rgb) · 2^exposure · wardSceneLuminance (cd/m²).
struct LogLuminanceStats {
  double sumLog = 0;       // Σ log(δ + Lw)
  uint64_t count = 0;      // number of pixels summed
  uint64_t nonBlack = 0;   // of those, pixels with Lw > 0
  uint64_t nonFinite = 0;  // NaN or infinite pixels: left out of the sum, only counted

  // Adds every pixel of one scene-linear image. Negative luminance counts as black.
  void add(std::span<const Rgb> sceneLinear, const ToneMapSettings& settings);
  void merge(const LogLuminanceStats& other);
  // Lwa = exp(mean log(δ + Lw)) in cd/m²; δ for an empty set.
  double logAverage() const;
  // True when no pixel had positive luminance (an all-black or empty frame).
  bool allBlack() const { return nonBlack == 0; }
};

// ---- sequences -------------------------------------------------------------------------------
//
// An animation is mapped in three steps: gather one LogLuminanceStats per frame, combine them
// with sequenceStats, then map every frame with the one toneMapScale(settings,
// sequence.logAverage()). The competition's animation tool averaged the frames' own scale
// factors; averaging log luminance over all pixels of all frames instead keeps Ward's statistic
// what it is for one image (a one-frame sequence maps exactly as the frame alone).

// The statistics of a whole sequence from each frame's: every pixel of every frame that has at
// least one non-black pixel. All-black frames (a fade to black, an empty first frame) are left
// out: their log-average is δ, a number chosen only to keep log finite, and one such frame in
// ten would lower Lwa of a 20 cd/m² sequence about threefold and brighten every other frame;
// the black frame itself maps to black at any scale. When every frame is black the result is
// their plain merge (Lwa = δ). nonFinite counts the NaN/Inf pixels of every frame.
LogLuminanceStats sequenceStats(std::span<const LogLuminanceStats> frames);

// Ward's contrast-based scale factor m = ((1.219 + (Ldmax/2)^0.4) / (1.219 + Lwa^0.4))^2.5,
// mapping world luminance to display luminance (cd/m²). Greg Ward, "A contrast-based
// scalefactor for luminance display", Graphics Gems IV (1994), pp. 415–421.
double wardScaleFactor(double logAverageLuminance, double displayMax);

// The single multiplier that takes scene-linear values to display-relative values for these
// settings: 2^exposure for "none"; 2^exposure · Lscene · m / Ldmax for "ward", where
// `logAverageLuminance` is Lwa from LogLuminanceStats (ignored for "none"). Throws ColorError
// for an unknown operator.
double toneMapScale(const ToneMapSettings& settings, double logAverageLuminance);

// Multiplies `pixels` in place by toneMapScale(settings, Lwa).
void applyToneMap(std::span<Rgb> pixels, const ToneMapSettings& settings,
                  double logAverageLuminance);

// One image on its own: gathers its statistics (Ward only) and applies them.
void toneMap(std::span<Rgb> pixels, const ToneMapSettings& settings);

}  // namespace glint
