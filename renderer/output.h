// glint — writing a Film to disk: scene-linear EXR, or display-referred PNG/JPEG/TIFF through
// exposure, tone mapping and an OpenColorIO display/view transform. Writes are atomic.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "renderer/film.h"
#include "renderer/image_diff.h"
#include "renderer/settings.h"

namespace glint {

struct ImageMetadata {
  std::string scene;  // the scene file
  int spp = 0;
  uint64_t seed = 0;
  double renderSeconds = 0;
  std::string accel;
  std::string integrator;
  double time = 0;  // the scene time of the frame, seconds
};

// A failure to write an image (disk full, unwritable folder): exit code 1.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// True when `path` has an extension glint can write (.exr, .png, .jpg/.jpeg, .tif/.tiff);
// otherwise sets *why. Checked before rendering so a typo costs nothing.
bool isSupportedOutput(const std::string& path, std::string* why);

// Writes `film` to `path` (format by extension). The data goes to a temporary file in the same
// folder that is renamed over `path` only when complete: a failed write never leaves a
// half-written file or destroys a previous good image. Throws OutputError.
void writeImage(const std::string& path, const Film& film, const RenderSettings& settings,
                const ImageMetadata& meta);

// Writes a display-referred image (PNG/JPEG/TIFF) of `film`, tone-mapped with the scale that
// `logAverageLuminance` gives (toneMapScale) instead of the film's own statistic: how every
// frame of a sequence shares one Ward scale. Atomic like writeImage. Throws OutputError (also
// for an .exr path: EXR stays scene-linear) or ColorError.
void writeDisplayImage(const std::string& path, const Film& film, const ToneMapSettings& tonemap,
                       double logAverageLuminance, const ImageMetadata& meta);

// Writes `channels` interleaved float channels per pixel as they are (no colour transform; PNG,
// JPEG and TIFF quantize [0, 1]): images that are data, such as an error heat map. Atomic like
// writeImage. Throws OutputError.
void writeRawImage(const std::string& path, int width, int height, int channels,
                   const std::vector<float>& pixels);

// Stitches partial EXRs (each a data window of the same whole frame, as `glint render --crop`
// and `--tile` write them) into one EXR at `output`, written atomically. The pieces must agree
// on the frame size, the channels and glint's render metadata (scene, spp, seed, integrator),
// must not overlap, and must cover the whole frame; the result carries the first piece's
// attributes, with render seconds the sum of the pieces'. Pixel values are copied, never
// resampled, so an assembled frame is bit-identical to the frame rendered whole. Throws
// ImageReadError (an unreadable or inconsistent piece, a gap, an overlap) or OutputError.
void assembleExr(const std::vector<std::string>& pieces, const std::string& output);

// What a finished output of one render must show: `glint render --resume` skips a frame only
// when every output passes.
struct ExpectedImage {
  int fullWidth = 0, fullHeight = 0;  // the whole frame
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

// The checksum glint:checksum holds: FNV-1a (64-bit) over each channel in the order of the
// names (as EXR stores them; readers may interleave them otherwise): the name, then the bits of
// its values row by row, as the file stores them (half channels rounded to half). 16 hex digits.
std::string pixelChecksum(const std::vector<float>& pixels,
                          const std::vector<std::string>& channelNames);

// Reads a scene-linear EXR (the R, G, B channels, and A when present, else alpha 1) into a film
// without AOVs; fills *meta from glint's attributes when given. Throws ImageReadError naming
// the file when it is missing, unreadable or has no R, G, B channels.
Film readExr(const std::string& path, ImageMetadata* meta = nullptr);

}  // namespace glint
