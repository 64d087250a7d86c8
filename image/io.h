// glint — the one image reader and the one image writer. Every image glint reads (environment
// maps, diff, tonemap, assemble, --resume) goes through readImage; every image it writes goes
// through writeImageFile: atomically (temporary file, then rename), with glint's metadata, and
// an EXR with the checksum of its pixels. OpenEXR files go through the OpenEXR library
// (exr.h); every other format through OpenImageIO, in the plugin glint loads only when it needs
// it (oiio/plugin.h). Image textures are the exception: they are read by OIIO's TextureSystem
// (materials/image_texture.h), which needs its own tiled, MIP-mapped cache for filtered lookups.
#pragma once

#include <charconv>
#include <cstdint>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "geometry/error.h"

namespace glint {

// An image that cannot be read or used: missing or unreadable file, unsuitable contents
// (bad input, exit code 2). what() names the file.
class ImageReadError : public InputError {
 public:
  using InputError::InputError;
};

// A failure to write an image or file (disk full, unwritable folder): exit code 1.
class OutputError : public FailureError {
 public:
  using FailureError::FailureError;
};

// glint's attributes of a rendered image (glint:scene, glint:spp, ...).
struct ImageMetadata {
  std::string scene;  // the scene file
  int spp = 0;
  uint64_t seed = 0;
  double renderSeconds = 0;
  std::string accel;
  std::string integrator;
  double time = 0;  // the scene time of the frame, seconds
  // How the render ended (renderer/render.h StopReason: "spp", "time-limit", "noise-target",
  // "interrupted") and its estimated relative error; written only when `stop` is set.
  std::string stop;
  double error = 0;
};

// glint's attributes, listed once: the EXR reader and writer (exr.cpp) and the OpenImageIO
// plugin's (oiio/formats.cpp) walk this list, so an attribute is added here and in
// ImageMetadata and nowhere else. Calls f(name, field, whenStopped) for each field of `meta`
// (ImageMetadata or const ImageMetadata) by reference: std::string, int, uint64_t or double.
// Fields marked whenStopped (the stop reason and its error) are written only when `stop` is set.
template <class Meta, class F>
void forEachMetadataField(Meta& meta, F&& f) {
  f("glint:scene", meta.scene, false);
  f("glint:spp", meta.spp, false);
  f("glint:seed", meta.seed, false);  // 64-bit: written as text, as no EXR integer holds it
  f("glint:render_seconds", meta.renderSeconds, false);
  f("glint:accel", meta.accel, false);
  f("glint:integrator", meta.integrator, false);
  f("glint:time", meta.time, false);
  f("glint:stop", meta.stop, true);
  f("glint:error", meta.error, true);
}

// A field's value as text (a number in its shortest form that reads back to the same value),
// and back: how formats that keep attributes only as text store them (PNG's tEXt chunks, the
// description of a TIFF or JPEG). parseMetadataText is false, and leaves *value alone, when
// the whole text is not a value of that type. Inline: the OpenImageIO plugin uses them too.
inline std::string metadataText(const std::string& value) { return value; }
template <class Number>
std::string metadataText(Number value) {
  char text[32];
  const auto [end, ec] = std::to_chars(text, text + sizeof text, value);
  return ec == std::errc() ? std::string(text, end) : std::string();
}
inline bool parseMetadataText(const std::string& text, std::string* value) {
  *value = text;
  return true;
}
template <class Number>
bool parseMetadataText(const std::string& text, Number* value) {
  Number parsed{};
  const char* end = text.data() + text.size();
  const auto [stop, ec] = std::from_chars(text.data(), end, parsed);
  if (ec != std::errc() || stop != end || text.empty()) return false;
  *value = parsed;
  return true;
}

// How a file stores its pixel values.
enum class PixelType { UInt8, UInt16, Half, Float };

// A whole image as float: the data window's pixels, interleaved, with what the file says about
// them. What readImage returns and writeImageFile takes.
struct Image {
  int width = 0, height = 0, channels = 0;  // the data window (height · depth for volumes)
  std::vector<std::string> names;           // channel names, in file order
  std::vector<float> pixels;                // width · height · channels, row by row
  int x = 0, y = 0;                         // the data window's origin in the frame
  int fullX = 0, fullY = 0, fullWidth = 0, fullHeight = 0;  // the frame (display window)
  int depth = 1;  // > 1 only for volume images (never glint's)

  // Storage. Writing: the type of every channel, except that a Half image keeps its "Z"
  // channel in Float (half tops out at 65504). Reading: Half when any channel is half, else
  // the file's type (Float for any other floating-point or wider integer type).
  PixelType type = PixelType::Float;
  bool floatingPoint = false;  // read: stored as float or half (scene-linear), not as integers
  std::string format;          // read: OIIO's format name ("openexr", "png", ...)

  ImageMetadata meta;    // glint's attributes; defaults when absent
  bool hasMeta = false;  // write: add glint's attributes (meta)
  // Read only: which of glint's attributes the file has, their text (as EXR stores them, for
  // comparing two files), and the stored glint:checksum ("" when absent).
  bool hasSeed = false, hasTime = false;
  std::vector<std::pair<std::string, std::string>> glintAttributes;
  std::string checksum;

  int channel(const std::string& name) const {  // index, or -1 (inline: the plugin uses it)
    for (size_t c = 0; c < names.size(); ++c)
      if (names[c] == name) return int(c);
    return -1;
  }
  std::string attribute(const std::string& name) const;  // glint attribute text, or "(none)"
  size_t pixelCount() const { return size_t(width) * size_t(height); }
};

// readImage's failure to decode a file that exists: why() is the decoder's message alone;
// afterHeader() tells whether the header was read (then the pixels are at fault).
class DecodeError : public ImageReadError {
 public:
  DecodeError(const std::string& path, const std::string& why, bool afterHeader)
      : ImageReadError(path + ": " + why), why_(why), afterHeader_(afterHeader) {}
  const std::string& why() const { return why_; }
  bool afterHeader() const { return afterHeader_; }

 private:
  std::string why_;
  bool afterHeader_;
};

// Reads `path` (OpenEXR, known by its magic number, or any format OpenImageIO reads); with
// `pixels` false, everything but the pixels.
// Throws ImageReadError "<path>: no such file" or "<path>: is a folder, not an image", and
// DecodeError when the file does not decode.
Image readImage(const std::string& path, bool pixels = true);

// True when `path` has an extension glint can write (.exr, .png, .jpg/.jpeg, .tif/.tiff);
// otherwise sets *why. Checked before rendering so a typo costs nothing.
bool isSupportedOutput(const std::string& path, std::string* why);

// True when `path` names an OpenEXR (a TIFF) file by its extension.
bool isExrPath(const std::string& path);
bool isTiffPath(const std::string& path);

// Writes `image` to `path` (format by extension) through a temporary file in the same folder
// that is renamed over `path` only when complete: a failed write never leaves a half-written
// file or destroys a previous good image. An EXR keeps the data and display windows, is ZIP
// compressed and carries glint:checksum of its values (half channels rounded first, so the
// checksum is of what the file holds). Throws OutputError.
void writeImageFile(const std::string& path, Image image);

// The checksum glint:checksum holds: FNV-1a (64-bit) over each channel in the order of the
// names (as EXR stores them; readers may interleave them otherwise): the name, then the bits of
// its values row by row, as the file stores them (half channels rounded to half). 16 hex digits.
std::string pixelChecksum(const std::vector<float>& pixels,
                          const std::vector<std::string>& channelNames);

// The temporary file an image write is filling at this moment, or null: a signal handler that
// ends the process at once (a second Ctrl-C) removes it. Async-signal-safe.
const char* temporaryOutputInFlight();

}  // namespace glint
