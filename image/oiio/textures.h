// glint — the OpenImageIO plugin's texture half (textures.cpp): the TextureSystem serving texture
// files kept on disk, and the decoders of the images glint keeps in memory.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "materials/image_texture.h"

namespace glint::oiio {

std::unique_ptr<TextureImages::Cache> newTextureCache();
// As the Plugin members of the same names (plugin.h).
EncodedImageInfo probeEncodedImage(const std::string& bytes);
std::vector<float> decodeEncodedImage(const std::string& bytes, EncodedImageInfo* info);
DecodedImage decodeEncoded(const std::string& bytes);
ImageFileInfo probeImageFile(const std::string& path);
DecodedImage decodeImageFile(const std::string& path);

}  // namespace glint::oiio
