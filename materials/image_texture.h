// glint — image textures through OpenImageIO's TextureSystem: MIP-mapped, filtered lookups with
// wrap modes, from images in memory (glTF buffers) or files, decoded from sRGB or linear.
//
// OpenImageIO stays behind this header (glint_materials links it privately).
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
  struct Image;

 public:
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
  // An image file (PNG, JPEG, EXR, TIFF, ...), read on demand by the cache. Throws
  // std::runtime_error("<path>: <reason>") when it cannot be opened.
  Handle addFile(const std::string& path, ColorEncoding enc);

  int width(Handle h) const;
  int height(Handle h) const;
  int channels(Handle h) const;  // as stored (1..4 are used; more are ignored)

  // Filtered linear RGBA at c.st (t = 0 is the top row; outside [0,1] the wrap modes apply),
  // over the footprint c.dstdx, c.dstdy (Mipmap only). Grey images give (g, g, g, a); a
  // missing alpha is 1. Colour is not premultiplied by alpha. Throws std::runtime_error if
  // the image's pixels cannot be read (a file damaged after addFile).
  Vec4f lookup(Handle h, const TexCoord2& c, TextureWrap wrapS, TextureWrap wrapT,
               TextureFilter filter) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
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

 private:
  const TextureImages* images_;
  TextureImages::Handle handle_;
  TextureMapping mapping_;
  TextureWrap wrapS_, wrapT_;
  TextureFilter filter_;
};

}  // namespace glint
