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

// Added to every world luminance before the log (Ward 1994 and Reinhard et al. 2002 use such a
// δ). In cd/m²: far below any visible level.
inline constexpr double kWardLogDelta = 1e-4;

// Ward adapts to the lit pixels only: a pixel whose world luminance is at most δ (black, or so
// dark that log(δ + Lw) is within log 2 of log δ) is left out of the log-average. Counting
// them, as glint did before, let a black background set the adaptation: a grey object of
// 50 cd/m² filling 5 % of a frame on black got Lwa ≈ 2e-4 cd/m² (pulled toward the black
// pixels' δ) instead of about its own 50, a scale factor 50 times the object's own, and was
// blown out to white. A frame without black pixels maps exactly as before.

// True for the operators ToneMapSettings::op accepts ("none", "ward").
bool isKnownToneMapOperator(const std::string& op);

// 2^stops.
float exposureScale(float stops);

// Log-average world luminance of the lit pixels (Lw > δ, see above), accumulated over any number
// of images (frames) and merged across threads. World luminance Lw = luminance(rgb) ·
// 2^exposure · wardSceneLuminance (cd/m²).
struct LogLuminanceStats {
  double sumLog = 0;       // Σ log(δ + Lw) over the lit pixels
  uint64_t count = 0;      // lit pixels summed
  uint64_t dark = 0;       // pixels left out as black (Lw <= δ, negative luminance included)
  uint64_t nonFinite = 0;  // NaN or infinite pixels: left out of the sum, only counted

  // Adds every pixel of one scene-linear image.
  void add(std::span<const Rgb> sceneLinear, const ToneMapSettings& settings);
  void merge(const LogLuminanceStats& other);
  // Lwa = exp(mean log(δ + Lw)) over the lit pixels, in cd/m²; δ when there are none.
  double logAverage() const;
  // True when no pixel was lit (an all-black, all-NaN or empty frame).
  bool allBlack() const { return count == 0; }
};

// ---- sequences -------------------------------------------------------------------------------
//
// An animation is mapped in three steps: gather one LogLuminanceStats per frame, combine them
// with sequenceStats, then map every frame with the one toneMapScale(settings,
// sequence.logAverage()). The competition's animation tool averaged the frames' own scale
// factors; averaging log luminance over the lit pixels of all frames instead keeps Ward's statistic
// what it is for one image (a one-frame sequence maps exactly as the frame alone).

// The statistics of a whole sequence from each frame's: the lit pixels of every frame. An
// all-black frame (a fade to black, an empty first frame) has none and adds nothing, so it does
// not lower Lwa (it maps to black at any scale); when every frame is black, Lwa = δ. nonFinite
// and dark count the pixels of every frame.
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
