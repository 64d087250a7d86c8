// glint — `glint render --resume`: whether an output of an earlier run is complete.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "renderer/film.h"

namespace glint::app {

// What a finished output of one render must show: `glint render --resume` skips a frame only
// when every output passes.
struct ExpectedImage {
  int fullWidth = 0, fullHeight = 0;          // the whole frame
  int x0 = 0, y0 = 0, width = 0, height = 0;  // the pixels this render wrote (crop or tile)
  std::string scene;  // compared by file name: the path may be spelled differently
  int spp = 0;        // without a budget: the spp a complete output has; with one: the cap
  uint64_t seed = 0;
  double time = 0;
  // A budgeted render (--time-limit, --noise-target) is complete when it stopped on its own
  // (not interrupted) and, with a noise target, reached it or the spp cap.
  bool budget = false;
  double noiseTarget = 0;
};

// Empty when `path` is a complete output of the render `expected` describes; else why not:
// exactly "missing" when there is no file, else e.g. "cannot read its pixels: ...", "its pixels
// do not match glint:checksum", "rendered with 4 spp, not 16". An EXR must
// decode, carry glint's metadata for that render and match the checksum of its pixel values
// (glint:checksum, written with every EXR); a PNG, JPEG or TIFF must decode at the expected size
// (PNG checks its own CRC-32 per chunk; these formats cannot carry glint's numeric metadata).
// An interrupted or stopped-early render is incomplete ("interrupted at 48 spp").
std::string whyIncomplete(const std::string& path, const ExpectedImage& expected);

// An EXR output of an earlier run of this render (same frame, window, scene, seed and time,
// checksum intact, float) that stopped below the spp asked for now, with what continuing it
// needs: its film (mean, variance, per-pixel samples, AOVs), spp and render time.
struct PartialRender {
  std::string path;
  Film film;
  uint32_t spp = 0;
  double seconds = 0;
  std::string integrator;
};

// The partial render in `path` that `expected` can continue, or nullopt with the reason in
// *whyNot ("missing", "rendered with 64 spp, not below 16", ...).
std::optional<PartialRender> continuableRender(const std::string& path,
                                               const ExpectedImage& expected, std::string* whyNot);

}  // namespace glint::app
