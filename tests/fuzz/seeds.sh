#!/usr/bin/env bash
# Collects the seed corpora of the loader fuzzers from files already in tests/ and scenes/ into
# OUT/{csg,gltf,sidecar} (OUT is emptied first); nothing is copied into the repository.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
out=${1:?usage: seeds.sh OUT}
mkdir -p "$out"
out=$(cd "$out" && pwd)
rm -rf "$out"
mkdir -p "$out/csg" "$out/gltf" "$out/sidecar"
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
for t in csg gltf sidecar; do
  echo "seeds: $t: $(ls "$out/$t" | wc -l) files" >&2
done
