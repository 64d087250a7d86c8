// glint — `glint assemble`: joins the partial EXRs of `glint render --crop/--tile` into the
// whole frame.
#include <filesystem>
#include <string>
#include <vector>

#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/frames.h"
#include "renderer/image_diff.h"
#include "renderer/output.h"

namespace glint::app {

namespace {

struct AssembleArgs {
  std::vector<std::string> inputs;  // files, or one pattern with a run of '#' for the tile
  std::string output;
};

// The pieces: the files given, where a single argument with a run of '#' stands for every
// existing file it matches (tiles/frame_0001_##.exr: the tile numbers).
std::vector<std::string> pieces(const AssembleArgs& args) {
  if (args.inputs.size() != 1) return args.inputs;
  const FramePattern pattern = parseFramePattern(args.inputs.front());
  if (!pattern.isPattern()) return args.inputs;
  std::vector<std::string> files;
  for (int n : findFrames(pattern, std::nullopt)) files.push_back(pattern.path(n));
  return files;
}

int runAssemble(const AssembleArgs& args) {
  if (std::filesystem::path(args.output).extension() != ".exr") {
    printError(args.output + ": glint assemble writes an EXR");
    return 2;
  }
  std::vector<std::string> files;
  try {
    files = pieces(args);
  } catch (const std::invalid_argument& e) {  // a bad pattern, or nothing matches it
    printError(e.what());
    return 2;
  }
  return runImageCommand([&] {
    assembleExr(files, args.output);
    return 0;
  });
}

}  // namespace

void addAssembleCommand(CLI::App& app, int* exitCode) {
  auto args = std::make_shared<AssembleArgs>();
  CLI::App* cmd = app.add_subcommand(
      "assemble", "join the partial EXRs of `glint render --crop/--tile` into the whole frame");
  cmd->add_option("inputs", args->inputs,
                  "the pieces: EXR files, or one pattern such as 'tiles/f_0001_##.exr'")
      ->required();
  cmd->add_option("-o,--output", args->output, "the whole frame (.exr)")->required();
  cmd->callback([args, exitCode] { *exitCode = runAssemble(*args); });
}

}  // namespace glint::app
