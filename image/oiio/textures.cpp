// glint — OpenImageIO's part in image textures (materials/image_texture.h), in the OpenImageIO
// plugin (plugin.h): the decoders of the images glint keeps in memory, and the TextureSystem
// serving the texture files kept on disk.
//
// glint looks up the images it holds in memory itself (materials/mipmap.h): OpenImageIO only
// decodes them here. What stays in the TextureSystem (OpenImageIO 2.4), chosen by
// TextureImages::addFile, are tiled, MIP-mapped files (.tx) and images too large to hold:
// - Linear files go to the ImageCache by path, untouched: it opens them on demand, reads them
//   in tiles (64x64 for untiled files: "autotile") within a memory budget ("max_memory_MB"),
//   and makes the MIP levels that un-MIP-mapped files lack on demand ("automip").
// - sRGB files are served by glint's own ImageInput, registered with ImageCache::add_file(name,
//   creator), which opens the real file and linearises each band of scanlines as the cache
//   reads it: OIIO 2.4's TextureOpt has no colour transform (that came in 2.5), and filtering
//   must see linear values (the mean of sRGB values is not the sRGB of the mean). The creator
//   is a plain function pointer, so the ImageInput looks the file up by its name in a
//   process-wide, mutex-protected registry when the cache opens it (and again whenever the
//   cache reopens it after closing it to respect "max_open_files"). Names are prefixed with the
//   owning cache's serial number, so two caches never share an entry.
// Alpha is never decoded, and never associated ("unassociatedalpha"): glTF and PNG store
// straight alpha.
#include "image/oiio/textures.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>
#include <OpenImageIO/ustring.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cassert>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <unordered_map>

#include "materials/image_texture.h"

namespace glint::oiio {

namespace {

// The sRGB files served by SrgbFileInput: the name the cache knows each by -> its path.
class Registry {
 public:
  static void add(const std::string& name, const std::string& path) {
    std::lock_guard lock(mutex());
    map()[name] = path;
  }
  static std::string find(const std::string& name) {
    std::lock_guard lock(mutex());
    auto it = map().find(name);
    return it == map().end() ? std::string() : it->second;
  }
  static void remove(const std::string& name) {
    std::lock_guard lock(mutex());
    map().erase(name);
  }

 private:
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  static std::unordered_map<std::string, std::string>& map() {
    static std::unordered_map<std::string, std::string> m;
    return m;
  }
};

// Which channels of `spec` hold colour (decoded from sRGB): R, G, B, or the grey channel;
// never alpha.
bool isColourChannel(const OIIO::ImageSpec& spec, int c) {
  if (c == spec.alpha_channel) return false;
  return spec.nchannels >= 3 ? c < 3 : c == 0;
}

// The OIIO format that reads `bytes`, from its signature, or "" when none is known.
std::string formatOf(const std::string& bytes) {
  auto starts = [&](const char* sig, size_t at = 0) {
    const size_t n = std::strlen(sig);
    return bytes.size() >= at + n && bytes.compare(at, n, sig) == 0;
  };
  if (starts("\x89PNG")) return "png";
  if (starts("\xFF\xD8\xFF")) return "jpeg";
  if (starts("RIFF") && starts("WEBP", 8)) return "webp";
  if (starts("BM")) return "bmp";
  if (starts("GIF8")) return "gif";
  return "";
}

// Opens an encoded image in memory; `mem` must outlive the input.
std::unique_ptr<OIIO::ImageInput> openEncoded(const std::string& bytes,
                                              OIIO::Filesystem::IOMemReader* mem,
                                              std::string* error) {
  const std::string format = formatOf(bytes);
  if (format.empty()) {
    *error = "not an image glint can read (PNG, JPEG, WebP, BMP or GIF expected)";
    return nullptr;
  }
  OIIO::ImageSpec config;
  void* proxy = mem;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::create(format, false, &config);
  OIIO::ImageSpec spec;
  if (!in || !in->open("memory." + format, spec, config)) {
    const std::string e = in ? in->geterror() : OIIO::geterror();
    *error = "cannot decode the " + format + " image" + (e.empty() ? "" : ": " + e);
    return nullptr;
  }
  in->threads(1);  // images are decoded in parallel with each other instead
  return in;
}

// Reads the first `nch` channels of every pixel of `in`'s first subimage: 8-bit images as
// bytes, others as floats.
bool readPixels(OIIO::ImageInput& in, int nch, DecodedImage* out, std::string* error) {
  const OIIO::ImageSpec& spec = in.spec();
  out->width = spec.width, out->height = spec.height, out->channels = nch;
  const size_t count = size_t(spec.width) * size_t(spec.height) * size_t(nch);
  bool ok = false;
  if (spec.format.basesize() == 1) {
    out->bytes.resize(count);
    ok = in.read_image(0, 0, 0, nch, OIIO::TypeUInt8, out->bytes.data());
  } else {
    out->floats.resize(count);
    ok = in.read_image(0, 0, 0, nch, OIIO::TypeFloat, out->floats.data());
  }
  if (!ok) *error = in.geterror();
  return ok;
}

// Serves a registered sRGB file linearised: the real file's first subimage as one untiled
// subimage (HALF for 8-bit files, FLOAT otherwise), decoded band by band as the cache reads.
class SrgbFileInput final : public OIIO::ImageInput {
 public:
  const char* format_name() const override { return "glint-srgb"; }
  using OIIO::ImageInput::open;
  bool open(const std::string& name, OIIO::ImageSpec& newspec) override {
    const std::string path = Registry::find(name);
    if (path.empty()) {
      errorfmt("no sRGB file registered under this name");
      return false;
    }
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    inner_ = OIIO::ImageInput::open(path, &config);
    if (!inner_) {
      errorfmt("{}", OIIO::geterror());
      return false;
    }
    inner_->threads(1);  // the renderer's threads already keep the cores busy
    m_spec = inner_->spec();
    m_spec.format = m_spec.format.basesize() == 1 ? OIIO::TypeHalf : OIIO::TypeFloat;
    m_spec.channelformats.clear();
    m_spec.tile_width = m_spec.tile_height = 0;
    m_spec.tile_depth = 1;
    m_spec.attribute("oiio:ColorSpace", "Linear");
    newspec = m_spec;
    return true;
  }
  bool close() override {
    std::lock_guard lock(mutex_);
    inner_.reset();
    return true;
  }
  bool read_native_scanline(int subimage, int miplevel, int y, int z, void* data) override {
    return read_native_scanlines(subimage, miplevel, y, y + 1, z, data);
  }
  bool read_native_scanlines(int subimage, int miplevel, int ybegin, int yend, int z,
                             void* data) override {
    std::lock_guard lock(mutex_);
    if (!inner_ || subimage != 0 || miplevel != 0) {
      errorfmt("no such subimage or MIP level");
      return false;
    }
    const int nch = m_spec.nchannels;
    size_t count = size_t(yend - ybegin) * size_t(m_spec.width) * size_t(nch);
    std::vector<float> buf(count);
    if (!inner_->read_scanlines(0, 0, ybegin, yend, z, 0, nch, OIIO::TypeFloat, buf.data())) {
      errorfmt("{}", inner_->geterror());
      return false;
    }
    for (size_t i = 0; i < count; ++i)
      if (isColourChannel(m_spec, int(i % size_t(nch)))) buf[i] = srgbToLinear(buf[i]);
    if (m_spec.format == OIIO::TypeFloat) {
      std::memcpy(data, buf.data(), count * sizeof(float));
      return true;
    }
    return OIIO::convert_pixel_values(OIIO::TypeFloat, buf.data(), m_spec.format, data, int(count));
  }

 private:
  std::mutex mutex_;
  std::unique_ptr<OIIO::ImageInput> inner_;
};

OIIO::ImageInput* createSrgbFileInput() { return new SrgbFileInput; }

std::string oneLine(std::string e) {
  while (!e.empty() && (e.back() == '\n' || e.back() == ' ')) e.pop_back();
  for (char& ch : e)
    if (ch == '\n') ch = ' ';
  return e.empty() ? "unknown OpenImageIO error" : e;
}

// OIIO's pending error text (TextureSystem first, then the global one), on one line.
std::string takeError(const OIIO::TextureSystem& ts) {
  std::string e = ts.geterror();
  return oneLine(e.empty() ? OIIO::geterror() : e);
}

OIIO::TextureOpt::Wrap oiioWrap(TextureWrap w) {
  switch (w) {
    case TextureWrap::Clamp:
      return OIIO::TextureOpt::WrapClamp;
    case TextureWrap::Mirror:
      return OIIO::TextureOpt::WrapMirror;
    case TextureWrap::Black:
      return OIIO::TextureOpt::WrapBlack;
    case TextureWrap::Repeat:
    default:
      return OIIO::TextureOpt::WrapPeriodic;
  }
}

float finiteOrZero(float v) { return std::isfinite(v) ? v : 0.0f; }

std::atomic<unsigned> nextCacheSerial{0};

}  // namespace

// ---------------------------------------------------------------------------------------------
// Decoding the images glint keeps in memory
// ---------------------------------------------------------------------------------------------

EncodedImageInfo probeEncodedImage(const std::string& bytes) {
  OIIO::Filesystem::IOMemReader mem(bytes.data(), bytes.size());
  std::string error;
  auto in = openEncoded(bytes, &mem, &error);
  if (!in) throw std::runtime_error(error);
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width < 1 || spec.height < 1 || spec.nchannels < 1 || spec.nchannels > 4)
    throw std::runtime_error("a " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                             " image of " + std::to_string(spec.nchannels) +
                             " channels; glint reads 1 to 4 channels");
  return {spec.width, spec.height, spec.nchannels, spec.format.basesize() == 1 ? 8 : 16};
}

std::vector<float> decodeEncodedImage(const std::string& bytes, EncodedImageInfo* info) {
  const EncodedImageInfo header = probeEncodedImage(bytes);
  if (info) *info = header;
  OIIO::Filesystem::IOMemReader mem(bytes.data(), bytes.size());
  std::string error;
  auto in = openEncoded(bytes, &mem, &error);
  std::vector<float> out(size_t(header.width) * size_t(header.height) * size_t(header.channels));
  if (!in || !in->read_image(0, 0, 0, header.channels, OIIO::TypeFloat, out.data()))
    throw std::runtime_error(in ? "cannot decode the image: " + in->geterror() : error);
  return out;
}

DecodedImage decodeEncoded(const std::string& bytes) {
  const EncodedImageInfo header = probeEncodedImage(bytes);  // throws for unreadable headers
  OIIO::Filesystem::IOMemReader mem(bytes.data(), bytes.size());
  std::string error;
  auto in = openEncoded(bytes, &mem, &error);
  DecodedImage out;
  if (!in) throw std::runtime_error(error);
  if (!readPixels(*in, header.channels, &out, &error))
    throw std::runtime_error("cannot decode the image: " + oneLine(error));
  return out;
}

namespace {
// Opens an image file. Like every error of the plugin's texture half, the reason alone: the
// caller names the file (TextureImages, as an InputError).
std::unique_ptr<OIIO::ImageInput> openFile(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw std::runtime_error("no such file");
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in) throw std::runtime_error(oneLine(OIIO::geterror()));
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width < 1 || spec.height < 1 || spec.nchannels < 1)
    throw std::runtime_error("an image of no pixels");
  return in;
}
}  // namespace

ImageFileInfo probeImageFile(const std::string& path) {
  auto in = openFile(path);
  const OIIO::ImageSpec& spec = in->spec();
  ImageFileInfo info;
  info.width = spec.width, info.height = spec.height, info.channels = spec.nchannels;
  info.bits = int(spec.format.basesize()) * 8;
  info.tiled = spec.tile_width > 0;
  info.mipLevels = 1;
  while (in->seek_subimage(0, info.mipLevels)) ++info.mipLevels;
  return info;
}

DecodedImage decodeImageFile(const std::string& path) {
  auto in = openFile(path);
  in->threads(1);  // images are decoded in parallel with each other instead
  DecodedImage out;
  std::string error;
  // The first 4 channels (RGBA, grey and alpha); glint reads no more.
  if (!readPixels(*in, std::min(in->spec().nchannels, 4), &out, &error))
    throw std::runtime_error(oneLine(error));
  return out;
}

// ---------------------------------------------------------------------------------------------
// The TextureSystem for files kept on disk
// ---------------------------------------------------------------------------------------------

}  // namespace glint::oiio

namespace glint {
struct TextureImages::Cache::File {
  const void* owner = nullptr;  // the OiioTextureCache holding it
  std::string name;             // the path, for messages
  OIIO::TextureSystem::TextureHandle* handle = nullptr;
  int channels = 0;
};
}  // namespace glint

namespace glint::oiio {

using File = TextureImages::Cache::File;

// One private TextureSystem and the files it was given.
class OiioTextureCache final : public TextureImages::Cache {
 public:
  OiioTextureCache() {
    prefix = "glint" + std::to_string(nextCacheSerial++) + ":";
    ts = OIIO::TextureSystem::create(/*shared=*/false);
    ts->attribute("automip", 1);             // MIP levels for untiled, un-MIP-mapped images
    ts->attribute("autotile", 64);           // page untiled images in 64x64 tiles
    ts->attribute("max_memory_MB", 256.0f);  // OIIO's default budget for the tiles it holds
    ts->attribute("unassociatedalpha", 1);   // straight alpha, as stored
  }
  ~OiioTextureCache() noexcept override {
    OIIO::TextureSystem::destroy(ts);
    for (const std::string& key : registered) Registry::remove(key);
  }
  const File* add(const std::string& path, ColorEncoding enc) override;
  Vec4f lookup(const File* f, const TexCoord2& c, TextureWrap wrapS, TextureWrap wrapT,
               TextureFilter filter) const override;

 private:
  OIIO::TextureSystem* ts = nullptr;
  std::string prefix;  // "glint<serial>:", keeps registry names unique per cache
  std::mutex mutex;    // guards the members below (adding files)
  std::vector<std::unique_ptr<File>> files;
  std::vector<std::string> registered;  // registry entries to remove at the end
};

const File* OiioTextureCache::add(const std::string& path, ColorEncoding enc) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw std::runtime_error("no such file");
  std::string key = path;
  if (enc == ColorEncoding::Srgb) {
    // The cache does not pass on why one of glint's ImageInputs failed to open, so open the
    // file once here (header only) for a helpful message.
    if (auto probe = OIIO::ImageInput::open(path); !probe)
      throw std::runtime_error(oneLine(OIIO::geterror()));
    key = prefix + "srgb:" + path;
    {
      std::lock_guard lock(mutex);
      registered.push_back(key);
    }
    Registry::add(key, path);
    // The same file may be added twice: the cache then shares it.
    if (!ts->imagecache()->add_file(OIIO::ustring(key), &createSrgbFileInput))
      throw std::runtime_error(takeError(*ts));
  }
  auto* handle = ts->get_texture_handle(OIIO::ustring(key));
  OIIO::ImageSpec spec;
  if (!handle || !ts->good(handle) || !ts->get_imagespec(handle, nullptr, 0, spec))
    throw std::runtime_error(takeError(*ts));
  auto file = std::make_unique<File>();
  file->owner = this;
  file->name = path;
  file->handle = handle;
  file->channels = spec.nchannels;
  std::lock_guard lock(mutex);
  files.push_back(std::move(file));
  return files.back().get();
}

Vec4f OiioTextureCache::lookup(const File* f, const TexCoord2& c, TextureWrap wrapS,
                               TextureWrap wrapT, TextureFilter filter) const {
  assert(f && f->owner == this);
  const File& image = *f;
  if (!std::isfinite(c.st.x) || !std::isfinite(c.st.y)) return {0, 0, 0, 1};

  OIIO::TextureOpt opt;
  opt.swrap = oiioWrap(wrapS);
  opt.twrap = oiioWrap(wrapT);
  // Bilinear within a level (not OIIO's default "smart bicubic", whose B-spline blurs even a
  // point sample); rnd stays negative, so no lookup is stochastic.
  opt.interpmode = OIIO::TextureOpt::InterpBilinear;
  float dsdx = 0, dtdx = 0, dsdy = 0, dtdy = 0;
  switch (filter) {
    case TextureFilter::Nearest:
      opt.mipmode = OIIO::TextureOpt::MipModeNoMIP;
      opt.interpmode = OIIO::TextureOpt::InterpClosest;
      break;
    case TextureFilter::Linear:
      opt.mipmode = OIIO::TextureOpt::MipModeNoMIP;
      break;
    case TextureFilter::Mipmap:
      opt.mipmode = OIIO::TextureOpt::MipModeAniso;
      dsdx = finiteOrZero(c.dstdx.x), dtdx = finiteOrZero(c.dstdx.y);
      dsdy = finiteOrZero(c.dstdy.x), dtdy = finiteOrZero(c.dstdy.y);
      break;
  }

  const int n = std::min(image.channels, 4);
  float r[4] = {0, 0, 0, 0};
  if (!ts->texture(image.handle, nullptr, opt, c.st.x, c.st.y, dsdx, dtdx, dsdy, dtdy, n, r))
    throw std::runtime_error(takeError(*ts));
  switch (n) {
    case 1:
      return {r[0], r[0], r[0], 1};
    case 2:
      return {r[0], r[0], r[0], r[1]};
    case 3:
      return {r[0], r[1], r[2], 1};
    default:
      return {r[0], r[1], r[2], r[3]};
  }
}

std::unique_ptr<TextureImages::Cache> newTextureCache() {
  return std::make_unique<OiioTextureCache>();
}

}  // namespace glint::oiio
