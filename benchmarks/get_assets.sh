#!/usr/bin/env bash
# Documents (and, where the network allows, performs) how to obtain the shared assets that
# glint's tests and benchmarks read through GLINT_ASSETS (default: ../shared/assets beside
# the repository). Nothing here is committed to the repository or fetched at build time.
#
# Layout expected under $GLINT_ASSETS:
#   stanford/bun_zipper.ply, bun_zipper.glb             Stanford bunny, 69,451 triangles
#   stanford/dragon_vrip_res2.ply, dragon_vrip_res2.glb Stanford dragon, 202,520 triangles
#   stanford/dragon_vrip.ply, dragon_vrip.glb           Stanford dragon, 871,414 triangles
#   gltf/<Model>/<variant>/...                          Khronos glTF-Sample-Models (Box,
#       BoxInterleaved, BoxTextured, SimpleMeshes, Triangle, TriangleWithoutIndices,
#       TextureCoordinateTest, ...), variants glTF/, glTF-Embedded/, glTF-Binary/
#
# Sources:
#   Stanford 3D Scanning Repository: http://graphics.stanford.edu/data/3Dscanrep/
#     bunny.tar.gz -> bunny/reconstruction/bun_zipper.ply
#     dragon_recon.tar.gz -> dragon_recon/dragon_vrip.ply, dragon_vrip_res2.ply
#   Khronos glTF sample models: https://github.com/KhronosGroup/glTF-Sample-Models (2.0/)
# The .glb files are made from the PLYs with assimp (Debian package assimp-utils):
#   assimp export NAME.ply NAME.glb -fglb2
set -euo pipefail

dest=${GLINT_ASSETS:-$(cd "$(dirname "$0")/../.." && pwd)/shared/assets}
echo "assets folder: $dest"
mkdir -p "$dest/stanford" "$dest/gltf"

fetch() {  # url file
  if [[ -f "$2" ]]; then return 0; fi
  echo "downloading $1"
  curl -fL --retry 2 -o "$2.part" "$1" && mv "$2.part" "$2"
}

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
if [[ ! -f "$dest/stanford/bun_zipper.ply" ]]; then
  fetch http://graphics.stanford.edu/pub/3Dscanrep/bunny.tar.gz "$tmp/bunny.tar.gz"
  tar -xzf "$tmp/bunny.tar.gz" -C "$tmp"
  cp "$tmp/bunny/reconstruction/bun_zipper.ply" "$dest/stanford/"
fi
if [[ ! -f "$dest/stanford/dragon_vrip.ply" ]]; then
  fetch http://graphics.stanford.edu/pub/3Dscanrep/dragon/dragon_recon.tar.gz "$tmp/dragon.tar.gz"
  tar -xzf "$tmp/dragon.tar.gz" -C "$tmp"
  cp "$tmp/dragon_recon/dragon_vrip.ply" "$tmp/dragon_recon/dragon_vrip_res2.ply" "$dest/stanford/"
fi
if command -v assimp >/dev/null; then
  for name in bun_zipper dragon_vrip_res2 dragon_vrip; do
    [[ -f "$dest/stanford/$name.glb" ]] || assimp export "$dest/stanford/$name.ply" "$dest/stanford/$name.glb" -fglb2
  done
else
  echo "install assimp-utils to convert the PLY files to .glb" >&2
fi
if [[ ! -d "$dest/gltf/Box" ]]; then
  echo "Khronos samples: clone https://github.com/KhronosGroup/glTF-Sample-Models and copy"
  echo "the model folders listed above from its 2.0/ folder into $dest/gltf/"
fi
