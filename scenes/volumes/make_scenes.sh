#!/usr/bin/env bash
# Writes cloud.vdb and fire.vdb into this folder (tools/make_vdb_scenes.cpp, libopenvdb) and
# renders cloud.png and fire.png with BUILD's glint (default: build, a Release build).
#   scenes/volumes/make_scenes.sh [BUILD]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-$here/../../build}
cmake --build "$build" --target glint glint_make_vdb_scenes >/dev/null
"$build/tools/glint_make_vdb_scenes" "$here"
"$build/glint" render "$here/cloud.json" -o "$here/cloud.png" --stats "$here/cloud.stats.json"
"$build/glint" render "$here/fire.json" -o "$here/fire.png" --stats "$here/fire.stats.json"
