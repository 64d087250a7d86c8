// glint — a Film from disk: a scene-linear EXR, a render to resume, or any scene-linear image
// read as light (environment maps), all through image/io.h's one reader. Writing films is
// image/output.h.
#pragma once

#include <string>

#include "image/io.h"
#include "renderer/film.h"

namespace glint {

// Reads a scene-linear EXR (the R, G, B channels, and A when present, else alpha 1) into a film
// without AOVs; fills *meta from glint's attributes when given. Throws ImageReadError naming
// the file when it is missing, unreadable or has no R, G, B channels.
Film readExr(const std::string& path, ImageMetadata* meta = nullptr);

// Reads what `glint render --resume` continues from: an EXR glint wrote in float, with its
// variance channels (and "samples" when adaptive sampling set each pixel's count; else every
// pixel has glint:spp), AOVs when present, its data window and metadata. When the file cannot
// be continued, returns an empty film (width 0) and says why in *whyNot. Throws ImageReadError
// (DecodeError) when the file cannot be read at all.
Film readRenderState(const std::string& path, ImageMetadata* meta, std::string* whyNot);

// The same for any scene-linear image glint reads as light: OpenEXR or Radiance .hdr
// (environment maps). Throws ImageReadError naming the file for any other format.
Film readSceneLinear(const std::string& path);

}  // namespace glint
