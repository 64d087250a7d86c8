// glint — numeric comparison of two images (any format OpenImageIO reads), with idiff's
// pass/warn/fail rule: a comparison fails when more than failPercent % of the pixels have a
// channel whose absolute error exceeds `fail`; likewise for warnings.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "image/io.h"

namespace glint {

struct DiffThresholds {    // defaults as idiff's
  double fail = 1e-6;      // absolute error above which a pixel fails
  double failPercent = 0;  // ... and the comparison fails when more than this % of pixels do
  double warn = 1e-6;
  double warnPercent = 0;
};

enum class DiffVerdict { Pass, Warn, Fail };
const char* verdictName(DiffVerdict v);  // "pass" | "warn" | "fail"

struct DiffResult {
  int widthA = 0, heightA = 0, widthB = 0, heightB = 0;
  bool sizeMismatch = false;          // then no metric below was computed and verdict = Fail
  std::vector<std::string> channels;  // compared: R, G, B (A) when both have them
  uint64_t pixels = 0;
  double meanAbsError = 0;  // over pixels × channels
  double rmse = 0;
  double relMse = 0;  // mean of (a−b)² / (b² + 0.01); B is the reference
  double psnr = 0;    // 20·log10(1/RMSE) dB; +inf when identical
  double maxError = 0;
  int maxX = 0, maxY = 0;  // pixel of the largest error (image coordinates)
  std::string maxChannel;
  uint64_t failPixels = 0, warnPixels = 0;  // pixels with any channel error > threshold
  double failPixelPercent = 0, warnPixelPercent = 0;
  DiffVerdict verdict = DiffVerdict::Pass;
};

// Compares image `a` against reference `b`. Channels R, G, B (and A when both have it) are
// compared by name; images without named colour channels are compared position by position
// over the channels both have. Throws ImageReadError.
DiffResult diffImages(const std::string& a, const std::string& b, const DiffThresholds& t);

}  // namespace glint
