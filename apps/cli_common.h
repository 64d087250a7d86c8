// glint — pieces shared by the subcommands: scene options, overrides, error reporting, atomic
// text output.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "image/io.h"
#include "scenes/description.h"

namespace glint::app {

// Options that change how a scene is rendered; the command line wins over the sidecar.
struct SceneOverrides {
  std::optional<int> width, height, spp, threads;
  std::optional<uint64_t> seed;
  std::optional<std::string> accel, camera, integrator, lightSampler;
  std::optional<int> maxDepth;
  std::optional<float> adaptive;  // adaptive sampling threshold
  bool aovs = false;              // EXR output also carries albedo, normal, depth and variance

  // Registers --width --height --spp --seed --threads --accel --camera --integrator
  // --max-depth --light-sampler --adaptive on `cmd`
  // (--aovs is render's own).
  void addOptions(CLI::App* cmd);
  // Applies the given options to desc->render; throws SceneError (location "command line")
  // for values that cannot work, e.g. an unknown camera name.
  void apply(SceneDescription* desc) const;
};

// Prints "glint: MESSAGE" to stderr.
void printError(const std::string& message);

// Writes `text` to `path` through a temporary file in the same folder and a rename, so a
// failed write never leaves a half-written file. Throws OutputError (image/io.h).
void writeTextAtomically(const std::string& path, const std::string& text);

}  // namespace glint::app
