// glint — writing a Film: scene-linear EXR, or display-referred PNG/JPEG/TIFF; always atomic.
#include "renderer/output.h"

#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <vector>

#include "renderer/color.h"
#include "renderer/tonemap.h"

namespace fs = std::filesystem;

namespace glint {

namespace {

enum class Format { Exr, Png, Jpeg, Tiff, Unknown };

std::string lowerExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

Format formatOf(const std::string& path) {
  std::string ext = lowerExtension(path);
  if (ext == ".exr") return Format::Exr;
  if (ext == ".png") return Format::Png;
  if (ext == ".jpg" || ext == ".jpeg") return Format::Jpeg;
  if (ext == ".tif" || ext == ".tiff") return Format::Tiff;
  return Format::Unknown;
}

// ---- pixels ----------------------------------------------------------------------------------

// An interleaved float buffer and the spec it is written with.
struct Image {
  OIIO::ImageSpec spec;
  std::vector<float> pixels;
};

void addMetadata(OIIO::ImageSpec& spec, const ImageMetadata& meta) {
  spec.attribute("Software", "glint");
  spec.attribute("glint:scene", meta.scene);
  spec.attribute("glint:spp", meta.spp);
  spec.attribute("glint:seed", std::to_string(meta.seed));  // 64-bit: no EXR integer holds it
  double seconds = meta.renderSeconds;
  spec.attribute("glint:render_seconds", OIIO::TypeDesc::DOUBLE, &seconds);
  spec.attribute("glint:accel", meta.accel);
  spec.attribute("glint:integrator", meta.integrator);
}

// Scene-linear RGBA (+ AOVs): what a compositor wants, untouched by display settings.
Image exrImage(const Film& film, const RenderSettings& settings) {
  std::vector<std::string> names = {"R", "G", "B", "A"};
  if (film.hasAovs) {
    names.insert(names.end(), {"albedo.R", "albedo.G", "albedo.B", "N.X", "N.Y", "N.Z", "Z",
                               "variance.R", "variance.G", "variance.B"});
  }
  const int nch = int(names.size());
  Image img;
  img.spec = OIIO::ImageSpec(film.width, film.height, nch,
                             settings.exrHalf ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
  img.spec.channelnames = names;
  img.spec.alpha_channel = 3;
  if (film.hasAovs) {
    img.spec.z_channel = 10;
    if (settings.exrHalf) {
      // Depth keeps float: half has 11 bits of mantissa and tops out at 65504.
      img.spec.channelformats.assign(size_t(nch), OIIO::TypeDesc::HALF);
      img.spec.channelformats[10] = OIIO::TypeDesc::FLOAT;
    }
  }
  img.spec.attribute("compression", "zip");

  const size_t n = size_t(film.width) * size_t(film.height);
  img.pixels.resize(n * size_t(nch));
  for (size_t i = 0; i < n; ++i) {
    float* p = &img.pixels[i * size_t(nch)];
    *p++ = film.color[i].x, *p++ = film.color[i].y, *p++ = film.color[i].z;
    *p++ = film.alpha[i];
    if (!film.hasAovs) continue;
    *p++ = film.albedo[i].x, *p++ = film.albedo[i].y, *p++ = film.albedo[i].z;
    *p++ = film.normal[i].x, *p++ = film.normal[i].y, *p++ = film.normal[i].z;
    *p++ = film.depth[i];
    *p++ = film.variance[i].x, *p++ = film.variance[i].y, *p++ = film.variance[i].z;
  }
  return img;
}

// Display-referred RGB: exposure, tone mapping, then the OCIO display/view transform.
Image displayImage(const Film& film, const RenderSettings& settings, Format format) {
  std::vector<Rgb> color = film.color;
  toneMap(color, settings.tonemap);

  Image img;
  img.pixels.resize(color.size() * 3);
  for (size_t i = 0; i < color.size(); ++i) {
    img.pixels[3 * i + 0] = color[i].x;
    img.pixels[3 * i + 1] = color[i].y;
    img.pixels[3 * i + 2] = color[i].z;
  }
  applyDisplayView(img.pixels, settings.tonemap.display, settings.tonemap.view);
  // OIIO clamps to [0, 1] and rounds when it quantizes; NaN has no defined conversion.
  for (float& v : img.pixels)
    if (std::isnan(v)) v = 0;

  img.spec =
      OIIO::ImageSpec(film.width, film.height, 3,
                      format == Format::Tiff ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8);
  return img;
}

// ---- atomic write ----------------------------------------------------------------------------

// Removes the temporary file unless the write got as far as the rename.
struct TempFile {
  fs::path path;
  bool keep = false;
  ~TempFile() {
    std::error_code ec;
    if (!keep) fs::remove(path, ec);
  }
};

fs::path temporaryPath(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  // Same folder (so the rename is atomic), hidden, and keeping the extension that selects the
  // format.
  std::string name = fmt::format(".{}.tmp-{}-{}{}", target.stem().string(), ::getpid(),
                                 counter.fetch_add(1), target.extension().string());
  return target.parent_path() / name;
}

void syncFile(const fs::path& path) {
  int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0 || ::fsync(fd) != 0) {
    int err = errno;
    if (fd >= 0) ::close(fd);
    throw OutputError(fmt::format("cannot write '{}': {}", path.string(), std::strerror(err)));
  }
  ::close(fd);
}

void writeAtomically(const std::string& target, Image& img) {
  TempFile temp{temporaryPath(fs::path(target))};
  auto fail = [&](const std::string& why) {
    return OutputError(fmt::format("cannot write '{}': {}", target, why));
  };

  auto out = OIIO::ImageOutput::create(target);
  if (!out) throw fail(OIIO::geterror());
  if (!out->open(temp.path.string(), img.spec)) throw fail(out->geterror());
  if (!out->write_image(OIIO::TypeDesc::FLOAT, img.pixels.data())) {
    std::string why = out->geterror();
    out->close();
    throw fail(why);
  }
  if (!out->close()) throw fail(out->geterror());
  out.reset();
  syncFile(temp.path);

  std::error_code ec;
  fs::rename(temp.path, target, ec);
  if (ec) throw fail(ec.message());
  temp.keep = true;
}

}  // namespace

// ---- public API ------------------------------------------------------------------------------

bool isSupportedOutput(const std::string& path, std::string* why) {
  if (formatOf(path) != Format::Unknown) return true;
  if (why) {
    std::string ext = fs::path(path).extension().string();
    *why = fmt::format("'{}': {}; glint writes .exr, .png, .jpg/.jpeg and .tif/.tiff", path,
                       ext.empty() ? std::string("no file extension")
                                   : fmt::format("unsupported image format '{}'", ext));
  }
  return false;
}

void writeImage(const std::string& path, const Film& film, const RenderSettings& settings,
                const ImageMetadata& meta) {
  Format format = formatOf(path);
  std::string why;
  if (format == Format::Unknown) {
    isSupportedOutput(path, &why);
    throw OutputError(why);
  }
  if (film.width <= 0 || film.height <= 0)
    throw OutputError(fmt::format("cannot write '{}': the image is empty", path));
  const size_t n = size_t(film.width) * size_t(film.height);
  assert(film.color.size() == n && film.alpha.size() == n);
  assert(!film.hasAovs || (film.albedo.size() == n && film.normal.size() == n &&
                           film.depth.size() == n && film.variance.size() == n));
  (void)n;

  // Pixels first (colour errors are bad input, not a failed write); then the file system.
  Image img =
      format == Format::Exr ? exrImage(film, settings) : displayImage(film, settings, format);
  addMetadata(img.spec, meta);
  writeAtomically(path, img);
}

}  // namespace glint
