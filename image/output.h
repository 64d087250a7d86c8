// glint — a Film to and from disk: scene-linear EXR, or display-referred PNG/JPEG/TIFF through
// exposure, tone mapping and an OpenColorIO display/view transform. All through image/io.h's
// one reader and one atomic writer.
#pragma once

#include <string>
#include <vector>

#include "image/io.h"
#include "renderer/film.h"
#include "renderer/settings.h"

namespace glint {

// Writes `film` to `path` (format by extension). The data goes to a temporary file in the same
// folder that is renamed over `path` only when complete: a failed write never leaves a
// half-written file or destroys a previous good image. Throws OutputError.
void writeImage(const std::string& path, const Film& film, const RenderSettings& settings,
                const ImageMetadata& meta);

// Writes a display-referred image (PNG/JPEG/TIFF) of `film`, tone-mapped with the scale that
// `logAverageLuminance` gives (toneMapScale) instead of the film's own statistic: how every
// frame of a sequence shares one Ward scale. Atomic like writeImage. Throws OutputError (also
// for an .exr path: EXR stays scene-linear) or ColorError.
void writeDisplayImage(const std::string& path, const Film& film, const ToneMapSettings& tonemap,
                       double logAverageLuminance, const ImageMetadata& meta);

// Writes `channels` interleaved float channels per pixel as they are (no colour transform; PNG,
// JPEG and TIFF quantize [0, 1]): images that are data, such as an error heat map. Atomic like
// writeImage. Throws OutputError.
void writeRawImage(const std::string& path, int width, int height, int channels,
                   const std::vector<float>& pixels);

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
