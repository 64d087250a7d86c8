// glint — the one image reader and the one atomic image writer, on OpenImageIO.
#include "image/io.h"

#include <Imath/half.h>
#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>

namespace fs = std::filesystem;

namespace glint {

namespace {

enum class Format { Exr, Png, Jpeg, Tiff, Unknown };

Format formatOf(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".exr") return Format::Exr;
  if (ext == ".png") return Format::Png;
  if (ext == ".jpg" || ext == ".jpeg") return Format::Jpeg;
  if (ext == ".tif" || ext == ".tiff") return Format::Tiff;
  return Format::Unknown;
}

// ---- metadata --------------------------------------------------------------------------------

void addMetadata(OIIO::ImageSpec& spec, const ImageMetadata& meta) {
  spec.attribute("glint:scene", meta.scene);
  spec.attribute("glint:spp", meta.spp);
  spec.attribute("glint:seed", std::to_string(meta.seed));  // 64-bit: no EXR integer holds it
  double seconds = meta.renderSeconds;
  spec.attribute("glint:render_seconds", OIIO::TypeDesc::DOUBLE, &seconds);
  spec.attribute("glint:accel", meta.accel);
  spec.attribute("glint:integrator", meta.integrator);
  double time = meta.time;
  spec.attribute("glint:time", OIIO::TypeDesc::DOUBLE, &time);
  if (!meta.stop.empty()) {
    spec.attribute("glint:stop", meta.stop);
    double error = meta.error;
    spec.attribute("glint:error", OIIO::TypeDesc::DOUBLE, &error);
  }
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
  meta.stop = spec.get_string_attribute("glint:stop");
  if (const OIIO::ParamValue* e = spec.find_attribute("glint:error", OIIO::TypeDesc::DOUBLE))
    meta.error = e->get<double>();
  return meta;
}

PixelType pixelTypeOf(OIIO::TypeDesc t) {
  if (t == OIIO::TypeDesc::HALF) return PixelType::Half;
  if (t == OIIO::TypeDesc::UINT8) return PixelType::UInt8;
  if (t == OIIO::TypeDesc::UINT16) return PixelType::UInt16;
  return PixelType::Float;
}

OIIO::TypeDesc typeDescOf(PixelType t) {
  switch (t) {
    case PixelType::UInt8:
      return OIIO::TypeDesc::UINT8;
    case PixelType::UInt16:
      return OIIO::TypeDesc::UINT16;
    case PixelType::Half:
      return OIIO::TypeDesc::HALF;
    case PixelType::Float:
      break;
  }
  return OIIO::TypeDesc::FLOAT;
}

// ---- atomic write ----------------------------------------------------------------------------

// The path temporaryOutputInFlight() reports: a fixed buffer, so a signal handler reads it
// without allocating. Writes happen one at a time.
char inFlightPath[4096];
std::atomic<bool> inFlight{false};

// Removes the temporary file unless the write got as far as the rename.
struct TempFile {
  fs::path path;
  bool keep = false;
  explicit TempFile(fs::path p) : path(std::move(p)) {
    const std::string& s = path.native();
    if (s.size() < sizeof inFlightPath) {
      std::memcpy(inFlightPath, s.c_str(), s.size() + 1);
      inFlight.store(true);
    }
  }
  ~TempFile() {
    inFlight.store(false);
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

void writeAtomically(const std::string& target, const OIIO::ImageSpec& spec,
                     const std::vector<float>& pixels) {
  TempFile temp{temporaryPath(fs::path(target))};
  auto fail = [&](const std::string& why) {
    return OutputError(fmt::format("cannot write '{}': {}", target, why));
  };

  auto out = OIIO::ImageOutput::create(target);
  if (!out) throw fail(OIIO::geterror());
  if (!out->open(temp.path.string(), spec)) throw fail(out->geterror());
  if (!out->write_image(OIIO::TypeDesc::FLOAT, pixels.data())) {
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

const char* temporaryOutputInFlight() { return inFlight.load() ? inFlightPath : nullptr; }

// ---- reading ---------------------------------------------------------------------------------

int Image::channel(const std::string& name) const {
  for (size_t c = 0; c < names.size(); ++c)
    if (names[c] == name) return int(c);
  return -1;
}

std::string Image::attribute(const std::string& name) const {
  for (const auto& [key, value] : glintAttributes)
    if (key == name) return value;
  return "(none)";
}

Image readImage(const std::string& path, bool pixels) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw ImageReadError(fmt::format("{}: no such file", path));
  if (fs::is_directory(path, ec))
    throw ImageReadError(fmt::format("{}: is a folder, not an image", path));
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    std::string why = OIIO::geterror();
    throw DecodeError(path, why.empty() ? "cannot read the image" : why, false);
  }
  const OIIO::ImageSpec spec = in->spec();
  Image image;
  image.format = in->format_name();
  image.width = spec.width;
  image.depth = std::max(spec.depth, 1);
  image.height = spec.height * image.depth;
  image.channels = spec.nchannels;
  image.names = spec.channelnames;
  image.x = spec.x, image.y = spec.y;
  image.fullX = spec.full_x, image.fullY = spec.full_y;
  image.fullWidth = spec.full_width, image.fullHeight = spec.full_height;
  image.floatingPoint = spec.format.is_floating_point();  // as stored, not as read
  image.type = pixelTypeOf(spec.format);
  for (const OIIO::TypeDesc& t : spec.channelformats)
    if (t == OIIO::TypeDesc::HALF) image.type = PixelType::Half;
  image.meta = metadataOf(spec);
  image.hasMeta = spec.find_attribute("glint:scene") != nullptr;
  image.hasSeed = spec.find_attribute("glint:seed") != nullptr;
  image.hasTime = spec.find_attribute("glint:time", OIIO::TypeDesc::DOUBLE) != nullptr;
  for (const OIIO::ParamValue& p : spec.extra_attribs)
    if (p.name().string().rfind("glint:", 0) == 0)
      image.glintAttributes.emplace_back(p.name().string(), spec.metadata_val(p));
  image.checksum = spec.get_string_attribute("glint:checksum");
  if (!pixels) return image;

  image.pixels.resize(image.pixelCount() * size_t(image.channels));
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data())) {
    std::string why = in->geterror();
    throw DecodeError(path, why.empty() ? "cannot read the image" : why, true);
  }
  return image;
}

// ---- writing ---------------------------------------------------------------------------------

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

bool isExrPath(const std::string& path) { return formatOf(path) == Format::Exr; }
bool isTiffPath(const std::string& path) { return formatOf(path) == Format::Tiff; }

void writeImageFile(const std::string& path, Image image) {
  const Format format = formatOf(path);
  std::string why;
  if (format == Format::Unknown) {
    isSupportedOutput(path, &why);
    throw OutputError(why);
  }
  const int nch = image.channels;
  if (image.width <= 0 || image.height <= 0 || nch <= 0 ||
      image.pixels.size() != image.pixelCount() * size_t(nch))
    throw OutputError(fmt::format("cannot write '{}': the image is empty", path));

  OIIO::ImageSpec spec(image.width, image.height, nch, typeDescOf(image.type));
  if (!image.names.empty()) {
    spec.channelnames = image.names;
    spec.alpha_channel = image.channel("A");
    spec.z_channel = image.channel("Z");
  }
  if (format == Format::Exr) {
    // A crop is the data window of the whole frame (the display window).
    spec.x = image.x, spec.y = image.y;
    spec.full_x = image.fullX, spec.full_y = image.fullY;
    spec.full_width = image.fullWidth > 0 ? image.fullWidth : image.width;
    spec.full_height = image.fullHeight > 0 ? image.fullHeight : image.height;
    if (image.type == PixelType::Half && spec.z_channel >= 0) {
      spec.channelformats.assign(size_t(nch), OIIO::TypeDesc::HALF);
      spec.channelformats[size_t(spec.z_channel)] = OIIO::TypeDesc::FLOAT;
    }
    spec.attribute("compression", "zip");
    // Round half channels here rather than in OIIO's conversion, so the checksum is of the
    // values the file holds (the rounding is the same: Imath's, to nearest even).
    if (image.type == PixelType::Half)
      for (size_t i = 0; i < image.pixels.size(); ++i)
        if (int(i % size_t(nch)) != spec.z_channel)
          image.pixels[i] = float(Imath::half(image.pixels[i]));
    spec.attribute("glint:checksum", pixelChecksum(image.pixels, spec.channelnames));
  }
  spec.attribute("Software", "glint");
  if (image.hasMeta) addMetadata(spec, image.meta);
  writeAtomically(path, spec, image.pixels);
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

}  // namespace glint
