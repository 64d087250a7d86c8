#!/bin/bash
# glint on a real Slurm cluster: a one-node cluster on localhost (scripts/slurm/local-cluster:
# Debian's slurmctld, slurmd and munge, a generated slurm.conf in a temporary folder, daemons
# stopped by PID at the end, also on failure) runs scripts/slurm/glint-submit on a small
# animation, 8 frames x 2 tiles at 48x48. The assembled frames and the tone-mapped PNGs must
# equal a local single-process render exactly (samples are keyed by pixel, sample and seed, so
# tiles and thread counts change nothing).
#
# Then a failure: one task fails (a wrapper around glint exits 1 the first time it renders frame
# 5, tile 0), so the jobs that depend on the array never run (the other frames are there all
# the same: the last tile of a frame to finish joins it); the same submission run again submits
# only that tile, and the frames come out right.
#
#   slurm_cluster_test.sh GLINT_EXECUTABLE
# Needs root (slurmd, munged) and the packages scripts/setup.sh installs.
set -euo pipefail

glint=$(realpath "$1")
root=$(cd "$(dirname "$0")/../.." && pwd)
scene=$root/scenes/motion/effects.json
tmp=$(mktemp -d /tmp/glint-slurm-test.XXXXXX)
chmod 755 "$tmp"  # munged runs as the munge user
cluster=$tmp/cluster

cleanup() {
  "$root/scripts/slurm/local-cluster" stop "$cluster" || true
  rm -rf "$tmp"
}
trap cleanup EXIT

fail() {
  echo "FAIL: $*" >&2
  for log in "$tmp"/out/logs/*; do
    [[ -f $log ]] && { echo "--- $log" >&2; tail -n 5 "$log" >&2; }
  done
  exit 1
}

# A port of its own, so a concurrent run (the benchmark, another checkout) does not collide.
port=$((20000 + ($$ % 5000) * 2))
"$root/scripts/slurm/local-cluster" start "$cluster" --port "$port" > /dev/null
export SLURM_CONF=$cluster/slurm.conf

# A glint that fails once, like a task on a node that dies: the first render of frame 5, tile 0.
wrapper=$tmp/glint-failing-once
cat > "$wrapper" <<EOF
#!/bin/bash
if [[ " \$* " == *" --frames 5-5 --tile 0/2 "* && ! -e $tmp/failed-once ]]; then
  touch $tmp/failed-once
  echo "simulated failure" >&2
  exit 1
fi
exec $glint "\$@"
EOF
chmod +x "$wrapper"

render=(-- --width 48 --height 48 --spp 4)
submit() {
  "$root/scripts/slurm/glint-submit" "$scene" --frames 0-7 --tiles 2 --output "$tmp/out" \
    --cpus-per-task 1 --mem 256M --time 10 --glint "$wrapper" "${render[@]}"
}

# Waits (bounded) until none of the jobs is queued or running; prints nothing.
wait_for() {
  local ids
  ids=$(IFS=,; echo "$*")
  for _ in $(seq 600); do  # 300 s
    [[ -z $(squeue -h -j "$ids" 2>/dev/null) ]] && return 0
    sleep 0.5
  done
  squeue >&2
  fail "jobs $ids still queued or running after 300 s"
}

# The states of a job (all tasks of an array), one per line.
states() { scontrol -o show job "$1" | grep -o 'JobState=[A-Z_]*' | cut -d= -f2; }

# --- 1. First submission: one task fails.
jobs=$(submit)
echo "$jobs"
render_job=$(awk '$1 == "render" {print $2}' <<< "$jobs")
assemble_job=$(awk '$1 == "assemble" {print $2}' <<< "$jobs")
tonemap_job=$(awk '$1 == "tonemap" {print $2}' <<< "$jobs")
[[ -n $render_job && -n $assemble_job && -n $tonemap_job ]] || fail "expected three jobs: $jobs"
[[ $(wc -l < "$(ls "$tmp"/out/submit/tasks-*.txt)") -eq 16 ]] || fail "expected 16 render tasks"
wait_for "$render_job" "$assemble_job" "$tonemap_job"
[[ -e $tmp/failed-once ]] || fail "the simulated failure did not happen"
[[ $(states "$render_job" | sort | uniq -c | awk '{print $2 "=" $1}' | tr '\n' ' ') == \
  "COMPLETED=15 FAILED=1 " ]] || fail "render tasks: $(states "$render_job" | sort | uniq -c)"
# kill_invalid_depend: what waited on the array is cancelled, not left pending.
[[ $(states "$assemble_job") == CANCELLED && $(states "$tonemap_job") == CANCELLED ]] ||
  fail "dependent jobs: assemble $(states "$assemble_job"), tonemap $(states "$tonemap_job")"

# The last tile of each frame to finish joined it, though the assemble job never ran: every
# frame but 5 is there.
for f in 0 1 2 3 4 6 7; do
  [[ -f $tmp/out/frames/$(printf 'effects_%04d' "$f").exr ]] || fail "frame $f was not assembled"
done
[[ ! -e $tmp/out/frames/effects_0005.exr ]] || fail "frame 5 was assembled with a tile missing"

# --- 2. The same submission again: only the failed tile is rendered.
rm -f "$tmp"/out/submit/tasks-*.txt
jobs=$(submit)
echo "$jobs"
tasks=$(ls "$tmp"/out/submit/tasks-*.txt)
[[ $(cat "$tasks") == "5 0" ]] || fail "the second submission should render frame 5 tile 0 only, got: $(cat "$tasks")"
read -r -a ids <<< "$(awk '{print $2}' <<< "$jobs" | tr '\n' ' ')"
[[ ${#ids[@]} -eq 3 ]] || fail "expected render, assemble and tonemap jobs: $jobs"
wait_for "${ids[@]}"
for id in "${ids[@]}"; do
  [[ $(states "$id" | sort -u) == COMPLETED ]] || fail "job $id: $(states "$id" | tr '\n' ' ')"
done

# --- 3. Against one local process on 2 threads.
local_out=$tmp/local
"$glint" render "$scene" --frames 0-7 --threads 2 --quiet -o "$local_out/effects_####.exr" \
  "${render[@]:1}"
"$glint" tonemap --sequence --operator ward --scene "$scene" --quiet \
  "$local_out/effects_####.exr" -o "$local_out/png/effects_####.png"
for f in 0 1 2 3 4 5 6 7; do
  name=$(printf 'effects_%04d' "$f")
  "$glint" diff "$tmp/out/frames/$name.exr" "$local_out/$name.exr" --fail 0 > /dev/null ||
    fail "frames/$name.exr differs from the local render"
  "$glint" diff "$tmp/out/png/$name.png" "$local_out/png/$name.png" --fail 0 > /dev/null ||
    fail "png/$name.png differs from the local render"
done

# --- 4. Nothing missing: a third submission renders nothing and leaves the PNGs alone.
jobs=$(submit 2>&1)
grep -q "all 8 frames are complete" <<< "$jobs" || fail "third submission: $jobs"
grep -q "PNGs are up to date" <<< "$jobs" || fail "third submission: $jobs"
echo "PASS: 8 frames x 2 tiles through Slurm equal the local render; a failed task was resubmitted alone"
