// glint — `glint render --resume`: whether an output of an earlier run is complete.
#pragma once

#include <cstdint>
#include <string>

namespace glint::app {

// What a finished output of one render must show: `glint render --resume` skips a frame only
// when every output passes.
struct ExpectedImage {
  int fullWidth = 0, fullHeight = 0;          // the whole frame
  int x0 = 0, y0 = 0, width = 0, height = 0;  // the pixels this render wrote (crop or tile)
  std::string scene;  // compared by file name: the path may be spelled differently
  int spp = 0;
  uint64_t seed = 0;
  double time = 0;
};

// Empty when `path` is a complete output of the render `expected` describes; else why not:
// exactly "missing" when there is no file, else e.g. "cannot read its pixels: ...", "its pixels
// do not match glint:checksum", "rendered with 4 spp, not 16". An EXR must
// decode, carry glint's metadata for that render and match the checksum of its pixel values
// (glint:checksum, written with every EXR); a PNG, JPEG or TIFF must decode at the expected size
// (PNG checks its own CRC-32 per chunk; these formats cannot carry glint's numeric metadata).
std::string whyIncomplete(const std::string& path, const ExpectedImage& expected);

}  // namespace glint::app
