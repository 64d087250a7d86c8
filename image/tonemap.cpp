// glint — exposure and Ward (1994) contrast-based tone mapping.
#include "image/tonemap.h"

#include <fmt/format.h>

#include <cmath>

#include "image/color.h"

namespace glint {

bool isKnownToneMapOperator(const std::string& op) { return op == "none" || op == "ward"; }

float exposureScale(float stops) { return std::exp2(stops); }

// ---- statistics ------------------------------------------------------------------------------

void LogLuminanceStats::add(std::span<const Rgb> sceneLinear, const ToneMapSettings& settings) {
  const double toWorld = double(exposureScale(settings.exposure)) * settings.wardSceneLuminance;
  for (const Rgb& c : sceneLinear) {
    const double lw = double(luminance(c)) * toWorld;
    // A NaN or infinite pixel (a bad sample) would make the mean NaN or ±inf for the whole
    // image, or the whole sequence: leave it out, and count it so the caller can say so.
    if (!std::isfinite(lw)) {
      ++nonFinite;
      continue;
    }
    // Black (or negative) pixels are not what the eye adapts to (tonemap.h).
    if (!(lw > kWardLogDelta)) {
      ++dark;
      continue;
    }
    sumLog += std::log(kWardLogDelta + lw);
    ++count;
  }
}

void LogLuminanceStats::merge(const LogLuminanceStats& other) {
  sumLog += other.sumLog;
  count += other.count;
  dark += other.dark;
  nonFinite += other.nonFinite;
}

double LogLuminanceStats::logAverage() const {
  return count == 0 ? kWardLogDelta : std::exp(sumLog / double(count));
}

// ---- sequences -------------------------------------------------------------------------------

LogLuminanceStats sequenceStats(std::span<const LogLuminanceStats> frames) {
  // Only lit pixels are summed, so an all-black frame adds to `dark` and nothing else.
  LogLuminanceStats all;
  for (const LogLuminanceStats& f : frames) all.merge(f);
  return all;
}

// ---- applying a scale ------------------------------------------------------------------------

double wardScaleFactor(double logAverageLuminance, double displayMax) {
  // Ward's fit to Blackwell's threshold-versus-intensity data: just-noticeable differences in
  // the world map to just-noticeable differences on a display adapted to half its maximum.
  double num = 1.219 + std::pow(displayMax / 2.0, 0.4);
  double den = 1.219 + std::pow(logAverageLuminance, 0.4);
  return std::pow(num / den, 2.5);
}

double toneMapScale(const ToneMapSettings& settings, double logAverageLuminance) {
  double exposure = exposureScale(settings.exposure);
  if (settings.op == "none") return exposure;
  if (settings.op == "ward") {
    double m = wardScaleFactor(logAverageLuminance, settings.wardDisplayMax);
    return exposure * settings.wardSceneLuminance * m / settings.wardDisplayMax;
  }
  throw ColorError(
      fmt::format("unknown tone-map operator '{}'; available: 'none', 'ward'", settings.op));
}

void applyToneMap(std::span<Rgb> pixels, const ToneMapSettings& settings,
                  double logAverageLuminance) {
  float k = float(toneMapScale(settings, logAverageLuminance));
  for (Rgb& c : pixels) c = Rgb{c.x * k, c.y * k, c.z * k};
}

void toneMap(std::span<Rgb> pixels, const ToneMapSettings& settings) {
  LogLuminanceStats stats;
  if (settings.op == "ward") stats.add(pixels, settings);
  applyToneMap(pixels, settings, stats.logAverage());
}

}  // namespace glint
