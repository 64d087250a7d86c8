// glint — a Film to disk: scene-linear EXR, or display-referred PNG/JPEG/TIFF.
#include "image/output.h"

#include <fmt/format.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>
#include <vector>

#include "image/color.h"
#include "image/tonemap.h"

namespace glint {

namespace {

// Scene-linear RGBA, the variance of each pixel's mean, and the AOVs: what a compositor wants,
// untouched by display settings, and what `glint render --resume` needs to continue the render
// (with adaptive sampling, also each pixel's sample count).
Image exrImage(const Film& film, const RenderSettings& settings) {
  Image img;
  img.names = {"R", "G", "B", "A", "variance.R", "variance.G", "variance.B"};
  const bool samples = (settings.adaptive.threshold > 0 || settings.adaptive.contrast > 0) &&
                       film.samples.size() == film.color.size();
  if (samples) img.names.push_back("samples");
  if (film.hasAovs)
    img.names.insert(img.names.end(),
                     {"albedo.R", "albedo.G", "albedo.B", "N.X", "N.Y", "N.Z", "Z"});
  const int nch = int(img.names.size());
  img.width = film.width, img.height = film.height, img.channels = nch;
  img.type = settings.exrHalf ? PixelType::Half : PixelType::Float;  // depth ("Z") stays float
  // A crop is the data window of the whole frame (the display window).
  img.x = film.originX, img.y = film.originY;
  img.fullWidth = film.fullWidth, img.fullHeight = film.fullHeight;

  const size_t n = size_t(film.width) * size_t(film.height);
  img.pixels.resize(n * size_t(nch));
  for (size_t i = 0; i < n; ++i) {
    float* p = &img.pixels[i * size_t(nch)];
    *p++ = film.color[i].x, *p++ = film.color[i].y, *p++ = film.color[i].z;
    *p++ = film.alpha[i];
    *p++ = film.variance[i].x, *p++ = film.variance[i].y, *p++ = film.variance[i].z;
    if (samples) *p++ = float(film.samples[i]);  // exact below 2^24
    if (!film.hasAovs) continue;
    *p++ = film.albedo[i].x, *p++ = film.albedo[i].y, *p++ = film.albedo[i].z;
    *p++ = film.normal[i].x, *p++ = film.normal[i].y, *p++ = film.normal[i].z;
    *p++ = film.depth[i];
  }
  return img;
}

// Display-referred RGB: exposure, tone mapping with the scale `logAverageLuminance` gives, then
// the OCIO display/view transform.
Image displayImage(const std::string& path, const Film& film, const ToneMapSettings& tonemap,
                   double logAverageLuminance) {
  Image img;
  img.width = film.width, img.height = film.height, img.channels = 3;
  img.pixels = displayPixels(film.color, tonemap, logAverageLuminance);
  img.type = isTiffPath(path) ? PixelType::UInt16 : PixelType::UInt8;
  return img;
}

// Checks what writeImage and writeDisplayImage check before any pixel work.
void checkWritable(const std::string& path, const Film& film) {
  std::string why;
  if (!isSupportedOutput(path, &why)) throw OutputError(why);
  if (film.width <= 0 || film.height <= 0)
    throw OutputError(fmt::format("cannot write '{}': the image is empty", path));
  const size_t n = size_t(film.width) * size_t(film.height);
  assert(film.color.size() == n && film.alpha.size() == n);
  assert(!film.hasAovs || (film.albedo.size() == n && film.normal.size() == n &&
                           film.depth.size() == n && film.variance.size() == n));
  (void)n;
}

}  // namespace

std::vector<float> displayPixels(std::span<const Rgb> sceneLinear, const ToneMapSettings& tonemap,
                                 double logAverageLuminance) {
  std::vector<Rgb> color(sceneLinear.begin(), sceneLinear.end());
  applyToneMap(color, tonemap, logAverageLuminance);
  std::vector<float> pixels(color.size() * 3);
  for (size_t i = 0; i < color.size(); ++i) {
    pixels[3 * i + 0] = color[i].x;
    pixels[3 * i + 1] = color[i].y;
    pixels[3 * i + 2] = color[i].z;
  }
  applyDisplayView(pixels, tonemap.display, tonemap.view);
  // OIIO clamps to [0, 1] and rounds when it quantizes; NaN has no defined conversion.
  for (float& v : pixels)
    if (std::isnan(v)) v = 0;
  return pixels;
}

ImageMetadata renderMetadata(const std::string& scene, const RenderSettings& settings,
                             const std::string& integrator, const ProgressiveResult& result,
                             double seconds) {
  ImageMetadata meta{scene, int(result.spp), settings.seed, seconds, settings.accel, integrator};
  meta.time = settings.time;
  meta.stop = std::string(stopReasonName(result.reason));
  meta.error = result.error;
  return meta;
}

void writeImage(const std::string& path, const Film& film, const RenderSettings& settings,
                const ImageMetadata& meta) {
  checkWritable(path, film);
  // Pixels first (colour errors are bad input, not a failed write); then the file system.
  Image img;
  if (isExrPath(path)) {
    img = exrImage(film, settings);
  } else {
    LogLuminanceStats stats;
    if (settings.tonemap.op == "ward") stats.add(film.color, settings.tonemap);
    img = displayImage(path, film, settings.tonemap, stats.logAverage());
  }
  img.meta = meta, img.hasMeta = true;
  writeImageFile(path, std::move(img));
}

void writeDisplayImage(const std::string& path, const Film& film, const ToneMapSettings& tonemap,
                       double logAverageLuminance, const ImageMetadata& meta) {
  checkWritable(path, film);
  if (isExrPath(path))
    throw OutputError(fmt::format(
        "cannot write '{}': tone-mapped output is display-referred (.png, .jpg, .tif); EXR "
        "stays scene-linear",
        path));
  Image img = displayImage(path, film, tonemap, logAverageLuminance);
  img.meta = meta, img.hasMeta = true;
  writeImageFile(path, std::move(img));
}

void writeRawImage(const std::string& path, int width, int height, int channels,
                   const std::vector<float>& pixels) {
  Image img;
  img.width = width, img.height = height, img.channels = channels;
  img.pixels = pixels;
  img.type = isExrPath(path)    ? PixelType::Float
             : isTiffPath(path) ? PixelType::UInt16
                                : PixelType::UInt8;
  writeImageFile(path, std::move(img));
}

}  // namespace glint
