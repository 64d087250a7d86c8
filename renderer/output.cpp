// glint — writing a Film: scene-linear EXR, or display-referred PNG/JPEG/TIFF; always atomic.
#include "renderer/output.h"

#include <Imath/half.h>
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
#include <cstdlib>
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
  double time = meta.time;
  spec.attribute("glint:time", OIIO::TypeDesc::DOUBLE, &time);
}

// glint's attributes of an image (what addMetadata wrote); absent ones keep their defaults.
ImageMetadata metadataOf(const OIIO::ImageSpec& spec) {
  ImageMetadata meta;
  meta.scene = spec.get_string_attribute("glint:scene");
  meta.spp = spec.get_int_attribute("glint:spp");
  meta.seed = std::strtoull(spec.get_string_attribute("glint:seed", "0").c_str(), nullptr, 10);
  meta.renderSeconds = spec.get_float_attribute("glint:render_seconds");
  meta.accel = spec.get_string_attribute("glint:accel");
  meta.integrator = spec.get_string_attribute("glint:integrator");
  if (const OIIO::ParamValue* t = spec.find_attribute("glint:time", OIIO::TypeDesc::DOUBLE))
    meta.time = t->get<double>();
  return meta;
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
  // A crop is the data window of the whole frame (the display window).
  img.spec.x = film.originX, img.spec.y = film.originY;
  img.spec.full_x = 0, img.spec.full_y = 0;
  img.spec.full_width = film.fullWidth, img.spec.full_height = film.fullHeight;
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
  // Round half channels here rather than in OIIO's conversion, so the checksum is of the
  // values the file holds (the rounding is the same: Imath's, to nearest even).
  if (settings.exrHalf)
    for (size_t i = 0; i < img.pixels.size(); ++i)
      if (int(i % size_t(nch)) != img.spec.z_channel)  // depth stays float
        img.pixels[i] = float(Imath::half(img.pixels[i]));
  img.spec.attribute("glint:checksum", pixelChecksum(img.pixels, img.spec.channelnames));
  return img;
}

// Display-referred RGB: exposure, tone mapping with the scale `logAverageLuminance` gives, then
// the OCIO display/view transform.
Image displayImage(const Film& film, const ToneMapSettings& tonemap, double logAverageLuminance,
                   Format format) {
  std::vector<Rgb> color = film.color;
  applyToneMap(color, tonemap, logAverageLuminance);

  Image img;
  img.pixels.resize(color.size() * 3);
  for (size_t i = 0; i < color.size(); ++i) {
    img.pixels[3 * i + 0] = color[i].x;
    img.pixels[3 * i + 1] = color[i].y;
    img.pixels[3 * i + 2] = color[i].z;
  }
  applyDisplayView(img.pixels, tonemap.display, tonemap.view);
  // OIIO clamps to [0, 1] and rounds when it quantizes; NaN has no defined conversion.
  for (float& v : img.pixels)
    if (std::isnan(v)) v = 0;

  img.spec =
      OIIO::ImageSpec(film.width, film.height, 3,
                      format == Format::Tiff ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8);
  return img;
}

// Checks what writeImage and writeDisplayImage check before any pixel work.
Format checkedFormat(const std::string& path, const Film& film) {
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
  return format;
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

void assembleExr(const std::vector<std::string>& pieces, const std::string& output) {
  if (pieces.empty()) throw ImageReadError("assemble: no input images");
  Image whole;
  std::vector<uint8_t> covered;
  double seconds = 0;
  int nch = 0;
  for (const std::string& path : pieces) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw ImageReadError(fmt::format("{}: cannot read: {}", path, OIIO::geterror()));
    const OIIO::ImageSpec spec = in->spec();
    std::vector<float> px(size_t(spec.image_pixels()) * size_t(spec.nchannels));
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()))
      throw ImageReadError(fmt::format("{}: cannot read: {}", path, in->geterror()));
    if (spec.full_x != 0 || spec.full_y != 0 || spec.full_width <= 0 || spec.full_height <= 0)
      throw ImageReadError(fmt::format("{}: its display window does not start at 0,0", path));
    seconds += spec.get_float_attribute("glint:render_seconds");
    if (covered.empty()) {
      whole.spec = spec;
      whole.spec.x = whole.spec.y = 0;
      whole.spec.width = spec.full_width, whole.spec.height = spec.full_height;
      nch = spec.nchannels;
      covered.assign(size_t(spec.full_width) * size_t(spec.full_height), 0);
      whole.pixels.assign(covered.size() * size_t(nch), 0.0f);
    } else {
      const OIIO::ImageSpec& first = whole.spec;
      if (spec.full_width != first.full_width || spec.full_height != first.full_height)
        throw ImageReadError(fmt::format("{}: a piece of a {}x{} frame, not {}x{} like {}", path,
                                         spec.full_width, spec.full_height, first.full_width,
                                         first.full_height, pieces.front()));
      if (spec.channelnames != first.channelnames)
        throw ImageReadError(
            fmt::format("{}: its channels differ from {}'s", path, pieces.front()));
      const auto attribute = [](const OIIO::ImageSpec& s, const char* key) {
        const OIIO::ParamValue* p = s.find_attribute(key);
        return p ? s.metadata_val(*p) : std::string("(none)");
      };
      for (const char* key :
           {"glint:scene", "glint:spp", "glint:seed", "glint:integrator", "glint:time"})
        if (attribute(spec, key) != attribute(first, key))
          throw ImageReadError(fmt::format("{}: {} is {}, but {} in {}: not the same render", path,
                                           key, attribute(spec, key), attribute(first, key),
                                           pieces.front()));
    }
    if (spec.x < 0 || spec.y < 0 || spec.x + spec.width > whole.spec.width ||
        spec.y + spec.height > whole.spec.height)
      throw ImageReadError(fmt::format("{}: its data window leaves the frame", path));
    for (int y = 0; y < spec.height; ++y)
      for (int x = 0; x < spec.width; ++x) {
        const size_t to = size_t(spec.y + y) * size_t(whole.spec.width) + size_t(spec.x + x);
        if (covered[to])
          throw ImageReadError(fmt::format("{}: pixel {},{} is also in an earlier piece", path,
                                           spec.x + x, spec.y + y));
        covered[to] = 1;
        const float* from = &px[(size_t(y) * size_t(spec.width) + size_t(x)) * size_t(nch)];
        std::copy(from, from + nch, &whole.pixels[to * size_t(nch)]);
      }
  }
  const size_t missing = size_t(std::count(covered.begin(), covered.end(), uint8_t(0)));
  if (missing > 0) {
    const size_t first =
        size_t(std::find(covered.begin(), covered.end(), uint8_t(0)) - covered.begin());
    throw ImageReadError(
        fmt::format("assemble: {} pixel{} of the {}x{} frame in no piece (the "
                    "first at {},{})",
                    missing, missing == 1 ? "" : "s", whole.spec.width, whole.spec.height,
                    first % size_t(whole.spec.width), first / size_t(whole.spec.width)));
  }
  whole.spec.attribute("glint:render_seconds", OIIO::TypeDesc::DOUBLE, &seconds);
  // Read back as float, every value is exactly what the pieces stored: the same checksum as
  // the frame rendered whole.
  whole.spec.attribute("glint:checksum", pixelChecksum(whole.pixels, whole.spec.channelnames));
  writeAtomically(output, whole);
}

std::string pixelChecksum(const std::vector<float>& pixels,
                          const std::vector<std::string>& channelNames) {
  uint64_t hash = 0xcbf29ce484222325ull;  // FNV-1a offset basis
  const auto mix = [&](uint8_t byte) {
    hash ^= byte;
    hash *= 0x100000001b3ull;
  };
  const size_t nch = channelNames.size();
  std::vector<size_t> order(nch);
  for (size_t c = 0; c < nch; ++c) order[c] = c;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return channelNames[a] < channelNames[b]; });
  for (size_t c : order) {
    for (char ch : channelNames[c]) mix(uint8_t(ch));
    mix(0);
    for (size_t i = c; i < pixels.size(); i += nch) {
      uint32_t bits;
      std::memcpy(&bits, &pixels[i], sizeof bits);
      for (int byte = 0; byte < 4; ++byte) mix(uint8_t(bits >> (8 * byte)));  // little-endian
    }
  }
  return fmt::format("{:016x}", hash);
}

std::string whyIncomplete(const std::string& path, const ExpectedImage& expected) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return "missing";
  if (!fs::is_regular_file(path, ec)) return "not a regular file";
  auto in = OIIO::ImageInput::open(path);
  if (!in) return "cannot read: " + OIIO::geterror();
  const OIIO::ImageSpec spec = in->spec();
  const bool exr = formatOf(path) == Format::Exr;
  if (exr != (std::string(in->format_name()) == "openexr"))
    return fmt::format("holds a {} image", in->format_name());
  if (exr) {
    if (spec.full_width != expected.fullWidth || spec.full_height != expected.fullHeight)
      return fmt::format("a {}x{} frame, not {}x{}", spec.full_width, spec.full_height,
                         expected.fullWidth, expected.fullHeight);
    if (spec.x != expected.x0 || spec.y != expected.y0 || spec.width != expected.width ||
        spec.height != expected.height)
      return fmt::format("holds pixels {},{}..{},{}, not {},{}..{},{}", spec.x, spec.y,
                         spec.x + spec.width, spec.y + spec.height, expected.x0, expected.y0,
                         expected.x0 + expected.width, expected.y0 + expected.height);
    const ImageMetadata meta = metadataOf(spec);
    const std::string scene = fs::path(meta.scene).filename();
    const std::string expectedScene = fs::path(expected.scene).filename();
    if (scene != expectedScene)
      return fmt::format("a render of '{}', not '{}'", scene, expectedScene);
    if (meta.spp != expected.spp)
      return fmt::format("rendered with {} spp, not {}", meta.spp, expected.spp);
    if (!spec.find_attribute("glint:seed"))
      return fmt::format("rendered with seed (none), not {}", expected.seed);
    if (meta.seed != expected.seed)
      return fmt::format("rendered with seed {}, not {}", meta.seed, expected.seed);
    if (!spec.find_attribute("glint:time", OIIO::TypeDesc::DOUBLE))
      return "no glint:time (written by an older glint)";
    if (meta.time != expected.time)
      return fmt::format("the frame at time {} s, not {} s", meta.time, expected.time);
  } else if (spec.width != expected.width || spec.height != expected.height) {
    return fmt::format("{}x{} pixels, not {}x{}", spec.width, spec.height, expected.width,
                       expected.height);
  }
  std::vector<float> pixels(size_t(spec.image_pixels()) * size_t(spec.nchannels));
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data()))
    return "cannot read its pixels: " + in->geterror();
  if (exr) {
    const std::string stored = spec.get_string_attribute("glint:checksum");
    if (stored.empty()) return "no glint:checksum (written by an older glint)";
    if (stored != pixelChecksum(pixels, spec.channelnames))
      return "its pixels do not match glint:checksum";
  }
  return "";
}

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
  Format format = checkedFormat(path, film);
  // Pixels first (colour errors are bad input, not a failed write); then the file system.
  Image img;
  if (format == Format::Exr) {
    img = exrImage(film, settings);
  } else {
    LogLuminanceStats stats;
    if (settings.tonemap.op == "ward") stats.add(film.color, settings.tonemap);
    img = displayImage(film, settings.tonemap, stats.logAverage(), format);
  }
  addMetadata(img.spec, meta);
  writeAtomically(path, img);
}

void writeDisplayImage(const std::string& path, const Film& film, const ToneMapSettings& tonemap,
                       double logAverageLuminance, const ImageMetadata& meta) {
  Format format = checkedFormat(path, film);
  if (format == Format::Exr)
    throw OutputError(fmt::format(
        "cannot write '{}': tone-mapped output is display-referred (.png, .jpg, .tif); EXR "
        "stays scene-linear",
        path));
  Image img = displayImage(film, tonemap, logAverageLuminance, format);
  addMetadata(img.spec, meta);
  writeAtomically(path, img);
}

void writeRawImage(const std::string& path, int width, int height, int channels,
                   const std::vector<float>& pixels) {
  Format format = formatOf(path);
  std::string why;
  if (format == Format::Unknown) {
    isSupportedOutput(path, &why);
    throw OutputError(why);
  }
  if (width <= 0 || height <= 0 || channels <= 0 ||
      pixels.size() != size_t(width) * size_t(height) * size_t(channels))
    throw OutputError(fmt::format("cannot write '{}': the image is empty", path));
  Image img;
  img.pixels = pixels;
  img.spec = OIIO::ImageSpec(width, height, channels,
                             format == Format::Exr    ? OIIO::TypeDesc::FLOAT
                             : format == Format::Tiff ? OIIO::TypeDesc::UINT16
                                                      : OIIO::TypeDesc::UINT8);
  img.spec.attribute("Software", "glint");
  writeAtomically(path, img);
}

Film readExr(const std::string& path, ImageMetadata* meta) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw ImageReadError(fmt::format("{}: no such file", path));
  if (fs::is_directory(path, ec))
    throw ImageReadError(fmt::format("{}: is a folder, not an image", path));
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw ImageReadError(fmt::format("{}: {}", path, OIIO::geterror()));
  const OIIO::ImageSpec& spec = in->spec();
  if (std::string(in->format_name()) != "openexr")
    throw ImageReadError(fmt::format("{}: is not an OpenEXR image ({})", path, in->format_name()));
  int r = spec.channelindex("R"), g = spec.channelindex("G"), b = spec.channelindex("B");
  int a = spec.channelindex("A");
  if (r < 0 || g < 0 || b < 0)
    throw ImageReadError(fmt::format("{}: has no R, G, B channels", path));
  if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1)
    throw ImageReadError(fmt::format("{}: not a 2D image", path));

  const int nch = spec.nchannels;
  std::vector<float> pixels(size_t(spec.width) * size_t(spec.height) * size_t(nch));
  if (!in->read_image(0, 0, 0, nch, OIIO::TypeDesc::FLOAT, pixels.data()))
    throw ImageReadError(fmt::format("{}: {}", path, in->geterror()));
  if (meta) *meta = metadataOf(spec);
  in->close();

  Film film(spec.width, spec.height, false);
  for (size_t i = 0; i < film.color.size(); ++i) {
    const float* p = &pixels[i * size_t(nch)];
    film.color[i] = Rgb{p[r], p[g], p[b]};
    film.alpha[i] = a >= 0 ? p[a] : 1.0f;
  }
  return film;
}

}  // namespace glint
