#!/usr/bin/env bash
# Re-renders the reference images in tests/images/references from tests/images/scenes with a
# Release build of glint (BUILD_DIR, default build). Run after an intended change to what
# these scenes look like, look at the new images, and commit them with the change.
#
# Two kinds of scene:
#   NAME.json        a glint scene, rendered as `glint render NAME.json`;
#   NAME.glint.json  a sidecar for one of the shared Khronos glTF samples (ASSETS below, read
#                    from $GLINT_ASSETS, default ../shared/assets beside the repository),
#                    rendered as `glint render ASSET --sidecar NAME.glint.json`. A missing asset
#                    is an error. tests/apps/image_reference_test.cpp holds the same list.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
glint=${BUILD_DIR:-$root/build}/glint
assets=${GLINT_ASSETS:-$root/../shared/assets}
scenes=$root/tests/images/scenes
references=$root/tests/images/references

# name (tests/images/scenes/NAME.glint.json) -> asset path under $assets
declare -A ASSETS=(
  [box_textured]=gltf/BoxTextured/glTF/BoxTextured.gltf
  [texture_coordinate_test]=gltf/TextureCoordinateTest/glTF/TextureCoordinateTest.gltf
  [normal_tangent_test]=gltf/NormalTangentTest/glTF/NormalTangentTest.gltf
)

for scene in "$scenes"/*.json; do
  case $scene in *.glint.json) continue ;; esac
  name=$(basename "$scene" .json)
  "$glint" render "$scene" --quiet -o "$references/$name.exr" -o "$references/$name.png"
  echo "updated $name"
done

for sidecar in "$scenes"/*.glint.json; do
  name=$(basename "$sidecar" .glint.json)
  if [[ -z ${ASSETS[$name]:-} ]]; then
    echo "$sidecar: no asset listed for '$name' in $0" >&2
    exit 1
  fi
  asset=$assets/${ASSETS[$name]}
  if [[ ! -f $asset ]]; then
    echo "$asset: missing (set GLINT_ASSETS to the shared asset folder)" >&2
    exit 1
  fi
  "$glint" render "$asset" --sidecar "$sidecar" --quiet \
    -o "$references/$name.exr" -o "$references/$name.png"
  echo "updated $name"
done
