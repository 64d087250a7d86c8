// glint — image textures through OpenImageIO's TextureSystem: the backend of TextureImages
// (materials/image_texture.h), in the OpenImageIO plugin (plugin.h).
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
// - Encoded images in memory (glTF's PNG, JPEG and WebP bytes) are served the same way, but
//   their spec comes from the header at once and their pixels are decoded once, on first need
//   (ensureDecoded: a startDecoding task, or the cache's first read), by an OIIO ImageInput
//   reading from memory (IOMemReader). 8-bit images are kept as bytes (linear) or linear
//   halves (sRGB).
// - sRGB decoding: OIIO 2.4's TextureOpt has no colour transform (that came in 2.5), and the
//   filtering must see linear values (the mean of sRGB values is not the sRGB of the mean).
//   In-memory sRGB pixels are linearised once, when added. sRGB files are wrapped by an
//   ImageInput that opens the real file and linearises each band of scanlines as the cache
//   reads it, so even big sRGB files are paged like linear ones instead of decoded eagerly.
//   Alpha is never decoded, and never associated ("unassociatedalpha"): glTF and PNG store
//   straight alpha.
#include "image/oiio/textures.h"
#include "materials/image_texture.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>
#include <OpenImageIO/ustring.h>

#include <Imath/half.h>
#include <tbb/task_group.h>

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
#include <type_traits>
#include <unordered_set>

namespace glint::oiio {

// ---------------------------------------------------------------------------------------------
// The registry of images served by glint's own ImageInputs
// ---------------------------------------------------------------------------------------------

namespace {

// One MIP level of an in-memory image, linear, rows top to bottom: floats; or, for images
// decoded from 8-bit files, the bytes themselves when they are linear (exact, a quarter of the
// memory of floats) and halves when they were sRGB (their 256 linearised values need no more
// precision than a half's 11 bits; half the memory of floats).
struct Level {
  int width = 0, height = 0;
  std::vector<float> pixels;
  std::vector<Imath::half> halves;
  std::vector<uint8_t> bytes;
};

// Samples as the [0, 1] values they stand for, and back (bytes round to the nearest).
inline float toFloat(float v) { return v; }
inline float toFloat(Imath::half v) { return float(v); }
inline float toFloat(uint8_t v) { return float(v) * (1.0f / 255.0f); }
template <class T>
T fromFloat(float v) {
  if constexpr (std::is_same_v<T, uint8_t>)
    return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
  else
    return T(v);
}

// One registered image: pixels in memory with their MIP levels (path empty), or an sRGB file
// to decode on read. An encoded image in memory (`encoded` set) is decoded once, by
// ensureDecoded, the first time anyone needs its pixels (a background task or a cache read);
// its spec is known from the header before that.
struct Source {
  OIIO::ImageSpec spec;       // in memory: level 0, FLOAT or HALF, linear
  int levelCount = 0;         // in memory: MIP levels, level 0 down to 1x1
  std::string path;           // sRGB file
  std::shared_ptr<const std::string> encoded;
  std::string format;         // OIIO format name of `encoded`
  ColorEncoding encoding = ColorEncoding::Linear;
  // Written once under `once` (levels directly for pixels added decoded).
  mutable std::once_flag once;
  mutable std::vector<Level> levels;
  mutable std::string error;  // why decoding failed, or empty
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
// Which channels of `spec` hold colour (decoded from sRGB): R, G, B, or the grey channel;
// never alpha.
bool isColourChannel(const OIIO::ImageSpec& spec, int c) {
  if (c == spec.alpha_channel) return false;
  return spec.nchannels >= 3 ? c < 3 : c == 0;
}

template <class T>
void downsampleInto(const std::vector<T>& inPixels, int inWidth, int inHeight, int nch,
                    Level* out, std::vector<T>* outPixels);

Level downsample(const Level& in, int nch) {
  Level out;
  if (!in.bytes.empty())
    downsampleInto(in.bytes, in.width, in.height, nch, &out, &out.bytes);
  else if (!in.halves.empty())
    downsampleInto(in.halves, in.width, in.height, nch, &out, &out.halves);
  else
    downsampleInto(in.pixels, in.width, in.height, nch, &out, &out.pixels);
  return out;
}

template <class T>
void downsampleInto(const std::vector<T>& inPixels, int inWidth, int inHeight, int nch,
                    Level* outLevel, std::vector<T>* outPixels) {
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
  Level& out = *outLevel;
  out.width = std::max(1, inWidth / 2);
  out.height = std::max(1, inHeight / 2);
  const size_t n = size_t(nch), inW = size_t(inWidth), outW = size_t(out.width);
  if (inWidth % 2 == 0 && inHeight % 2 == 0) {
    // Even sides: each new texel is the mean of a 2x2 box (the general case below gives the
    // same weights, a quarter each, at several times the cost).
    outPixels->clear();
    outPixels->reserve(size_t(out.height) * outW * n);
    for (size_t y = 0; y < size_t(out.height); ++y) {
      const T* row0 = &inPixels[2 * y * inW * n];
      const T* row1 = row0 + inW * n;
      for (size_t x = 0; x < outW; ++x)
        for (size_t c = 0; c < n; ++c) {
          const size_t i = 2 * x * n + c;
          outPixels->push_back(fromFloat<T>(0.25f * ((toFloat(row0[i]) + toFloat(row0[i + n])) +
                                                     (toFloat(row1[i]) + toFloat(row1[i + n])))));
        }
    }
    return;
  }
  const std::vector<Taps> tx = taps(inWidth, out.width), ty = taps(inHeight, out.height);
  // Along rows first (in height x out width texels), then along columns, in float.
  std::vector<float> rows(size_t(inHeight) * outW * n, 0.0f);
  for (size_t y = 0; y < size_t(inHeight); ++y)
    for (size_t x = 0; x < outW; ++x) {
      float* dst = &rows[(y * outW + x) * n];
      for (size_t k = 0; k < tx[x].w.size(); ++k) {
        const T* src = &inPixels[(y * inW + tx[x].first + k) * n];
        for (size_t c = 0; c < n; ++c) dst[c] += tx[x].w[k] * toFloat(src[c]);
      }
    }
  std::vector<float> line(outW * n);
  outPixels->resize(size_t(out.height) * outW * n);
  for (size_t y = 0; y < size_t(out.height); ++y) {
    std::fill(line.begin(), line.end(), 0.0f);
    for (size_t k = 0; k < ty[y].w.size(); ++k) {
      const float* src = &rows[(ty[y].first + k) * outW * n];
      for (size_t i = 0; i < outW * n; ++i) line[i] += ty[y].w[k] * src[i];
    }
    for (size_t i = 0; i < outW * n; ++i) (*outPixels)[y * outW * n + i] = fromFloat<T>(line[i]);
  }
}

// MIP levels of a w x h image: halving (rounded down, at least 1) until 1 x 1.
int mipLevelCount(int w, int h) {
  int count = 1;
  while (w > 1 || h > 1) w = std::max(1, w / 2), h = std::max(1, h / 2), ++count;
  return count;
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

// Decodes `src` (an encoded image) into its levels, or records why it cannot.
void decode(const Source& src) {
  OIIO::Filesystem::IOMemReader mem(src.encoded->data(), src.encoded->size());
  std::string error;
  auto in = openEncoded(*src.encoded, &mem, &error);
  if (!in) {
    src.error = error;
    return;
  }
  const OIIO::ImageSpec& spec = in->spec();
  const int nch = src.spec.nchannels;
  const size_t count = size_t(spec.width) * size_t(spec.height) * size_t(nch);
  Level level{spec.width, spec.height, {}, {}};
  if (src.spec.format == OIIO::TypeUInt8) {
    level.bytes.resize(count);
    if (!in->read_image(0, 0, 0, nch, OIIO::TypeUInt8, level.bytes.data())) {
      src.error = "cannot decode the image: " + in->geterror();
      return;
    }
  } else if (src.spec.format == OIIO::TypeHalf) {
    std::unique_ptr<uint8_t[]> raw(new uint8_t[count]);  // not zeroed: read_image fills it
    if (!in->read_image(0, 0, 0, nch, OIIO::TypeUInt8, raw.get())) {
      src.error = "cannot decode the image: " + in->geterror();
      return;
    }
    // 256 values per channel: linearised through a table.
    std::array<Imath::half, 256> colour, plain;
    for (int v = 0; v < 256; ++v) {
      plain[size_t(v)] = Imath::half(v / 255.0f);
      colour[size_t(v)] = src.encoding == ColorEncoding::Srgb ? Imath::half(srgbToLinear(v / 255.0f))
                                                              : plain[size_t(v)];
    }
    level.halves.reserve(count);
    for (size_t i = 0; i < count; i += size_t(nch))
      for (int c = 0; c < nch; ++c)
        level.halves.push_back((isColourChannel(src.spec, c) ? colour : plain)[raw[i + size_t(c)]]);
  } else {
    level.pixels.resize(count);
    if (!in->read_image(0, 0, 0, nch, OIIO::TypeFloat, level.pixels.data())) {
      src.error = "cannot decode the image: " + in->geterror();
      return;
    }
    if (src.encoding == ColorEncoding::Srgb)
      for (size_t i = 0; i < count; ++i)
        if (isColourChannel(src.spec, int(i % size_t(nch))))
          level.pixels[i] = srgbToLinear(level.pixels[i]);
  }
  src.levels.push_back(std::move(level));
  while (src.levels.back().width > 1 || src.levels.back().height > 1)
    src.levels.push_back(downsample(src.levels.back(), nch));
}

// The pixels of `src`, decoded on first use; false (with the reason in src.error) when they
// cannot be.
bool ensureDecoded(const Source& src) {
  if (src.encoded) std::call_once(src.once, [&] { decode(src); });
  return src.error.empty();
}

// Serves registered in-memory pixels: one untiled FLOAT subimage with all its MIP levels.
class MemoryInput final : public OIIO::ImageInput {
 public:
  const char* format_name() const override { return "glint-memory"; }
  using OIIO::ImageInput::open;
  bool open(const std::string& name, OIIO::ImageSpec& newspec) override {
    src_ = Registry::find(name);
    if (!src_ || src_->levelCount == 0) {
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
    if (!src_ || subimage != 0 || miplevel < 0 || miplevel >= src_->levelCount) return false;
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
    if (!src_ || subimage != 0 || miplevel < 0 || miplevel >= src_->levelCount) {
      errorfmt("no such subimage or MIP level");
      return false;
    }
    if (!ensureDecoded(*src_)) {
      errorfmt("{}", src_->error);
      return false;
    }
    const Level& level = src_->levels[size_t(miplevel)];
    if (ybegin < 0 || yend > level.height || ybegin > yend) {
      errorfmt("scanlines {}..{} out of range", ybegin, yend);
      return false;
    }
    const size_t row = size_t(level.width) * size_t(src_->spec.nchannels);
    const size_t first = size_t(ybegin) * row, count = size_t(yend - ybegin) * row;
    if (!level.bytes.empty())
      std::memcpy(data, level.bytes.data() + first, count);
    else if (!level.halves.empty())
      std::memcpy(data, level.halves.data() + first, count * sizeof(Imath::half));
    else
      std::memcpy(data, level.pixels.data() + first, count * sizeof(float));
    return true;
  }

 private:
  OIIO::ImageSpec specOf(int miplevel) const {
    OIIO::ImageSpec spec = src_->spec;
    for (int l = 0; l < miplevel; ++l)
      spec.width = std::max(1, spec.width / 2), spec.height = std::max(1, spec.height / 2);
    spec.full_width = spec.width;
    spec.full_height = spec.height;
    return spec;
  }

  std::shared_ptr<const Source> src_;
  int miplevel_ = 0;
};


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

}  // namespace glint::oiio

namespace glint {
struct TextureImages::Image {
  const void* owner = nullptr;  // the OiioTextureImages holding it
  std::string name;             // for messages
  OIIO::TextureSystem::TextureHandle* handle = nullptr;
  int width = 0, height = 0, channels = 0;
};
}  // namespace glint

namespace glint::oiio {

namespace {
// The keys of OiioTextureImages::sources.
std::string encodedSourceKey(const std::string& name) { return "encoded:" + name; }
std::string fileSourceKey(const std::string& path, ColorEncoding enc) {
  return (enc == ColorEncoding::Srgb ? "srgb:" : "linear:") + path;
}
}  // namespace

using Handle = TextureImages::Handle;
using Image = TextureImages::Image;

// A TextureImages' backend: one private TextureSystem and what it was given.
class OiioTextureImages final : public TextureImages::Backend {
 public:
  OiioTextureImages();
  ~OiioTextureImages() noexcept override;
  Handle addPixels(const std::string& name, int width, int height, int channels,
                   const std::vector<float>& pixels, ColorEncoding enc) override;
  Handle addEncoded(const std::string& name, std::shared_ptr<const std::string> bytes,
                    ColorEncoding enc) override;
  void startDecoding() override;
  std::vector<std::pair<std::string, std::string>> waitForDecodes() override;
  Handle addFile(const std::string& path, ColorEncoding enc) override;
  Handle findEncoded(const std::string& name, const std::string* bytes) const override;
  Handle findFile(const std::string& path, ColorEncoding enc) const override;
  size_t size() const override;
  bool contains(const std::string& name) const override;
  int width(Handle h) const override { return h.image ? h.image->width : 0; }
  int height(Handle h) const override { return h.image ? h.image->height : 0; }
  int channels(Handle h) const override { return h.image ? h.image->channels : 0; }
  Vec4f lookup(Handle h, const TexCoord2& c, TextureWrap wrapS, TextureWrap wrapT,
               TextureFilter filter) const override;

 private:
  OIIO::TextureSystem* ts = nullptr;
  std::string prefix;  // "glint<serial>:", keeps registry names unique per set
  mutable std::mutex mutex;  // guards the members below (adding images)
  std::vector<std::unique_ptr<Image>> images;
  std::unordered_set<std::string> names;  // of addPixels and addEncoded
  // What findEncoded and findFile look up: encodedSourceKey(name) with its bytes,
  // fileSourceKey(path, encoding) with nullptr.
  std::unordered_map<std::string, std::pair<Handle, const void*>> sources;
  std::vector<std::string> registered;    // registry entries to remove at the end
  // Encoded images not yet handed to a decoding task, and the tasks.
  std::vector<std::pair<std::string, std::shared_ptr<const Source>>> pending, encoded;
  tbb::task_group decoding;

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

OiioTextureImages::OiioTextureImages() {
  prefix = "glint" + std::to_string(nextSetSerial++) + ":";
  ts = OIIO::TextureSystem::create(/*shared=*/false);
  OIIO::TextureSystem& cache = *ts;
  cache.attribute("automip", 1);    // MIP levels for untiled, un-MIP-mapped images
  cache.attribute("autotile", 64);  // page untiled images in 64x64 tiles
  // The cache holds tiles of every image it reads, a second copy of in-memory images: OIIO's
  // default budget, so it stays a cache (evicted tiles are read again, from memory or disk).
  cache.attribute("max_memory_MB", 256.0f);
  cache.attribute("unassociatedalpha", 1);  // straight alpha, as stored
}

OiioTextureImages::~OiioTextureImages() noexcept {
  decoding.wait();
  OIIO::TextureSystem::destroy(ts);
  for (const std::string& key : registered) Registry::remove(key);
}

Handle OiioTextureImages::addPixels(const std::string& name, int width, int height, int channels,
                                    const std::vector<float>& pixels, ColorEncoding enc) {
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
  Level level{width, height, pixels, {}};
  if (enc == ColorEncoding::Srgb)
    for (size_t i = 0; i < level.pixels.size(); ++i)
      if (isColourChannel(src->spec, int(i % size_t(channels))))
        level.pixels[i] = srgbToLinear(level.pixels[i]);
  src->levels.push_back(std::move(level));
  while (src->levels.back().width > 1 || src->levels.back().height > 1)
    src->levels.push_back(downsample(src->levels.back(), channels));
  src->levelCount = int(src->levels.size());

  std::string key = prefix + "memory:" + name;
  {
    std::lock_guard lock(mutex);
    if (!names.insert(name).second)
      throw std::logic_error(name + ": an image of this name was already added");
    registered.push_back(key);
  }
  Registry::add(key, std::move(src));
  return open(name, key, &createMemoryInput);
}

Handle OiioTextureImages::addEncoded(const std::string& name,
                                     std::shared_ptr<const std::string> bytes, ColorEncoding enc) {
  const EncodedImageInfo info = probeEncodedImage(*bytes);  // throws for unreadable headers
  auto src = std::make_shared<Source>();
  src->spec = OIIO::ImageSpec(info.width, info.height, info.channels,
                              info.bits != 8                ? OIIO::TypeFloat
                              : enc == ColorEncoding::Srgb ? OIIO::TypeHalf
                                                           : OIIO::TypeUInt8);
  if (info.channels == 2) {
    src->spec.channelnames = {"Y", "A"};
    src->spec.alpha_channel = 1;
  } else if (info.channels == 1) {
    src->spec.channelnames = {"Y"};
  }
  src->levelCount = mipLevelCount(info.width, info.height);
  src->encoded = std::move(bytes);
  src->encoding = enc;
  std::string key = prefix + "memory:" + name;
  {
    std::lock_guard lock(mutex);
    if (!names.insert(name).second)
      throw std::logic_error(name + ": an image of this name was already added");
    registered.push_back(key);
    pending.emplace_back(name, src);
  }
  const void* identity = src->encoded.get();
  Registry::add(key, src);
  const Handle h = open(name, key, &createMemoryInput);
  std::lock_guard lock(mutex);
  sources[encodedSourceKey(name)] = {h, identity};
  return h;
}

Handle OiioTextureImages::findEncoded(const std::string& name, const std::string* bytes) const {
  std::lock_guard lock(mutex);
  auto it = sources.find(encodedSourceKey(name));
  return it != sources.end() && it->second.second == bytes ? it->second.first : Handle{};
}

Handle OiioTextureImages::findFile(const std::string& path, ColorEncoding enc) const {
  std::lock_guard lock(mutex);
  auto it = sources.find(fileSourceKey(path, enc));
  return it != sources.end() ? it->second.first : Handle{};
}

void OiioTextureImages::startDecoding() {
  std::lock_guard lock(mutex);
  for (auto& [name, src] : pending) {
    decoding.run([s = src] { ensureDecoded(*s); });
    encoded.push_back({name, src});
  }
  pending.clear();
}

std::vector<std::pair<std::string, std::string>> OiioTextureImages::waitForDecodes() {
  startDecoding();
  decoding.wait();
  std::vector<std::pair<std::string, std::string>> failed;
  std::lock_guard lock(mutex);
  for (auto& [name, src] : encoded)
    if (!ensureDecoded(*src)) failed.emplace_back(name, src->error);
  return failed;
}

EncodedImageInfo probeEncodedImage(const std::string& bytes) {
  OIIO::Filesystem::IOMemReader mem(bytes.data(), bytes.size());
  std::string error;
  auto in = openEncoded(bytes, &mem, &error);
  if (!in) throw std::runtime_error(error);
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width < 1 || spec.height < 1 || spec.nchannels < 1 || spec.nchannels > 4)
    throw std::runtime_error("a " + std::to_string(spec.width) + "x" +
                             std::to_string(spec.height) + " image of " +
                             std::to_string(spec.nchannels) +
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

Handle OiioTextureImages::addFile(const std::string& path, ColorEncoding enc) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw std::runtime_error(path + ": no such file");
  auto remember = [&](Handle h) {
    std::lock_guard lock(mutex);
    sources[fileSourceKey(path, enc)] = {h, nullptr};
    return h;
  };
  if (enc == ColorEncoding::Linear) return remember(open(path, path, nullptr));
  // The cache does not pass on why one of glint's ImageInputs failed to open, so open the
  // file once here (header only) for a helpful message.
  if (auto probe = OIIO::ImageInput::open(path); !probe)
    throw std::runtime_error(path + ": " + oneLine(OIIO::geterror()));
  // The same file may be added twice: the cache then shares it.
  std::string key = prefix + "srgb:" + path;
  auto src = std::make_shared<Source>();
  src->path = path;
  {
    std::lock_guard lock(mutex);
    registered.push_back(key);
  }
  Registry::add(key, std::move(src));
  return remember(open(path, key, &createSrgbFileInput));
}

size_t OiioTextureImages::size() const {
  std::lock_guard lock(mutex);
  return images.size();
}

bool OiioTextureImages::contains(const std::string& name) const {
  std::lock_guard lock(mutex);
  return names.count(name) > 0;
}


Vec4f OiioTextureImages::lookup(Handle h, const TexCoord2& c, TextureWrap wrapS, TextureWrap wrapT,
                            TextureFilter filter) const {
  assert(h.image && h.image->owner == this);
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
  if (!ts->texture(image.handle, nullptr, opt, c.st.x, c.st.y, dsdx, dtdx, dsdy, dtdy, n, r))
    throw std::runtime_error(image.name + ": " + takeError(*ts));
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

std::unique_ptr<TextureImages::Backend> newTextureImages() {
  return std::make_unique<OiioTextureImages>();
}

}  // namespace glint::oiio
