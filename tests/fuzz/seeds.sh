#!/usr/bin/env bash
# Collects the seed corpora of the loader fuzzers from files already in tests/ and scenes/ into
# OUT/{csg,gltf,sidecar,dict} (OUT is emptied first); nothing is copied into the repository.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
out=${1:?usage: seeds.sh OUT}
mkdir -p "$out"
out=$(cd "$out" && pwd)
rm -rf "$out"
mkdir -p "$out/csg" "$out/gltf" "$out/sidecar" "$out/dict"
cd "$root"

# Copies FILES into folder $1, prefixed with their parent folder so names stay unique.
collect() {
  local dest=$1
  shift
  local f
  for f in "$@"; do
    # Files far above the fuzzers' -max_len (scenes/demo/demo.gltf, 250 KB) would only be
    # truncated; they add nothing but start-up time.
    (($(stat -c %s "$f") <= 65536)) || continue
    cp "$f" "$dest/$(basename "$(dirname "$f")")_$(basename "$f")"
  done
}

collect "$out/csg" $(find tests scenes -name '*.csg')
collect "$out/gltf" $(find tests scenes -name '*.gltf' -o -name '*.glb')
collect "$out/sidecar" $(find tests scenes -name '*.json' -not -path '*/references/*')
# The dict target's: the sidecars as load dicts, and small [load, patch, options] calls over
# triangle.gltf (a material, a light, a camera changed; render options) and a scene dict.
collect "$out/dict" $(find tests/data/sidecar -name '*.json')
seed() { printf '%s\n' "$2" >"$out/dict/$1.json"; }
seed material '[{"materials": [{"name": "Red", "type": "lambert", "diffuse": [0.8, 0.1, 0.1]}]},
 {"materials": [{"name": "Red", "diffuse": [0.1, 0.8, 0.1], "emissive": [1, 1, 1]}]},
 {"seed": 3, "integrator": "path"}]'
seed light '[{"lights": [{"name": "Sun", "type": "directional", "direction": [0, -1, 0],
 "intensity": 2}]}, {"lights": [{"name": "Bulb", "type": "point", "position": [0, 1, 1]}]}, {}]'
seed camera '[{}, {"cameras": [{"name": "Top", "type": "perspective", "position": [0, 0, 3],
 "look_at": [0, 0, 0]}]}, {"camera": "Top", "aovs": true}]'
seed scene '[{"gltf": ["triangle.gltf"], "materials": [{"name": "Glow", "type": "lambert",
 "emissive": [2, 2, 2]}], "objects": [{"name": "Ball", "type": "sphere", "radius": 0.5,
 "material": "Glow"}]}, {"materials": [{"name": "Glow", "emissive": [0, 1, 0]}]}, null]'
for t in csg gltf sidecar dict; do
  echo "seeds: $t: $(ls "$out/$t" | wc -l) files" >&2
done
