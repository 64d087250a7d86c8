// glint — the subcommands of the `glint` executable. Each `add*Command` registers one
// subcommand on the CLI11 app. A subcommand reports what went wrong by throwing a glint::Error
// (geometry/error.h); apps/main.cpp alone turns it into the exit code.
#pragma once

#include <CLI/CLI.hpp>

namespace glint::app {

void addRenderCommand(CLI::App& app);
void addInfoCommand(CLI::App& app);
// Sets *differ when the images differ beyond the thresholds: not an error but diff's answer,
// which main gives as exit code 1.
void addDiffCommand(CLI::App& app, bool* differ);
void addBenchAccelCommand(CLI::App& app);
void addTonemapCommand(CLI::App& app);
void addAssembleCommand(CLI::App& app);
void addPreviewCommand(CLI::App& app);

}  // namespace glint::app
