// glint — image textures: TextureImages hands every call to its backend, OpenImageIO's
// TextureSystem in the OpenImageIO plugin (image/oiio/textures.cpp, loaded on first use).
#include "materials/image_texture.h"

#include <stdexcept>

#include "image/oiio/plugin.h"

namespace glint {

// ---------------------------------------------------------------------------------------------
// TextureImages
// ---------------------------------------------------------------------------------------------

TextureImages::TextureImages() : impl_(oiio::plugin().newTextureImages()) {}
TextureImages::~TextureImages() = default;

TextureImages::Handle TextureImages::addPixels(const std::string& name, int width, int height,
                                               int channels, const std::vector<float>& pixels,
                                               ColorEncoding enc) {
  return impl_->addPixels(name, width, height, channels, pixels, enc);
}

TextureImages::Handle TextureImages::addEncoded(const std::string& name,
                                                std::shared_ptr<const std::string> bytes,
                                                ColorEncoding enc) {
  return impl_->addEncoded(name, std::move(bytes), enc);
}

void TextureImages::startDecoding() { impl_->startDecoding(); }

std::vector<std::pair<std::string, std::string>> TextureImages::waitForDecodes() {
  return impl_->waitForDecodes();
}

TextureImages::Handle TextureImages::addFile(const std::string& path, ColorEncoding enc) {
  return impl_->addFile(path, enc);
}

TextureImages::Handle TextureImages::findEncoded(const std::string& name,
                                                 const std::string* bytes) const {
  return impl_->findEncoded(name, bytes);
}

TextureImages::Handle TextureImages::findFile(const std::string& path, ColorEncoding enc) const {
  return impl_->findFile(path, enc);
}

size_t TextureImages::size() const { return impl_->size(); }
bool TextureImages::contains(const std::string& name) const { return impl_->contains(name); }
int TextureImages::width(Handle h) const { return impl_->width(h); }
int TextureImages::height(Handle h) const { return impl_->height(h); }
int TextureImages::channels(Handle h) const { return impl_->channels(h); }

Vec4f TextureImages::lookup(Handle h, const TexCoord2& c, TextureWrap wrapS, TextureWrap wrapT,
                            TextureFilter filter) const {
  return impl_->lookup(h, c, wrapS, wrapT, filter);
}

EncodedImageInfo probeEncodedImage(const std::string& bytes) {
  return oiio::plugin().probeEncodedImage(bytes);
}

std::vector<float> decodeEncodedImage(const std::string& bytes, EncodedImageInfo* info) {
  return oiio::plugin().decodeEncodedImage(bytes, info);
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
