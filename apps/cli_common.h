// glint — pieces shared by the subcommands: scene options, overrides, naming the scene in an
// error, output folders, atomic text output.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "image/io.h"
#include "scenes/description.h"
#include "scenes/json_reader.h"

namespace glint::app {

// Options that change how a scene is rendered; the command line wins over the sidecar.
struct SceneOverrides {
  std::optional<int> width, height, spp, threads;
  std::optional<uint64_t> seed;
  std::optional<std::string> accel, camera, integrator, lightSampler;
  std::optional<int> maxDepth;
  std::optional<float> adaptive;  // adaptive sampling threshold
  std::optional<int> adaptiveMinSpp;
  std::optional<float> antialias;  // AdaptiveSettings::contrast
  std::optional<int> subdivide;    // AdaptiveSettings::subdivide
  std::optional<float> jitter;     // AdaptiveSettings::jitter
  bool aovs = false;               // EXR output also carries albedo, normal, depth and variance
  std::optional<std::string> env;  // "studio" or an .exr/.hdr file: replaces the environment
  std::optional<float> envStrength, envRotation;  // the environment's intensity, degrees
  bool noDefaultLight = false;
  std::optional<std::string> variant;  // KHR_materials_variants
  std::optional<std::string> shutter;  // "S" (open for S seconds from the frame) or "OPEN,CLOSE"

  // Registers --width --height --spp --seed --threads --accel --camera --integrator
  // --max-depth --light-sampler --adaptive --adaptive-min-spp --antialias --env --env-strength
  // --env-rotation
  // --no-default-light --variant --shutter on `cmd`
  // (--aovs is render's own).
  void addOptions(CLI::App* cmd);
  // Applies the given options to desc->render; throws SceneError (location "command line")
  // for values that cannot work, e.g. an unknown camera name.
  void apply(SceneDescription* desc) const;
};

// A check for a numeric option whose message reads as the sidecar's range errors do
// ("--width: must be >= 1, got 0", "--min-pass: must be >= 0 and <= 100, got 150"): CLI11's
// PositiveNumber and NonNegativeNumber print their bounds in full, DBL_MAX as a 309-digit
// number, and CLI::Range prints 1e-12 as 0.000000. `whole` options (an int) also reject a
// fraction or a number that does not fit an int. --help shows the range after the option's
// type ("INT:>= 1").
CLI::Validator numberIn(const Range& range, bool whole = false);

// Creates the folder an output `path` goes into when it is missing (a sequence usually goes
// into a folder of its own: -o out/frame_####.exr). Throws OutputError.
void createOutputFolder(const std::string& path);

// Writes `text` to `path` through a temporary file in the same folder and a rename, so a
// failed write never leaves a half-written file. Throws OutputError (image/io.h).
void writeTextAtomically(const std::string& path, const std::string& text);

}  // namespace glint::app
