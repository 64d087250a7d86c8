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
build_dir="$root/build-tests"
BUILD_DIR="$build_dir" BUILD_TYPE=RelWithDebInfo "$root/scripts/build.sh"
(cd "$build_dir" && ctest --output-on-failure --parallel "$(nproc)" --timeout 600 "$@")
if [[ ${GLINT_SKIP_SANITIZE:-0} != 1 ]]; then
  "$root/scripts/sanitize.sh"
fi
