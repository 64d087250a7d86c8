// glint — a Film to disk: scene-linear EXR, or display-referred PNG/JPEG/TIFF through exposure,
// tone mapping and an OpenColorIO display/view transform, all through image/io.h's one atomic
// writer. Reading films back (EXR, a render to resume, environment maps) is image/input.h.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "image/io.h"
#include "renderer/film.h"
#include "renderer/render.h"
#include "renderer/settings.h"

namespace glint {

// Scene-linear pixels as a display shows them: exposure, tone mapping with the scale that
// `logAverageLuminance` gives (toneMapScale), then the OCIO display/view transform; interleaved
// RGB, display-encoded, NaN as 0 (not clamped: quantizing clamps). What PNG, JPEG and TIFF
// output hold. Throws ColorError for an unknown display or view.
std::vector<float> displayPixels(std::span<const Rgb> sceneLinear, const ToneMapSettings& tonemap,
                                 double logAverageLuminance);

// glint's metadata of a render of `scene` with `settings` by `integrator` that ended as `result`
// after `seconds` of rendering.
ImageMetadata renderMetadata(const std::string& scene, const RenderSettings& settings,
                             const std::string& integrator, const ProgressiveResult& result,
                             double seconds);

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

}  // namespace glint
