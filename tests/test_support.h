// glint tests — shared helpers: data paths, the shared asset folder, running the CLI.
#pragma once

#include <string>

namespace glint::test {

// Folder of the project's own test data (tests/data).
std::string dataDir();
// The shared asset folder: $GLINT_ASSETS, else the CMake setting (../shared/assets).
std::string assetsDir();
// A fresh, empty scratch folder for one test (under the build tree), named after it.
std::string scratchDir(const std::string& name);

struct CommandResult {
  int exitCode = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};
// Runs the glint executable with `args` (already shell-quoted where needed).
CommandResult runGlint(const std::string& args);

}  // namespace glint::test
