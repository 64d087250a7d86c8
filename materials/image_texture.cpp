// glint — image textures through OpenImageIO's TextureSystem.
//
// Texture files do not go through image/io.h's reader, which decodes a whole image at once:
// the TextureSystem pages big files in tiles within a memory budget and makes MIP levels on
// demand for filtered lookups (and materials/ sits below image/ in the rooms).
//
// How images reach the TextureSystem (OpenImageIO 2.4):
// - Linear files go to the ImageCache by path, untouched: it opens them on demand, reads them
//   in 64x64 tiles ("autotile") within a memory budget ("max_memory_MB"), and makes the MIP
//   levels that untiled, un-MIP-mapped files lack on demand ("automip").
// - Pixels in memory and sRGB files are served by glint's own ImageInputs, registered with
//   ImageCache::add_file(name, creator). The creator is a plain function pointer, so it cannot
//   carry the pixels; the ImageInput it makes looks its name up in a process-wide,
//   mutex-protected registry when the cache opens it (and again whenever the cache reopens it
//   after closing it to respect "max_open_files"). Names are prefixed with the owning
//   TextureImages' serial number, so two sets never share an entry. An IOProxy would instead
//   need the pixels re-encoded into some file format first, which is wasted work and loses
//   float precision for the 8-bit-coded formats. In-memory images come with their MIP levels,
//   made here by area averaging (see downsample), so automip does not touch them.
// - sRGB decoding: OIIO 2.4's TextureOpt has no colour transform (that came in 2.5), and the
//   filtering must see linear values (the mean of sRGB values is not the sRGB of the mean).
//   In-memory sRGB pixels are linearised once, when added. sRGB files are wrapped by an
//   ImageInput that opens the real file and linearises each band of scanlines as the cache
//   reads it, so even big sRGB files are paged like linear ones instead of decoded eagerly.
//   Alpha is never decoded, and never associated ("unassociatedalpha"): glTF and PNG store
//   straight alpha.
#include "materials/image_texture.h"

#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>
#include <OpenImageIO/ustring.h>

#include <atomic>
#include <cassert>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

namespace glint {

// ---------------------------------------------------------------------------------------------
// The registry of images served by glint's own ImageInputs
// ---------------------------------------------------------------------------------------------

namespace {

// One MIP level of an in-memory image: linear floats, rows top to bottom.
struct Level {
  int width = 0, height = 0;
  std::vector<float> pixels;
};

// One registered image: pixels in memory with their MIP levels (path empty), or an sRGB file
// to decode on read.
struct Source {
  OIIO::ImageSpec spec;       // in memory: level 0, FLOAT, linear
  std::vector<Level> levels;  // in memory: level 0 first, down to 1x1
  std::string path;           // sRGB file
};

class Registry {
 public:
  static void add(const std::string& name, std::shared_ptr<const Source> src) {
    std::lock_guard lock(mutex());
    map()[name] = std::move(src);
  }
  static std::shared_ptr<const Source> find(const std::string& name) {
    std::lock_guard lock(mutex());
    auto it = map().find(name);
    return it == map().end() ? nullptr : it->second;
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
  static std::unordered_map<std::string, std::shared_ptr<const Source>>& map() {
    static std::unordered_map<std::string, std::shared_ptr<const Source>> m;
    return m;
  }
};

// The next MIP level (each side halved, rounded down, at least 1): every new texel is the
// area-weighted mean of the texels it covers. For even sides that is the 2x2 box; for odd ones
// it still keeps the mean, unlike OIIO's "automip", which resamples each level bilinearly at
// the new texel centres and so skips texels (a 3x5 image's 1x1 level is then not its mean).
Level downsample(const Level& in, int nch) {
  // For each coarse texel along one axis of n -> m texels: the first fine texel it covers and
  // the weights of the fine texels from there on (they sum to 1).
  struct Taps {
    size_t first = 0;
    std::vector<float> w;
  };
  auto taps = [](int n, int m) {
    std::vector<Taps> t(static_cast<size_t>(m));
    const double ratio = double(n) / double(m);
    for (int i = 0; i < m; ++i) {
      const double a = i * ratio, b = (i + 1) * ratio;
      Taps& tap = t[size_t(i)];
      tap.first = size_t(a);
      for (int k = int(a); k < n && k < b; ++k)
        tap.w.push_back(float((std::min(b, k + 1.0) - std::max(a, double(k))) / ratio));
    }
    return t;
  };
  Level out;
  out.width = std::max(1, in.width / 2);
  out.height = std::max(1, in.height / 2);
  const size_t n = size_t(nch), inW = size_t(in.width), outW = size_t(out.width);
  const std::vector<Taps> tx = taps(in.width, out.width), ty = taps(in.height, out.height);
  // Along rows first (in.height x out.width texels), then along columns.
  std::vector<float> rows(size_t(in.height) * outW * n, 0.0f);
  for (size_t y = 0; y < size_t(in.height); ++y)
    for (size_t x = 0; x < outW; ++x) {
      float* dst = &rows[(y * outW + x) * n];
      for (size_t k = 0; k < tx[x].w.size(); ++k) {
        const float* src = &in.pixels[(y * inW + tx[x].first + k) * n];
        for (size_t c = 0; c < n; ++c) dst[c] += tx[x].w[k] * src[c];
      }
    }
  out.pixels.assign(size_t(out.height) * outW * n, 0.0f);
  for (size_t y = 0; y < size_t(out.height); ++y) {
    float* dst = &out.pixels[y * outW * n];
    for (size_t k = 0; k < ty[y].w.size(); ++k) {
      const float* src = &rows[(ty[y].first + k) * outW * n];
      for (size_t i = 0; i < outW * n; ++i) dst[i] += ty[y].w[k] * src[i];
    }
  }
  return out;
}

// Serves registered in-memory pixels: one untiled FLOAT subimage with all its MIP levels.
class MemoryInput final : public OIIO::ImageInput {
 public:
  const char* format_name() const override { return "glint-memory"; }
  using OIIO::ImageInput::open;
  bool open(const std::string& name, OIIO::ImageSpec& newspec) override {
    src_ = Registry::find(name);
    if (!src_ || src_->levels.empty()) {
      errorfmt("no in-memory image registered under this name");
      return false;
    }
    miplevel_ = 0;
    m_spec = src_->spec;
    newspec = m_spec;
    return true;
  }
  bool close() override {
    src_.reset();
    return true;
  }
  int current_miplevel() const override { return miplevel_; }
  bool seek_subimage(int subimage, int miplevel) override {
    if (!src_ || subimage != 0 || miplevel < 0 || miplevel >= int(src_->levels.size()))
      return false;
    miplevel_ = miplevel;
    m_spec = specOf(miplevel);
    return true;
  }
  bool read_native_scanline(int subimage, int miplevel, int y, int z, void* data) override {
    return read_native_scanlines(subimage, miplevel, y, y + 1, z, data);
  }
  // Needs no lock: reads only the immutable source.
  bool read_native_scanlines(int subimage, int miplevel, int ybegin, int yend, int /*z*/,
                             void* data) override {
    if (!src_ || subimage != 0 || miplevel < 0 || miplevel >= int(src_->levels.size())) {
      errorfmt("no such subimage or MIP level");
      return false;
    }
    const Level& level = src_->levels[size_t(miplevel)];
    if (ybegin < 0 || yend > level.height || ybegin > yend) {
      errorfmt("scanlines {}..{} out of range", ybegin, yend);
      return false;
    }
    size_t row = size_t(level.width) * size_t(src_->spec.nchannels);
    std::memcpy(data, level.pixels.data() + size_t(ybegin) * row,
                size_t(yend - ybegin) * row * sizeof(float));
    return true;
  }

 private:
  OIIO::ImageSpec specOf(int miplevel) const {
    OIIO::ImageSpec spec = src_->spec;
    const Level& level = src_->levels[size_t(miplevel)];
    spec.width = spec.full_width = level.width;
    spec.height = spec.full_height = level.height;
    return spec;
  }

  std::shared_ptr<const Source> src_;
  int miplevel_ = 0;
};

// Which channels of `spec` hold colour (decoded from sRGB): R, G, B, or the grey channel;
// never alpha.
bool isColourChannel(const OIIO::ImageSpec& spec, int c) {
  if (c == spec.alpha_channel) return false;
  return spec.nchannels >= 3 ? c < 3 : c == 0;
}

// Serves a registered sRGB file linearised: the real file's first subimage as one untiled
// subimage (HALF for 8-bit files, FLOAT otherwise), decoded band by band as the cache reads.
class SrgbFileInput final : public OIIO::ImageInput {
 public:
  const char* format_name() const override { return "glint-srgb"; }
  using OIIO::ImageInput::open;
  bool open(const std::string& name, OIIO::ImageSpec& newspec) override {
    auto src = Registry::find(name);
    if (!src || src->path.empty()) {
      errorfmt("no sRGB file registered under this name");
      return false;
    }
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    inner_ = OIIO::ImageInput::open(src->path, &config);
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

OIIO::ImageInput* createMemoryInput() { return new MemoryInput; }
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

std::atomic<unsigned> nextSetSerial{0};

}  // namespace

// ---------------------------------------------------------------------------------------------
// TextureImages
// ---------------------------------------------------------------------------------------------

struct TextureImages::Image {
  const Impl* owner = nullptr;
  std::string name;  // for messages
  OIIO::TextureSystem::TextureHandle* handle = nullptr;
  int width = 0, height = 0, channels = 0;
};

struct TextureImages::Impl {
  OIIO::TextureSystem* ts = nullptr;
  std::string prefix;  // "glint<serial>:", keeps registry names unique per set
  std::mutex mutex;    // guards the members below (adding images)
  std::vector<std::unique_ptr<Image>> images;
  std::unordered_set<std::string> names;  // of addPixels
  std::vector<std::string> registered;    // registry entries to remove at the end

  // Opens `key` in the cache (through `creator` when given) and records the image.
  Handle open(const std::string& name, const std::string& key, OIIO::ImageInput::Creator creator) {
    OIIO::ustring ukey(key);
    if (creator && !ts->imagecache()->add_file(ukey, creator))
      throw std::runtime_error(name + ": " + takeError(*ts));
    auto* handle = ts->get_texture_handle(ukey);
    OIIO::ImageSpec spec;
    if (!handle || !ts->good(handle) || !ts->get_imagespec(handle, nullptr, 0, spec))
      throw std::runtime_error(name + ": " + takeError(*ts));
    auto image = std::make_unique<Image>();
    image->owner = this;
    image->name = name;
    image->handle = handle;
    image->width = spec.width;
    image->height = spec.height;
    image->channels = spec.nchannels;
    std::lock_guard lock(mutex);
    images.push_back(std::move(image));
    return Handle{images.back().get()};
  }
};

TextureImages::TextureImages() : impl_(std::make_unique<Impl>()) {
  impl_->prefix = "glint" + std::to_string(nextSetSerial++) + ":";
  impl_->ts = OIIO::TextureSystem::create(/*shared=*/false);
  OIIO::TextureSystem& ts = *impl_->ts;
  ts.attribute("automip", 1);    // MIP levels for untiled, un-MIP-mapped images
  ts.attribute("autotile", 64);  // page untiled images in 64x64 tiles
  ts.attribute("max_memory_MB", 1024.0f);
  ts.attribute("unassociatedalpha", 1);  // straight alpha, as stored
}

TextureImages::~TextureImages() {
  OIIO::TextureSystem::destroy(impl_->ts);
  for (const std::string& key : impl_->registered) Registry::remove(key);
}

TextureImages::Handle TextureImages::addPixels(const std::string& name, int width, int height,
                                               int channels, const std::vector<float>& pixels,
                                               ColorEncoding enc) {
  if (width <= 0 || height <= 0 || channels < 1 || channels > 4 ||
      pixels.size() != size_t(width) * size_t(height) * size_t(channels))
    throw std::logic_error(name + ": " + std::to_string(pixels.size()) + " floats do not make a " +
                           std::to_string(width) + "x" + std::to_string(height) + " image of " +
                           std::to_string(channels) + " channels");
  auto src = std::make_shared<Source>();
  src->spec = OIIO::ImageSpec(width, height, channels, OIIO::TypeFloat);
  if (channels == 2) {
    src->spec.channelnames = {"Y", "A"};
    src->spec.alpha_channel = 1;
  } else if (channels == 1) {
    src->spec.channelnames = {"Y"};
  }
  Level level{width, height, pixels};
  if (enc == ColorEncoding::Srgb)
    for (size_t i = 0; i < level.pixels.size(); ++i)
      if (isColourChannel(src->spec, int(i % size_t(channels))))
        level.pixels[i] = srgbToLinear(level.pixels[i]);
  src->levels.push_back(std::move(level));
  while (src->levels.back().width > 1 || src->levels.back().height > 1)
    src->levels.push_back(downsample(src->levels.back(), channels));

  std::string key = impl_->prefix + "memory:" + name;
  {
    std::lock_guard lock(impl_->mutex);
    if (!impl_->names.insert(name).second)
      throw std::logic_error(name + ": an image of this name was already added");
    impl_->registered.push_back(key);
  }
  Registry::add(key, std::move(src));
  return impl_->open(name, key, &createMemoryInput);
}

TextureImages::Handle TextureImages::addFile(const std::string& path, ColorEncoding enc) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw std::runtime_error(path + ": no such file");
  if (enc == ColorEncoding::Linear) return impl_->open(path, path, nullptr);
  // The cache does not pass on why one of glint's ImageInputs failed to open, so open the
  // file once here (header only) for a helpful message.
  if (auto probe = OIIO::ImageInput::open(path); !probe)
    throw std::runtime_error(path + ": " + oneLine(OIIO::geterror()));
  // The same file may be added twice: the cache then shares it.
  std::string key = impl_->prefix + "srgb:" + path;
  auto src = std::make_shared<Source>();
  src->path = path;
  {
    std::lock_guard lock(impl_->mutex);
    impl_->registered.push_back(key);
  }
  Registry::add(key, std::move(src));
  return impl_->open(path, key, &createSrgbFileInput);
}

int TextureImages::width(Handle h) const { return h.image ? h.image->width : 0; }
int TextureImages::height(Handle h) const { return h.image ? h.image->height : 0; }
int TextureImages::channels(Handle h) const { return h.image ? h.image->channels : 0; }

Vec4f TextureImages::lookup(Handle h, const TexCoord2& c, TextureWrap wrapS, TextureWrap wrapT,
                            TextureFilter filter) const {
  assert(h.image && h.image->owner == impl_.get());
  const Image& image = *h.image;
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
  if (!impl_->ts->texture(image.handle, nullptr, opt, c.st.x, c.st.y, dsdx, dtdx, dsdy, dtdy, n, r))
    throw std::runtime_error(image.name + ": " + takeError(*impl_->ts));
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

// ---------------------------------------------------------------------------------------------
// ImageTexture
// ---------------------------------------------------------------------------------------------

ImageTexture::ImageTexture(const TextureImages& images, TextureImages::Handle h,
                           TextureMapping mapping, TextureWrap wrapS, TextureWrap wrapT,
                           TextureFilter filter)
    : images_(&images),
      handle_(h),
      mapping_(mapping),
      wrapS_(wrapS),
      wrapT_(wrapT),
      filter_(filter) {
  if (!h.valid()) throw std::logic_error("ImageTexture: invalid image handle");
}

Vec4f ImageTexture::evaluate(const TexturePoint& tp) const {
  return images_->lookup(handle_, mapping_.map2D(tp), wrapS_, wrapT_, filter_);
}

}  // namespace glint
