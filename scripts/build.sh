#!/usr/bin/env bash
# Configures and builds glint into BUILD_DIR (default: build) with BUILD_TYPE
# (default: Release). Extra arguments go to the CMake configure step.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build_dir=${BUILD_DIR:-$root/build}
build_type=${BUILD_TYPE:-Release}
source "$root/scripts/compiler_cache.sh"
cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE="$build_type" \
  "${compiler_cache[@]}" "$@" >/dev/null
cmake --build "$build_dir" --parallel "$(nproc)"
