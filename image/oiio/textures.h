// glint — the OpenImageIO plugin's texture half (textures.cpp): TextureImages' backend on a
// TextureSystem, and encoded images in memory read through OpenImageIO.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "materials/image_texture.h"

namespace glint::oiio {

std::unique_ptr<TextureImages::Backend> newTextureImages();
// As probeEncodedImage and decodeEncodedImage in materials/image_texture.h.
EncodedImageInfo probeEncodedImage(const std::string& bytes);
std::vector<float> decodeEncodedImage(const std::string& bytes, EncodedImageInfo* info);

}  // namespace glint::oiio
