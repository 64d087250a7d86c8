// glint — image textures: a set of images with filtered lookups and wrap modes, from images in
// memory (glTF buffers) or files, decoded from sRGB or linear.
//
// Where each image's texels live is chosen per image (TextureStorage):
// - In memory, as a MipMap (mipmap.h): every image glint decodes whole anyway (glTF's PNG and
//   JPEG bytes, pixels handed over, and image files of moderate size). 8-bit images stay 8-bit.
// - In OpenImageIO's TextureSystem (image/oiio/textures.cpp, in the OpenImageIO plugin, loaded
//   on first use): files that are tiled and MIP-mapped already (a `.tx` made by maketx, a tiled
//   EXR with MIP levels), which the cache pages in tile by tile within a memory budget, and
//   files too large to hold decoded (kMemoryLimitBytes).
// OpenImageIO decodes the images in memory too (the plugin's decoders), but never looks them up.
// Materials never name the plugin: a set is given its decoder (ImageDecoder, below) by the one
// who makes it, the scene builder (the rooms' order, docs/layout.md).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "materials/mipmap.h"
#include "materials/texture.h"

namespace glint {

// Where an image's texels live. Auto: the TextureSystem for tiled, MIP-mapped files and files
// over kMemoryLimitBytes decoded, memory for everything else.
enum class TextureStorage { Auto, Memory, Cache };
const char* textureStorageName(TextureStorage s);  // "memory", "cache" ("auto")

// What a decoder makes of an image: 8-bit samples as their bytes, deeper ones as floats; values
// in [0, 1] as stored (no colour decoding), `channels` per pixel, rows top to bottom.
struct DecodedImage {
  int width = 0, height = 0, channels = 0;
  std::vector<uint8_t> bytes;
  std::vector<float> floats;
};

// An encoded image file in memory, as OpenImageIO reads it (PNG, JPEG, WebP, BMP, GIF).
struct EncodedImageInfo {
  int width = 0, height = 0, channels = 0;
  int bits = 8;  // per channel as stored: 8, or 16 (and more) otherwise
};

// An image file's header: what choosing its storage needs.
struct ImageFileInfo {
  int width = 0, height = 0, channels = 0;
  int bits = 8;        // per channel as stored (8, 16, 32)
  bool tiled = false;  // stored in tiles
  int mipLevels = 1;   // MIP levels stored in the file
};

class ImageDecoder;
// Where a set finds its decoder, asked on first need (glint's is OpenImageIO's plugin, loaded
// then: a scene without image textures never loads it).
using ImageDecoderSource = const ImageDecoder& (*)();

// A set of images. Lookups are thread-safe and deterministic; add images before looking them
// up (adding is thread-safe too, and never disturbs lookups of images added earlier).
class TextureImages {
 public:
  struct Image;  // one image of the set (image_texture.cpp)
  // Names one image of this set; default-constructed = invalid.
  struct Handle {
    const Image* image = nullptr;
    bool valid() const { return image != nullptr; }
  };
  // Decoded files over this size (level 0) stay in the TextureSystem's cache.
  static constexpr size_t kMemoryLimitBytes = size_t(1) << 30;

  // `decoder` decodes the encoded images and files added (the scene builder gives OpenImageIO's
  // plugin, image/oiio/plugin.h: materials know no codec). Sets of decoded pixels alone need
  // none; adding an encoded image or a file to such a set throws std::logic_error.
  explicit TextureImages(ImageDecoderSource decoder = nullptr);
  ~TextureImages();
  TextureImages(const TextureImages&) = delete;
  TextureImages& operator=(const TextureImages&) = delete;

  // Pixels already decoded in memory: `channels` (1..4) floats per pixel, as stored (sRGB-encoded
  // when enc == Srgb), rows top to bottom. `name` names the image in messages and must be unique
  // within this set. Throws std::logic_error on bad sizes or a repeated name: the scene builder
  // makes both from decoded images, so either is a bug.
  Handle addPixels(const std::string& name, int width, int height, int channels,
                   const std::vector<float>& pixels, ColorEncoding enc);
  // The same for 8-bit samples, kept 8-bit (their colour channels sRGB-encoded when enc ==
  // Srgb, decoded on lookup), as a glTF PNG or JPEG is once decoded.
  Handle addBytes(const std::string& name, int width, int height, int channels,
                  std::vector<uint8_t> pixels, ColorEncoding enc);
  // An encoded image file held in memory (a glTF image: PNG, JPEG, WebP, ...), its size known
  // from the header at once and its pixels decoded later, once: by startDecoding's background
  // tasks (several images decode in parallel while the caller goes on), or else by the first
  // lookup that needs them. Kept in memory: 8-bit images as bytes, others as floats. Throws
  // InputError("<name>: <reason>") when the header cannot be read, and std::logic_error for a
  // repeated name.
  Handle addEncoded(const std::string& name, std::shared_ptr<const std::string> bytes,
                    ColorEncoding enc);
  // Starts decoding every encoded image added so far, on TBB tasks; returns at once.
  void startDecoding();
  // Starts and waits for all of them; returns those whose pixels cannot be decoded, as
  // (name, reason), in the order they were added.
  std::vector<std::pair<std::string, std::string>> waitForDecodes();
  // An image file (PNG, JPEG, EXR, TIFF, ...), stored as `storage` says (Auto: see
  // TextureStorage). In memory it is decoded here, at once. Throws
  // InputError("<path>: <reason>") when it cannot be opened or decoded.
  Handle addFile(const std::string& path, ColorEncoding enc,
                 TextureStorage storage = TextureStorage::Auto);

  // The image this set already holds for the same source, or an invalid handle: an encoded
  // image added under `name` from the very same bytes (the same buffer, not equal contents),
  // or the file `path` added with encoding `enc`. A sequence's frames share one set this way,
  // so each image is decoded once per sequence, not once per frame.
  Handle findEncoded(const std::string& name, const std::string* bytes) const;
  Handle findFile(const std::string& path, ColorEncoding enc) const;

  size_t size() const;                           // how many images the set holds
  bool contains(const std::string& name) const;  // an image added under `name`
  std::vector<Handle> handles() const;           // every image, in the order added

  const std::string& name(Handle h) const;
  int width(Handle h) const;
  int height(Handle h) const;
  int channels(Handle h) const;            // as stored (1..4 are used; more are ignored)
  TextureStorage storage(Handle h) const;  // Memory or Cache
  // The bytes an image in memory holds once decoded (its MIP pyramid; known before decoding),
  // 0 for one in the cache (whose budget bounds what it holds of all its files).
  size_t residentBytes(Handle h) const;
  // One line for `glint info`: size, channels, samples, encoding and where it lives.
  std::string describe(Handle h) const;

  // Filtered linear RGBA at c.st (t = 0 is the top row; outside [0,1] the wrap modes apply),
  // over the footprint c.dstdx, c.dstdy (Mipmap only). Grey images give (g, g, g, a); a
  // missing alpha is 1. Colour is not premultiplied by alpha. Throws InputError("<name>:
  // <reason>") if the image's pixels cannot be read (a file damaged after addFile, an encoded
  // image that does not decode).
  Vec4f lookup(Handle h, const TexCoord2& c, TextureWrap wrapS, TextureWrap wrapT,
               TextureFilter filter) const;

  // The images kept on disk: OpenImageIO's TextureSystem, in the plugin
  // (image/oiio/textures.cpp).
  class Cache {
   public:
    struct File;  // one file of the cache
    virtual ~Cache() = default;
    // Opens `path`, read through `enc`. Both throw std::runtime_error with the reason, which
    // TextureImages gives as an InputError naming the file.
    virtual const File* add(const std::string& path, ColorEncoding enc) = 0;
    virtual Vec4f lookup(const File* f, const TexCoord2& c, TextureWrap wrapS, TextureWrap wrapT,
                         TextureFilter filter) const = 0;
  };

 private:
  const ImageDecoder& decoder() const;  // throws std::logic_error without one
  struct Set;
  std::unique_ptr<Set> set_;
};

// What decodes a TextureImages' images: OpenImageIO's plugin in glint (image/oiio/plugin.h),
// tests may give their own. Each throws std::runtime_error with the reason alone (the plugin
// throws no glint types); TextureImages gives it as an InputError naming the image or file.
class ImageDecoder {
 public:
  virtual ~ImageDecoder() = default;
  // The TextureSystem serving the texture files kept on disk.
  virtual std::unique_ptr<TextureImages::Cache> newTextureCache() const = 0;
  // An encoded image in memory: its header alone (not such an image, or more than 4
  // channels, throws), all of it as floats in [0, 1] as stored, or as decode() keeps it.
  virtual EncodedImageInfo probeEncodedImage(const std::string& bytes) const = 0;
  virtual std::vector<float> decodeEncodedImage(const std::string& bytes,
                                                EncodedImageInfo* info) const = 0;
  virtual DecodedImage decodeEncoded(const std::string& bytes) const = 0;
  // An image file: its header, or all of it.
  virtual ImageFileInfo probeImageFile(const std::string& path) const = 0;
  virtual DecodedImage decodeImageFile(const std::string& path) const = 0;
};

// A Texture reading one image of a TextureImages (which must outlive it) through a mapping.
class ImageTexture final : public Texture {
 public:
  ImageTexture(const TextureImages& images, TextureImages::Handle h, TextureMapping mapping,
               TextureWrap wrapS, TextureWrap wrapT, TextureFilter filter);
  Vec4f evaluate(const TexturePoint& tp) const override;
  TextureNeeds needs() const override {
    return {mapping_.usesUvs(), mapping_.usesObjectSpace(), filter_ == TextureFilter::Mipmap};
  }
  bool isImage() const override { return true; }
  int uvSet() const override { return mapping_.usesUvs() ? mapping_.uvSet : 0; }

 private:
  const TextureImages* images_;
  TextureImages::Handle handle_;
  TextureMapping mapping_;
  TextureWrap wrapS_, wrapT_;
  TextureFilter filter_;
};

}  // namespace glint
