// glint — the subcommands of the `glint` executable. Each `add*Command` registers one
// subcommand on the CLI11 app; when it runs it stores its exit code in *exitCode
// (0 success, 1 failure, 2 bad input or usage).
#pragma once

#include <CLI/CLI.hpp>

namespace glint::app {

void addRenderCommand(CLI::App& app, int* exitCode);
void addInfoCommand(CLI::App& app, int* exitCode);
void addDiffCommand(CLI::App& app, int* exitCode);
void addBenchAccelCommand(CLI::App& app, int* exitCode);
void addTonemapCommand(CLI::App& app, int* exitCode);
void addAssembleCommand(CLI::App& app, int* exitCode);

}  // namespace glint::app
