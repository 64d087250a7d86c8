// glint — image textures through OpenImageIO's TextureSystem: MIP-mapped, filtered lookups with
// wrap modes, from images in memory (glTF buffers) or files, decoded from sRGB or linear.
//
// OpenImageIO stays behind this header: the TextureSystem lives in the OpenImageIO plugin
// (image/oiio/textures.cpp), which glint loads the first time a scene has an image texture.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "materials/texture.h"

namespace glint {

// Nearest: the closest texel, no MIP maps. Linear: bilinear, no MIP maps. Mipmap: OIIO's
// MIP-mapped lookup, filtered over the footprint (anisotropic, bilinear within each level).
enum class TextureFilter { Nearest, Linear, Mipmap };

// How the stored colour channels are encoded; alpha is always linear.
enum class ColorEncoding { Linear, Srgb };

// A set of images served by one private OpenImageIO TextureSystem (and its ImageCache).
// Lookups are thread-safe and deterministic; add images before looking them up (adding is
// thread-safe too, and never disturbs lookups of images added earlier).
class TextureImages {
 public:
  struct Image;  // one image of the set; defined by the backend
  // Names one image of this set; default-constructed = invalid.
  struct Handle {
    const Image* image = nullptr;
    bool valid() const { return image != nullptr; }
  };

  TextureImages();
  ~TextureImages();
  TextureImages(const TextureImages&) = delete;
  TextureImages& operator=(const TextureImages&) = delete;

  // Pixels already decoded in memory: `channels` (1..4) floats per pixel, as stored (sRGB-encoded
  // when enc == Srgb), rows top to bottom. `name` names the image in messages and must be unique
  // within this set. Throws std::logic_error on bad sizes or a repeated name: the scene builder
  // makes both from decoded images, so either is a bug.
  Handle addPixels(const std::string& name, int width, int height, int channels,
                   const std::vector<float>& pixels, ColorEncoding enc);
  // An encoded image file held in memory (a glTF image: PNG, JPEG, WebP, ...), its size known
  // from the header at once and its pixels decoded later, once: by startDecoding's background
  // tasks (several images decode in parallel while the caller goes on), or else by the first
  // lookup that needs them. 8-bit images are kept as their bytes (linear) or as linearised
  // halves (sRGB), others as floats, with their MIP levels. Throws std::runtime_error when the header cannot be read, and
  // std::logic_error for a repeated name.
  Handle addEncoded(const std::string& name, std::shared_ptr<const std::string> bytes,
                    ColorEncoding enc);
  // Starts decoding every encoded image added so far, on TBB tasks; returns at once.
  void startDecoding();
  // Starts and waits for all of them; returns those whose pixels cannot be decoded, as
  // (name, reason), in the order they were added.
  std::vector<std::pair<std::string, std::string>> waitForDecodes();
  // An image file (PNG, JPEG, EXR, TIFF, ...), read on demand by the cache. Throws
  // std::runtime_error("<path>: <reason>") when it cannot be opened.
  Handle addFile(const std::string& path, ColorEncoding enc);

  // The image this set already holds for the same source, or an invalid handle: an encoded
  // image added under `name` from the very same bytes (the same buffer, not equal contents),
  // or the file `path` added with encoding `enc`. A sequence's frames share one set this way,
  // so each image is decoded once per sequence, not once per frame.
  Handle findEncoded(const std::string& name, const std::string* bytes) const;
  Handle findFile(const std::string& path, ColorEncoding enc) const;

  size_t size() const;  // how many images the set holds
  bool contains(const std::string& name) const;  // an image added under `name`

  int width(Handle h) const;
  int height(Handle h) const;
  int channels(Handle h) const;  // as stored (1..4 are used; more are ignored)

  // Filtered linear RGBA at c.st (t = 0 is the top row; outside [0,1] the wrap modes apply),
  // over the footprint c.dstdx, c.dstdy (Mipmap only). Grey images give (g, g, g, a); a
  // missing alpha is 1. Colour is not premultiplied by alpha. Throws std::runtime_error if
  // the image's pixels cannot be read (a file damaged after addFile).
  Vec4f lookup(Handle h, const TexCoord2& c, TextureWrap wrapS, TextureWrap wrapT,
               TextureFilter filter) const;

 // What serves the set: OpenImageIO's TextureSystem, in the plugin (image/oiio/textures.cpp).
  // Each member does what the TextureImages member of the same name promises.
  class Backend {
   public:
    virtual ~Backend() = default;
    virtual Handle addPixels(const std::string& name, int width, int height, int channels,
                             const std::vector<float>& pixels, ColorEncoding enc) = 0;
    virtual Handle addEncoded(const std::string& name, std::shared_ptr<const std::string> bytes,
                              ColorEncoding enc) = 0;
    virtual void startDecoding() = 0;
    virtual std::vector<std::pair<std::string, std::string>> waitForDecodes() = 0;
    virtual Handle addFile(const std::string& path, ColorEncoding enc) = 0;
    virtual Handle findEncoded(const std::string& name, const std::string* bytes) const = 0;
    virtual Handle findFile(const std::string& path, ColorEncoding enc) const = 0;
    virtual size_t size() const = 0;
    virtual bool contains(const std::string& name) const = 0;
    virtual int width(Handle h) const = 0;
    virtual int height(Handle h) const = 0;
    virtual int channels(Handle h) const = 0;
    virtual Vec4f lookup(Handle h, const TexCoord2& c, TextureWrap wrapS, TextureWrap wrapT,
                         TextureFilter filter) const = 0;
  };

 private:
  std::unique_ptr<Backend> impl_;
};

// An encoded image file in memory, as OpenImageIO reads it (PNG, JPEG, WebP, BMP, GIF).
struct EncodedImageInfo {
  int width = 0, height = 0, channels = 0;
  int bits = 8;  // per channel as stored: 8, or 16 (and more) otherwise
};
// Reads the header alone. Throws std::runtime_error(reason) when it is not such an image or
// has more than 4 channels.
EncodedImageInfo probeEncodedImage(const std::string& bytes);
// Decodes the whole image: samples in [0, 1] as stored (no colour decoding), rows top to
// bottom. Throws std::runtime_error(reason).
std::vector<float> decodeEncodedImage(const std::string& bytes, EncodedImageInfo* info = nullptr);

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
