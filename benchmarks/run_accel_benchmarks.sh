#!/usr/bin/env bash
# Runs `glint bench-accel` on the Stanford meshes and writes the comparison report:
#   benchmarks/results/accel/NAME.json            one run per mesh (every backend)
#   benchmarks/results/accel/NAME_subN.json       the build-time scaling study: NAME cut to N
#                                                 triangles with --subsample
#   benchmarks/results/accel.md, accel.png        made by benchmarks/accel_report.py
#
# The meshes are read as the original .ply files through Assimp (the .glb copies hold the same
# vertices; tests/scenes/mesh_import_test.cpp checks the bunny's), from $GLINT_ASSETS/stanford
# (default ../shared/assets; benchmarks/get_assets.sh fetches them). Build in Release first
# (scripts/build.sh); BUILD_DIR names the build folder (default: build).
#
# Usage: benchmarks/run_accel_benchmarks.sh [--mesh NAME]... [--accel LIST] [--no-scaling]
#   --mesh NAME     only this mesh (repeatable; default: bun_zipper dragon_vrip_res2 dragon_vrip)
#   --accel LIST    backends, comma-separated (default: every backend glint knows)
#   --no-scaling    skip the subsampled runs
#   --scaling-mesh NAME   the mesh the subsamples are cut from (default: dragon_vrip); sizes
#                   at or above its triangle count are skipped
# Results are regenerated, never edited by hand; old JSON files of the meshes run are replaced.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build}
assets=${GLINT_ASSETS:-$root/../shared/assets}
out=$root/benchmarks/results/accel
glint=$build/glint

meshes=()
accel=()
scaling=1
scaling_mesh=dragon_vrip
sizes=(10000 30000 100000 300000)
while (($#)); do
  case $1 in
    --mesh) meshes+=("$2"); shift 2 ;;
    --accel) accel=(--accel "$2"); shift 2 ;;
    --no-scaling) scaling=0; shift ;;
    --scaling-mesh) scaling_mesh=$2; shift 2 ;;
    -h|--help) sed -n '2,21p' "$0"; exit 0 ;;
    *) echo "run_accel_benchmarks: unknown option $1" >&2; exit 2 ;;
  esac
done
((${#meshes[@]})) || meshes=(bun_zipper dragon_vrip_res2 dragon_vrip)

[[ -x $glint ]] || { echo "run_accel_benchmarks: $glint not found; build first (BUILD_DIR)" >&2; exit 1; }
mkdir -p "$out"

mesh_path() {
  local path=$assets/stanford/$1.ply
  [[ -f $path ]] || { echo "run_accel_benchmarks: $path not found; see benchmarks/get_assets.sh" >&2; exit 1; }
  echo "$path"
}

for name in "${meshes[@]}"; do
  path=$(mesh_path "$name")
  echo "== $name" >&2
  "$glint" bench-accel "$path" "${accel[@]}" --embree-high-quality --json "$out/$name.json"
done

if ((scaling)); then
  path=$(mesh_path "$scaling_mesh")
  triangles=$("$glint" info "$path" | awk '/^meshes:/ { gsub(/\(/, "", $3); print $3 }')
  for n in "${sizes[@]}"; do
    if ((n >= triangles)); then
      echo "== $scaling_mesh: skipping $n triangles (it has $triangles)" >&2
      continue
    fi
    echo "== $scaling_mesh cut to $n triangles" >&2
    "$glint" bench-accel "$path" "${accel[@]}" --subsample "$n" --json "$out/${scaling_mesh}_sub$n.json"
  done
fi

# Debian's python3-matplotlib belongs to the system Python; a pyenv or venv python3 earlier on
# PATH may not have it.
python=${PYTHON:-python3}
if ! "$python" -c 'import matplotlib' 2>/dev/null && [[ -x /usr/bin/python3 ]]; then
  python=/usr/bin/python3
fi
"$python" "$root/benchmarks/accel_report.py" "$out" \
  --markdown "$root/benchmarks/results/accel.md" --plot "$root/benchmarks/results/accel.png"
