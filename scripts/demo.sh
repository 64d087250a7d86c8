#!/usr/bin/env bash
# One command for a fresh Debian 12 machine: install what is missing, build (Release), and
# render the default demo scene to demo.png and demo.exr in the repository root.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/setup.sh"
BUILD_DIR="$root/build" BUILD_TYPE=Release "$root/scripts/build.sh" -DGLINT_BUILD_TESTS=OFF
"$root/build/glint" render "$root/scenes/demo/demo.gltf" -o "$root/demo.png" -o "$root/demo.exr"
