// glint — comparing two image files (see compare.h).
#include "image/compare.h"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <vector>

#include "image/output.h"

namespace glint {

namespace {

std::vector<float> rgbOf(const Image& image, const std::string& path) {
  int r = image.channel("R"), g = image.channel("G"), b = image.channel("B");
  if (r < 0 || g < 0 || b < 0) {
    if (image.channels < 3) throw ImageReadError(fmt::format("{}: FLIP needs R, G, B", path));
    r = 0, g = 1, b = 2;
  }
  std::vector<float> rgb(size_t(image.width) * size_t(image.height) * 3);
  for (size_t i = 0; i < rgb.size() / 3; ++i) {
    const float* p = &image.pixels[i * size_t(image.channels)];
    rgb[3 * i] = p[r], rgb[3 * i + 1] = p[g], rgb[3 * i + 2] = p[b];
  }
  return rgb;
}

FlipReport flipImages(const CompareOptions& o, const Image& a, const Image& b) {
  if (a.floatingPoint != b.floatingPoint)
    throw ImageReadError(fmt::format(
        "{} vs {}: FLIP compares two display-encoded images (PNG, JPEG) or two scene-linear "
        "ones (EXR), not one of each",
        o.a, o.b));
  std::vector<float> rgbA = rgbOf(a, o.a), rgbB = rgbOf(b, o.b);
  FlipReport report;
  report.hdr = a.floatingPoint;
  if (report.hdr) {
    FlipHdrOptions options;
    options.pixelsPerDegree = o.pixelsPerDegree;
    report.result = flipHdr(rgbB, rgbA, a.width, a.height, options);
  } else {
    report.result = flipLdr(rgbB, rgbA, a.width, a.height, o.pixelsPerDegree);
  }
  if (!o.flipMap.empty())
    writeRawImage(o.flipMap, a.width, a.height, 3, flipHeatMap(report.result.error));
  return report;
}

nlohmann::ordered_json flipJson(const CompareOptions& o, const FlipReport& f) {
  const FlipStats& s = f.result.stats;
  nlohmann::ordered_json j;
  j["mode"] = f.hdr ? "hdr" : "ldr";
  j["pixels_per_degree"] = o.pixelsPerDegree;
  if (f.hdr)
    j["exposures"] = {{"start", f.result.exposures.start},
                      {"stop", f.result.exposures.stop},
                      {"count", f.result.exposures.count}};
  j["mean"] = s.mean;
  j["weighted_median"] = s.weightedMedian;
  j["weighted_quartiles"] = {s.weightedQuartile1, s.weightedQuartile3};
  j["percentile_95"] = s.percentile95;
  j["max"] = s.max;
  j["max_pixel"] = {s.maxX, s.maxY};
  j["max_mean_allowed"] = o.flipMax;  // null when there is no limit
  return j;
}

// What both modes report first: the files, the verdict and the sizes.
template <class Result>
nlohmann::ordered_json jsonHeader(const CompareOptions& o, const Result& r, const char* mode) {
  nlohmann::ordered_json j;
  j["a"] = o.a;
  j["b"] = o.b;
  if (mode) j["mode"] = mode;
  j["verdict"] = verdictName(r.verdict);
  j["pass"] = r.verdict != DiffVerdict::Fail;
  j["size_a"] = {r.widthA, r.heightA};
  j["size_b"] = {r.widthB, r.heightB};
  j["size_mismatch"] = r.sizeMismatch;
  return j;
}

std::string diffJson(const CompareOptions& o, const DiffResult& r,
                     const std::optional<FlipReport>& flip) {
  nlohmann::ordered_json j = jsonHeader(o, r, nullptr);
  if (!r.sizeMismatch) {  // JSON has no infinity (PSNR of identical images): nlohmann writes null
    j["channels"] = r.channels;
    j["pixels"] = r.pixels;
    j["mean_abs_error"] = r.meanAbsError;
    j["rmse"] = r.rmse;
    j["rel_mse"] = r.relMse;
    j["psnr"] = r.psnr;
    j["max_error"] = r.maxError;
    j["max_pixel"] = {r.maxX, r.maxY};
    j["max_channel"] = r.maxChannel;
    j["fail_threshold"] = o.thresholds.fail;
    j["fail_percent_allowed"] = o.thresholds.failPercent;
    j["fail_pixels"] = r.failPixels;
    j["fail_pixel_percent"] = r.failPixelPercent;
    j["warn_threshold"] = o.thresholds.warn;
    j["warn_percent_allowed"] = o.thresholds.warnPercent;
    j["warn_pixels"] = r.warnPixels;
    j["warn_pixel_percent"] = r.warnPixelPercent;
  }
  if (flip) j["flip"] = flipJson(o, *flip);
  return j.dump(2);
}

std::string statisticalJson(const CompareOptions& o, const StatisticalResult& r,
                            const std::optional<FlipReport>& flip) {
  const StatisticalThresholds& t = o.statistics;
  nlohmann::ordered_json j = jsonHeader(o, r, "statistical");
  if (!r.sizeMismatch) {
    j["pixels"] = r.pixels;
    j["spp"] = {r.sppA, r.sppB};
    j["variance_model"] = r.varianceModel;
    j["significance"] = t.significance;
    j["pixel_z_limit"] = r.pixelZ;
    j["fail_pixels"] = r.failPixels;
    j["pass_percent"] = r.passPercent;
    j["min_pass_percent"] = t.minPassPercent;
    j["max_z"] = r.maxZ;
    j["max_z_pixel"] = {r.maxZX, r.maxZY};
    j["max_z_channel"] = r.maxZChannel;
    j["mean_z2"] = r.meanZ2;
    j["global_z"] = r.globalZ;
    j["global_z_limit"] = r.globalZLimit;
    j["biased"] = r.biased;
    j["max_error"] = r.maxError;
    j["max_error_pixel"] = {r.maxErrorX, r.maxErrorY};
    j["max_error_allowed"] = t.maxError;  // null when there is no cap
    j["error_cap_exceeded"] = r.errorCapExceeded;
    j["non_finite"] = r.nonFinite;
  }
  if (flip) j["flip"] = flipJson(o, *flip);
  return j.dump(2);
}

}  // namespace

Comparison compareImages(const CompareOptions& o) {
  // A FLIP map or limit asks for FLIP.
  const bool wantFlip = o.flip || !o.flipMap.empty() || std::isfinite(o.flipMax);
  Comparison c;
  bool sizeMismatch = false;
  if (!o.statistical) {
    c.plain = diffImages(o.a, o.b, o.thresholds);
    sizeMismatch = c.plain->sizeMismatch;
    // OpenImageIO's comparison read the files itself; FLIP reads them once more.
    if (wantFlip && !sizeMismatch) c.flip = flipImages(o, readImage(o.a), readImage(o.b));
  } else {
    const Image a = readImage(o.a), b = readImage(o.b);
    c.statistical = diffStatistical(a, o.a, b, o.b, o.statistics);
    sizeMismatch = c.statistical->sizeMismatch;
    if (!o.heatMap.empty() && !sizeMismatch) writeZHeatMap(o.heatMap, *c.statistical);
    if (wantFlip && !sizeMismatch) c.flip = flipImages(o, a, b);
  }
  // A mean FLIP above --flip-max fails a comparison that would otherwise pass.
  if (c.flip && c.flip->result.stats.mean > o.flipMax)
    (c.plain ? c.plain->verdict : c.statistical->verdict) = DiffVerdict::Fail;
  return c;
}

std::string comparisonJson(const CompareOptions& o, const Comparison& c) {
  return c.plain ? diffJson(o, *c.plain, c.flip) : statisticalJson(o, *c.statistical, c.flip);
}

}  // namespace glint
