// glint — image textures: TextureImages keeps most images in memory as MIP pyramids (mipmap.h)
// and looks them up itself; the set's ImageDecoder (in glint the OpenImageIO plugin,
// image/oiio/, loaded on first use) decodes them, and serves the files kept on disk through its
// TextureSystem.
#include "materials/image_texture.h"

#include <tbb/task_group.h>

#include <atomic>
#include <cstdio>
#include <mutex>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include "geometry/error.h"

namespace glint {

const char* textureStorageName(TextureStorage s) {
  switch (s) {
    case TextureStorage::Memory:
      return "memory";
    case TextureStorage::Cache:
      return "cache";
    case TextureStorage::Auto:
    default:
      return "auto";
  }
}

// ---------------------------------------------------------------------------------------------
// TextureImages
// ---------------------------------------------------------------------------------------------

// One image of a set. In memory: `pyramid`, usable once `ready` (pixels handed over and files
// are ready when added; an encoded image when decoded, once, under `once`). In the cache:
// `file`.
struct TextureImages::Image {
  std::string name;
  int width = 0, height = 0, channels = 0;
  TextureStorage storage = TextureStorage::Memory;
  ColorEncoding encoding = ColorEncoding::Linear;
  MipMap::Texel texel = MipMap::Texel::Float;  // in memory: how the pyramid stores samples
  int bits = 8;                                // as the source stores them
  int fileMipLevels = 1;                       // in the cache: levels stored in the file
  std::atomic<bool> ready{false};
  MipMap pyramid;
  std::shared_ptr<const std::string> encoded;
  std::once_flag once;
  std::string error;  // why an encoded image could not be decoded
  const Cache::File* file = nullptr;
};

struct TextureImages::Set {
  ImageDecoderSource decoder = nullptr;  // set once, by the constructor
  mutable std::mutex mutex;              // guards the members below (adding images)
  std::vector<std::unique_ptr<Image>> images;
  std::unordered_set<std::string> names;  // of addPixels and addEncoded
  // What findEncoded and findFile look up: encodedKey(name) with its bytes, fileKey(path,
  // encoding) with nullptr.
  std::unordered_map<std::string, std::pair<Handle, const void*>> sources;
  // Encoded images not yet handed to a decoding task, and those that were.
  std::vector<Image*> pending, encoded;
  std::unique_ptr<Cache> cache;  // OpenImageIO's TextureSystem, made for the first file it keeps
  tbb::task_group decoding;

  ~Set() { decoding.wait(); }

  static std::string encodedKey(const std::string& name) { return "encoded:" + name; }
  static std::string fileKey(const std::string& path, ColorEncoding enc) {
    return (enc == ColorEncoding::Srgb ? "srgb:" : "linear:") + path;
  }
  // Records `image` (and `name` as taken, unless empty); throws logic_error for a taken name.
  Image* add(std::unique_ptr<Image> image, bool uniqueName) {
    std::lock_guard lock(mutex);
    if (uniqueName && !names.insert(image->name).second)
      throw std::logic_error(image->name + ": an image of this name was already added");
    images.push_back(std::move(image));
    return images.back().get();
  }
};

namespace {

// Runs f, a call of the decoder or its cache about the image `name` (a file's path, or an
// encoded image's name), and gives their std::runtime_error (the OpenImageIO plugin throws no
// glint types, image/oiio/plugin.h) as what it is: the image cannot be read, bad input that
// names it. glint's own errors (a missing plugin is a FailureError) and std::logic_error (a bug)
// pass as they are.
template <class F>
auto readingImage(const std::string& name, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const Error&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw InputError(name + ": " + e.what());
  }
}

MipMap pyramidOf(DecodedImage&& d, ColorEncoding enc) {
  return d.bytes.empty()
             ? MipMap::fromFloats(d.width, d.height, d.channels, std::move(d.floats), enc)
             : MipMap::fromBytes(d.width, d.height, d.channels, std::move(d.bytes), enc);
}

// Decodes an encoded image's pixels, once; false (with the reason in image.error) when they
// cannot be.
bool ensureDecoded(TextureImages::Image& image, ImageDecoderSource decoder) {
  if (image.ready.load(std::memory_order_acquire)) return true;
  if (image.encoded)
    std::call_once(image.once, [&] {
      try {
        image.pyramid = pyramidOf(decoder().decodeEncoded(*image.encoded), image.encoding);
        image.ready.store(true, std::memory_order_release);
      } catch (const std::exception& e) {
        image.error = e.what();
      }
    });
  return image.ready.load(std::memory_order_acquire);
}

std::string mebibytes(size_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f MiB", double(bytes) / (1024.0 * 1024.0));
  return buf;
}

}  // namespace

TextureImages::TextureImages(ImageDecoderSource decoder) : set_(std::make_unique<Set>()) {
  set_->decoder = decoder;
}

const ImageDecoder& TextureImages::decoder() const {
  if (!set_->decoder)
    throw std::logic_error(
        "TextureImages: an encoded image or a file added to a set made "
        "without a decoder");
  return set_->decoder();
}
TextureImages::~TextureImages() = default;

namespace {
// Pixels handed over decoded: checks their size (a wrong one is the caller's bug) and makes the
// image, ready for lookups.
template <class T>
std::unique_ptr<TextureImages::Image> decodedImage(const std::string& name, int width, int height,
                                                   int channels, std::vector<T> pixels,
                                                   ColorEncoding enc) {
  if (width <= 0 || height <= 0 || channels < 1 || channels > 4 ||
      pixels.size() != size_t(width) * size_t(height) * size_t(channels))
    throw std::logic_error(name + ": " + std::to_string(pixels.size()) +
                           (sizeof(T) == 1 ? " bytes" : " floats") + " do not make a " +
                           std::to_string(width) + "x" + std::to_string(height) + " image of " +
                           std::to_string(channels) + " channels");
  auto image = std::make_unique<TextureImages::Image>();
  image->name = name;
  image->width = width, image->height = height, image->channels = channels;
  image->encoding = enc;
  image->bits = int(sizeof(T)) * 8;
  image->texel = sizeof(T) == 1 ? MipMap::Texel::Byte : MipMap::Texel::Float;
  if constexpr (sizeof(T) == 1)
    image->pyramid = MipMap::fromBytes(width, height, channels, std::move(pixels), enc);
  else
    image->pyramid = MipMap::fromFloats(width, height, channels, std::move(pixels), enc);
  image->ready.store(true, std::memory_order_release);
  return image;
}
}  // namespace

TextureImages::Handle TextureImages::addPixels(const std::string& name, int width, int height,
                                               int channels, const std::vector<float>& pixels,
                                               ColorEncoding enc) {
  return Handle{set_->add(decodedImage(name, width, height, channels, pixels, enc), true)};
}

TextureImages::Handle TextureImages::addBytes(const std::string& name, int width, int height,
                                              int channels, std::vector<uint8_t> pixels,
                                              ColorEncoding enc) {
  return Handle{
      set_->add(decodedImage(name, width, height, channels, std::move(pixels), enc), true)};
}

TextureImages::Handle TextureImages::addEncoded(const std::string& name,
                                                std::shared_ptr<const std::string> bytes,
                                                ColorEncoding enc) {
  const EncodedImageInfo info =
      readingImage(name, [&] { return decoder().probeEncodedImage(*bytes); });
  auto image = std::make_unique<Image>();
  image->name = name;
  image->width = info.width, image->height = info.height, image->channels = info.channels;
  image->encoding = enc;
  image->bits = info.bits;
  image->texel = info.bits == 8 ? MipMap::Texel::Byte : MipMap::Texel::Float;
  const void* identity = bytes.get();
  image->encoded = std::move(bytes);
  Image* added = set_->add(std::move(image), true);
  std::lock_guard lock(set_->mutex);
  set_->pending.push_back(added);
  set_->sources[Set::encodedKey(name)] = {Handle{added}, identity};
  return Handle{added};
}

void TextureImages::startDecoding() {
  std::lock_guard lock(set_->mutex);
  for (Image* image : set_->pending) {
    set_->decoding.run([image, d = set_->decoder] { ensureDecoded(*image, d); });
    set_->encoded.push_back(image);
  }
  set_->pending.clear();
}

std::vector<std::pair<std::string, std::string>> TextureImages::waitForDecodes() {
  startDecoding();
  set_->decoding.wait();
  std::vector<std::pair<std::string, std::string>> failed;
  std::lock_guard lock(set_->mutex);
  for (Image* image : set_->encoded)
    if (!ensureDecoded(*image, set_->decoder)) failed.emplace_back(image->name, image->error);
  return failed;
}

TextureImages::Handle TextureImages::addFile(const std::string& path, ColorEncoding enc,
                                             TextureStorage storage) {
  const ImageFileInfo info = readingImage(path, [&] { return decoder().probeImageFile(path); });
  auto image = std::make_unique<Image>();
  image->name = path;
  image->width = info.width, image->height = info.height;
  image->channels = std::min(info.channels, 4);
  image->encoding = enc;
  image->bits = info.bits;
  image->fileMipLevels = info.mipLevels;
  image->texel = info.bits == 8 ? MipMap::Texel::Byte : MipMap::Texel::Float;
  if (storage == TextureStorage::Auto) {
    const size_t decoded = size_t(info.width) * size_t(info.height) * size_t(image->channels) *
                           (image->texel == MipMap::Texel::Byte ? 1 : sizeof(float));
    storage = (info.tiled && info.mipLevels > 1) || decoded > kMemoryLimitBytes
                  ? TextureStorage::Cache
                  : TextureStorage::Memory;
  }
  image->storage = storage;
  if (storage == TextureStorage::Memory) {
    image->pyramid =
        pyramidOf(readingImage(path, [&] { return decoder().decodeImageFile(path); }), enc);
    image->ready.store(true, std::memory_order_release);
  } else {
    std::unique_lock lock(set_->mutex);
    if (!set_->cache) set_->cache = decoder().newTextureCache();
    Cache* cache = set_->cache.get();
    lock.unlock();
    image->file = readingImage(path, [&] { return cache->add(path, enc); });
    image->channels = info.channels;
  }
  Image* added = set_->add(std::move(image), false);
  std::lock_guard lock(set_->mutex);
  set_->sources[Set::fileKey(path, enc)] = {Handle{added}, nullptr};
  return Handle{added};
}

TextureImages::Handle TextureImages::findEncoded(const std::string& name,
                                                 const std::string* bytes) const {
  std::lock_guard lock(set_->mutex);
  auto it = set_->sources.find(Set::encodedKey(name));
  return it != set_->sources.end() && it->second.second == bytes ? it->second.first : Handle{};
}

TextureImages::Handle TextureImages::findFile(const std::string& path, ColorEncoding enc) const {
  std::lock_guard lock(set_->mutex);
  auto it = set_->sources.find(Set::fileKey(path, enc));
  return it != set_->sources.end() ? it->second.first : Handle{};
}

size_t TextureImages::size() const {
  std::lock_guard lock(set_->mutex);
  return set_->images.size();
}

bool TextureImages::contains(const std::string& name) const {
  std::lock_guard lock(set_->mutex);
  return set_->names.count(name) > 0;
}

std::vector<TextureImages::Handle> TextureImages::handles() const {
  std::lock_guard lock(set_->mutex);
  std::vector<Handle> all;
  for (const auto& image : set_->images) all.push_back(Handle{image.get()});
  return all;
}

const std::string& TextureImages::name(Handle h) const { return h.image->name; }
int TextureImages::width(Handle h) const { return h.valid() ? h.image->width : 0; }
int TextureImages::height(Handle h) const { return h.valid() ? h.image->height : 0; }
int TextureImages::channels(Handle h) const { return h.valid() ? h.image->channels : 0; }
TextureStorage TextureImages::storage(Handle h) const { return h.image->storage; }

size_t TextureImages::residentBytes(Handle h) const {
  const Image& image = *h.image;
  if (image.storage == TextureStorage::Cache) return 0;
  return MipMap::residentBytes(image.width, image.height, image.channels, image.texel);
}

std::string TextureImages::describe(Handle h) const {
  const Image& image = *h.image;
  std::string s = image.name + ": " + std::to_string(image.width) + "x" +
                  std::to_string(image.height) + ", " + std::to_string(image.channels) +
                  (image.channels == 1 ? " channel, " : " channels, ") +
                  std::to_string(image.bits) + "-bit " +
                  (image.encoding == ColorEncoding::Srgb ? "sRGB" : "linear") + ", ";
  if (image.storage == TextureStorage::Cache)
    return s + "OpenImageIO's texture cache (" +
           (image.fileMipLevels > 1
                ? std::to_string(image.fileMipLevels) + " MIP levels in the file"
                : std::string("MIP levels made on demand")) +
           ")";
  return s + "in memory (" + (image.texel == MipMap::Texel::Byte ? "8-bit" : "float") +
         " MIP pyramid, " + mebibytes(residentBytes(h)) + ")";
}

Vec4f TextureImages::lookup(Handle h, const TexCoord2& c, TextureWrap wrapS, TextureWrap wrapT,
                            TextureFilter filter) const {
  Image& image = *const_cast<Image*>(h.image);  // decoding on first need fills it in, once
  if (image.ready.load(std::memory_order_acquire))
    return image.pyramid.lookup(c, wrapS, wrapT, filter);
  if (image.file)
    return readingImage(image.name,
                        [&] { return set_->cache->lookup(image.file, c, wrapS, wrapT, filter); });
  if (!ensureDecoded(image, set_->decoder)) throw InputError(image.name + ": " + image.error);
  return image.pyramid.lookup(c, wrapS, wrapT, filter);
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
