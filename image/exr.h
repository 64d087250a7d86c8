// glint — OpenEXR files through the OpenEXR library itself: the format glint renders to and
// reads back (--resume, assemble, tonemap, diff, environment maps). io.h's readImage and
// writeImageFile call these for EXR; every other format goes through OpenImageIO, in a plugin
// loaded only when needed (image/oiio/plugin.h), so a render that writes EXR never loads it.
//
// The reader presents what OpenImageIO's EXR reader presented, so files read the same either
// way: channels in OpenImageIO's order (by layer, then R G B Y A ... Z, then by name), the data
// and display windows, the storage type, and glint's attributes.
#pragma once

#include <string>

#include "image/io.h"

namespace glint {

// True when the file at `path` starts with OpenEXR's magic number.
bool isExrFile(const std::string& path);

// Reads an OpenEXR file (its first part; scanline or tiled, level 0). Throws DecodeError.
Image readExrImage(const std::string& path, bool pixels);

// Writes `image` (pixels already rounded for Half) to `file` as a ZIP-compressed OpenEXR with
// glint's attributes and `checksum` (glint:checksum). Throws OutputError naming `target`.
void writeExrImage(const std::string& file, const std::string& target, const Image& image,
                   const std::string& checksum);

}  // namespace glint
