// glint — the OpenImageIO plugin: every use glint makes of OpenImageIO, in one shared module
// (libglint_oiio.so) that glint loads the first time it needs it.
//
// Why a plugin: libOpenImageIO pulls about 260 shared libraries into a process (FFmpeg, GDCM,
// LibRaw, OpenVDB, ...), and the dynamic loader's symbol lookups for them took 0.2 s of every
// glint start, as long as a small render. Most runs never need them: OpenEXR, the format
// glint renders to and reads back, goes through OpenEXR directly (image/exr.cpp). The plugin
// serves what only OpenImageIO does well: the other image formats (PNG, JPEG, TIFF, HDR, ...),
// the texture cache with its MIP maps and filtered lookups, and idiff's comparison.
//
// Both sides are built together from this tree by the same compiler, so the interface is plain
// C++ (strings, vectors, glint's own structs); only the entry point is extern "C". Errors come
// back as text or as std::runtime_error / std::logic_error (whose type information lives in
// libstdc++, shared by both sides); glint's own exception types are thrown on glint's side
// (the texture half's reasons become InputErrors naming the file in materials' TextureImages).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "image/io.h"
#include "materials/image_texture.h"

namespace glint::oiio {

// idiff's comparison of two images of the same size and channel count (ImageBufAlgo::compare),
// plus the mean relative MSE over the channels.
struct CompareStats {
  double meanError = 0, rmsError = 0, maxError = 0;
  int maxX = 0, maxY = 0, maxChannel = -1;
  uint64_t failPixels = 0, warnPixels = 0;
  double relMse = 0;
  std::string error;  // set when the comparison itself failed
};

// It is also the decoder of the texture images materials keep (materials' ImageDecoder: the
// scene builder hands it to TextureImages, materials never name the plugin).
class Plugin : public ImageDecoder {
 public:
  // Reads an image file in any format OpenImageIO reads into `image` (format, windows, channel
  // names and types, glint's attributes; the pixels too when `pixels`). On failure returns
  // false with the decoder's message in *why and whether the header had been read.
  virtual bool readImage(const std::string& path, bool pixels, Image* image, std::string* why,
                         bool* afterHeader) const = 0;
  // Writes `image` to `file`, in the format of `formatPath`'s extension (PNG, JPEG, TIFF), with
  // its channel names, glint's attributes when image.hasMeta, and Software "glint". Returns
  // false with the reason in *why.
  virtual bool writeImage(const std::string& file, const std::string& formatPath,
                          const Image& image, std::string* why) const = 0;

  // `a` and `b`: width × height pixels of `channels` floats each.
  virtual CompareStats compare(const std::vector<float>& a, const std::vector<float>& b, int width,
                               int height, int channels, float failThreshold,
                               float warnThreshold) const = 0;
};

// The plugin, loaded on first use (thread-safe). Looked for as $GLINT_OIIO_PLUGIN when set,
// else beside the running executable, in ../lib/glint/ from it, and in the build tree it was
// built in. Throws FailureError (exit code 1) naming the places tried when it cannot be loaded.
const Plugin& plugin();
// The same, as the source of a TextureImages' decoder.
inline const ImageDecoder& imageDecoder() { return plugin(); }

// The entry point the module exports: a function returning its one Plugin.
inline constexpr const char* kEntryPoint = "glint_oiio_plugin";
using EntryPoint = const Plugin* (*)();

}  // namespace glint::oiio
