#!/usr/bin/env bash
# Re-renders the reference images in tests/images/references from tests/images/scenes with a
# Release build of glint (BUILD_DIR, default build). Run after an intended change to what
# these scenes look like, look at the new images, and commit them with the change.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
glint=${BUILD_DIR:-$root/build}/glint
for scene in "$root"/tests/images/scenes/*.json; do
  name=$(basename "$scene" .json)
  "$glint" render "$scene" --quiet -o "$root/tests/images/references/$name.exr"
  "$glint" render "$scene" --quiet -o "$root/tests/images/references/$name.png"
  echo "updated $name"
done
