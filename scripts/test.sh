#!/usr/bin/env bash
# One command for a fresh Debian 12 machine: install what is missing, build (RelWithDebInfo),
# and run the whole test suite with ctest. Test data shared with other projects is found
# through GLINT_ASSETS (default: ../shared/assets beside the repository).
#
# Then the robustness stage, scripts/sanitize.sh: the unit tests under AddressSanitizer and
# UndefinedBehaviorSanitizer and a bounded fuzzing run of the scene loaders (build-sanitize).
# GLINT_SKIP_SANITIZE=1 skips it; it only runs when the normal suite passed.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/setup.sh"
# The house's include order (rooms include only rooms below them, no header cycles) and its
# format (clang-format, .clang-format): seconds, so before the build.
python3 "$root/scripts/check_includes.py"
"$root/scripts/check_format.sh"
build_dir="$root/build-tests"
# RelWithDebInfo with line tables only (-g1): a failure's backtrace still names files and
# lines, and the build takes two thirds of the time full debug information does (a test file
# compiled in 28 s with -g, 16.5 s with -g1; the test binaries are 60% of the build).
BUILD_DIR="$build_dir" BUILD_TYPE=RelWithDebInfo "$root/scripts/build.sh" \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG"
(cd "$build_dir" && ctest --output-on-failure --parallel "$(nproc)" --timeout 600 "$@")
if [[ ${GLINT_SKIP_SANITIZE:-0} != 1 ]]; then
  "$root/scripts/sanitize.sh"
fi
