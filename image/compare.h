// glint — comparing two image files as `glint diff` does: idiff's thresholds or the statistical
// z-tests (image/diff.h, image/statistical.h), optionally FLIP (image/flip.h), and the figures
// as the JSON `glint diff --json` prints. The command line prints them; the Python module
// returns them.
#pragma once

#include <limits>
#include <optional>
#include <string>

#include "image/diff.h"
#include "image/flip.h"
#include "image/statistical.h"

namespace glint {

struct CompareOptions {
  std::string a, b;
  DiffThresholds thresholds;
  bool statistical = false;
  StatisticalThresholds statistics;
  std::string heatMap;  // statistical mode: where to write the |z| heat map
  bool flip = false;    // also compute FLIP
  double pixelsPerDegree = kFlipDefaultPixelsPerDegree;
  double flipMax = std::numeric_limits<double>::infinity();  // fail above this mean FLIP
  std::string flipMap;                                       // where to write FLIP's error map
};

// FLIP of `a` against reference `b`: LDR-FLIP for two display-encoded images (PNG, JPEG, 8/16-bit
// TIFF), HDR-FLIP for two scene-linear ones (EXR).
struct FlipReport {
  bool hdr = false;
  FlipResult result;
};

// What a comparison found: the plain or the statistical result, and FLIP's when asked for (a
// FLIP map or limit asks for it too). A mean FLIP above flipMax has made the verdict Fail.
struct Comparison {
  std::optional<DiffResult> plain;
  std::optional<StatisticalResult> statistical;
  std::optional<FlipReport> flip;
  DiffVerdict verdict() const { return plain ? plain->verdict : statistical->verdict; }
  bool differ() const { return verdict() == DiffVerdict::Fail; }  // a warning passes
};

// Compares image `o.a` against reference `o.b` and writes the maps asked for. Throws
// ImageReadError for an unreadable image, OutputError for a map that cannot be written.
Comparison compareImages(const CompareOptions& o);

// The figures of `c` as `glint diff --json` prints them (JSON text, indented by 2).
std::string comparisonJson(const CompareOptions& o, const Comparison& c);

}  // namespace glint
