// glint — the subcommands of the `glint` executable. Each `add*Command` registers one
// subcommand on the CLI11 app. A subcommand reports what went wrong by throwing a glint::Error
// (geometry/error.h), and how a command that did its work ended in its Outcome; apps/main.cpp
// alone turns either into the exit code.
#pragma once

#include <CLI/CLI.hpp>

namespace glint::app {

// How a command that ran to its end (no error) ended, when that is more than "done": answers
// main gives as exit codes, though nothing went wrong.
struct Outcome {
  bool imagesDiffer = false;  // diff: beyond the thresholds (exit code 1)
  int interruptedBy = 0;      // render: the signal that stopped it, its outputs written
                              // (exit code 128 + signal, as the shell reports a signal)
};

// Sets outcome->interruptedBy when Ctrl-C or SIGTERM stopped the render (apps/interrupt.h).
void addRenderCommand(CLI::App& app, Outcome* outcome);
void addInfoCommand(CLI::App& app);
// Sets outcome->imagesDiffer when the images differ beyond the thresholds: not an error but
// diff's answer.
void addDiffCommand(CLI::App& app, Outcome* outcome);
void addBenchAccelCommand(CLI::App& app);
void addTonemapCommand(CLI::App& app);
void addAssembleCommand(CLI::App& app);
void addPreviewCommand(CLI::App& app);

}  // namespace glint::app
