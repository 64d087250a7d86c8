#!/usr/bin/env bash
# The robustness stage (issue 8), run by scripts/test.sh after the normal suite:
#   1. builds glint with Clang, AddressSanitizer + LeakSanitizer + UndefinedBehaviorSanitizer
#      and the libFuzzer targets (GLINT_SANITIZE, GLINT_FUZZ) into build-sanitize;
#   2. runs the unit tests under the sanitizers (any report fails the test);
#   3. runs the Python module's pytest suite with the module built under the same sanitizers;
#   4. fuzzes each scene loader and the module's dict loader (tests/fuzz) for FUZZ_SECONDS on
#      its seed corpus.
# Exits non-zero on a failing test, a sanitizer report or a fuzzer finding; findings are kept
# in build-sanitize/fuzz/findings/TARGET/ (tests/fuzz/README.md: how to turn one into a
# regression test).
#
# Environment:
#   BUILD_DIR      build folder (default: build-sanitize)
#   FUZZ_SECONDS   seconds per fuzz target (default: 45; 0 skips fuzzing)
#   SANITIZE_ALL=1 also run the heavy tests excluded by default (see kHeavyTests below)
#   SANITIZE_FILTER  a gtest filter for the unit tests instead (e.g. 'Gltf*:CsgRpn.*')
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build_dir=${BUILD_DIR:-$root/build-sanitize}
fuzz_seconds=${FUZZ_SECONDS:-45}

"$root/scripts/setup.sh"

# ---- build -----------------------------------------------------------------------------------
# -O2 keeps the renders in the tests fast enough; no -DNDEBUG, so assertions are checked too;
# line tables are all a symbolised stack trace needs.
source "$root/scripts/compiler_cache.sh"
start=$SECONDS
cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only" \
  -DGLINT_SANITIZE=ON -DGLINT_FUZZ=ON -DGLINT_BUILD_BENCHMARKS=OFF -DGLINT_BUILD_PYTHON=ON "${compiler_cache[@]}" >/dev/null
nice cmake --build "$build_dir" --parallel "$(nproc)"
echo "sanitize: build took $((SECONDS - start)) s" >&2

# ---- sanitizer settings ----------------------------------------------------------------------
# Every report is fatal and symbolised; LeakSanitizer runs at exit. The suppressions name only
# third-party code (tests/sanitizers/lsan.supp says why for each).
# new_delete_type_mismatch=0: OpenImageIO 2.4's TextureSystem::destroy deletes its
# TextureSystemImpl through the base class with a sized delete (inside libOpenImageIO, not
# glint); ASan suppression files cannot name this error, so the check is off for all code.
# intercept_tls_get_addr=0: up to LLVM 16 (Debian 12 has 14) the runtime's __tls_get_addr
# interceptor takes a dynamic TLS block whose address is 16 bytes past a page boundary for a
# pre-2.25 glibc header and reads garbage from it; LeakSanitizer's tracer then crashes at exit
# ("Tracer caught signal 11", exit code 1, no leak reported). Dynamic TLS blocks come from
# libraries loaded with dlopen, as the OpenImageIO plugin and its libraries are, so the crash
# hit one run in a few hundred (Mudlet/Mudlet#9809 traced it to the runtime).
export ASAN_OPTIONS=halt_on_error=1:abort_on_error=0:detect_leaks=1:check_initialization_order=1:strict_init_order=1:new_delete_type_mismatch=0:intercept_tls_get_addr=0
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
export LSAN_OPTIONS=suppressions=$root/tests/sanitizers/lsan.supp:print_suppressions=0
export ASAN_SYMBOLIZER_PATH=${ASAN_SYMBOLIZER_PATH:-$(command -v llvm-symbolizer || true)}

# ---- unit tests ------------------------------------------------------------------------------
# Each gtest binary runs once, all its tests in one process (ctest would start a process per
# test: 1400 starts of an instrumented binary cost more than most tests), two binaries at a
# time. A sanitizer report aborts the binary; its log names the test that was running.
# kHeavyTests (a negative gtest filter) leaves out the heavy end-to-end image and statistical
# tests: under ASan they cost minutes, and lighter tests run the same code. SANITIZE_ALL=1 runs
# them too; SANITIZE_FILTER replaces the whole filter (e.g. 'Gltf*').
kHeavyTests='KdTree.MatchesBruteForce*:KdTree.AgreesWithEmbreeOnManyBunnyRays'
kHeavyTests+=':*ImageReference*:*Chi2*:Furnace.*:InstantRadiosity.*:Convergence.*'
kHeavyTests+=':TrowbridgeReitz.SampledVisibleNormalsFollowThePdf'
kHeavyTests+=':CliFrames.*:CliTonemap.*:CliBenchAccel.*:DiffCommand.*'
filter=${SANITIZE_FILTER:-}
if [[ -z $filter ]]; then
  filter='*'
  [[ -n $kHeavyTests && ${SANITIZE_ALL:-0} != 1 ]] && filter="*-$kHeavyTests"
fi
log_dir=$build_dir/sanitize-logs
rm -rf "$log_dir"
mkdir -p "$log_dir"
export GLINT_TEST_OUTPUT=$build_dir/test_output  # what ctest sets for the tests
start=$SECONDS
failed=0
printf '%s\n' "$build_dir"/tests/glint_*_tests |
  xargs -P "$(nproc)" -I{} sh -c \
    'cd "$(dirname "$1")" && "$1" --gtest_filter="$2" >"$3/$(basename "$1").log" 2>&1 ||
     { echo "sanitize: $(basename "$1") FAILED" >&2; exit 1; }' sh {} "$filter" "$log_dir" ||
  failed=1
for log in "$log_dir"/*.log; do
  # The summary line of each binary, and the full report of a failing one.
  if grep -qE '^\[  PASSED  \]' "$log" && ! grep -qE '^\[  FAILED  \]|ERROR: |runtime error' "$log"; then
    echo "sanitize: $(basename "$log" .log): $(grep -E '^\[==========\] [0-9]+ tests' "$log" | tail -1)" >&2
  else
    echo "sanitize: $(basename "$log" .log) failed; the end of $log:" >&2
    grep -E '^\[  FAILED  \]' "$log" >&2 || true
    tail -60 "$log" >&2
    failed=1
  fi
done
echo "sanitize: unit tests took $((SECONDS - start)) s" >&2
((failed == 0)) || exit 1

# ---- the Python module -----------------------------------------------------------------------
# The module's C++ side (python/ and the libraries it links), instrumented as the rest, driven by
# its pytest suite. A shared object built with Clang's -fsanitize=address leaves the runtime out
# (executables link it in), and Debian's python3 (the one the module is built for) is not
# instrumented, so the runtime is preloaded into
# the interpreter, where it must come first: Clang's shared ASan runtime, which holds UBSan's
# handlers too. PYTHONMALLOC=malloc gives Python's objects to malloc, where ASan sees them,
# rather than to pymalloc's arenas. detect_leaks=0 for this run alone: CPython does not free
# its interned strings, modules and numpy's caches at exit, so LeakSanitizer would report the
# interpreter's memory, not glint's; the module's C++ is the rooms' code, whose leaks the unit
# tests above check. The suite's glint executable (the command-line comparisons) has its own
# runtime linked in, and two runtimes in one process abort: a wrapper drops the preload for it
# (and for glint_make_vdb_scenes, which writes the VDB tests' files).
# test_notebook is left out: its 1024-spp reference takes minutes under ASan, through calls
# the other files test. SIGINT is set to its default for the interpreter: a shell that starts
# the stage in the background ignores it, Python then installs no handler of its own, and the
# Ctrl-C test would render on for hours.
start=$SECONDS
unpreloaded() {  # a wrapper of executable $1 without the preload; prints its path
  printf '#!/bin/sh\nunset LD_PRELOAD\nexec "%s" "$@"\n' "$1" >"$1-unpreloaded"
  chmod +x "$1-unpreloaded"
  echo "$1-unpreloaded"
}
glint_unpreloaded=$(unpreloaded "$build_dir/glint")
vdb_tool_unpreloaded=$(unpreloaded "$build_dir/tools/glint_make_vdb_scenes")
if ! (cd "$root/tests/python" &&
      LD_PRELOAD=$(clang++ -print-file-name=libclang_rt.asan-x86_64.so) PYTHONMALLOC=malloc \
      ASAN_OPTIONS=$ASAN_OPTIONS:detect_leaks=0 PYTHONPATH=$build_dir/python \
      GLINT_EXECUTABLE=$glint_unpreloaded GLINT_TEST_DATA=$root/tests/data \
      GLINT_SOURCE_DIR=$root GLINT_TEST_OUTPUT=$build_dir/test_output/python \
      GLINT_MAKE_VDB_SCENES=$vdb_tool_unpreloaded \
      env --default-signal=INT /usr/bin/python3 -m pytest -q -p no:cacheprovider --ignore=test_notebook.py \
        >"$log_dir/python.log" 2>&1); then
  echo "sanitize: the Python suite failed; the end of $log_dir/python.log:" >&2
  tail -60 "$log_dir/python.log" >&2
  exit 1
fi
echo "sanitize: Python suite: $(tail -1 "$log_dir/python.log") in $((SECONDS - start)) s" >&2

# ---- fuzzing ---------------------------------------------------------------------------------
((fuzz_seconds > 0)) || exit 0
fuzz_dir=$build_dir/fuzz
"$root/tests/fuzz/seeds.sh" "$fuzz_dir/seeds"
# One libFuzzer run; returns non-zero on a finding.
fuzz_one() {
  local target=$1
  # glTF seeds reach 6 KB (features.gltf); JSON and CSG seeds stay below 6 KB.
  local max_len=8192
  [[ $target == gltf ]] && max_len=16384
  local dict=$root/tests/fuzz/json.dict
  [[ $target == csg ]] && dict=$root/tests/fuzz/csg.dict
  local corpus=$fuzz_dir/corpus/$target   # grows from run to run; the seeds stay read-only
  local findings=$fuzz_dir/findings/$target
  mkdir -p "$corpus" "$findings"
  local start=$SECONDS status=0
  # -timeout: an input that takes 10 s is a hang; -rss_limit_mb/-malloc_limit_mb: no input of
  # at most max_len bytes may make a loader allocate 512 MB at once or 2 GB in total.
  if ! "$fuzz_dir/fuzz_$target" -max_total_time="$fuzz_seconds" -timeout=10 -rss_limit_mb=2048 \
      -malloc_limit_mb=512 -max_len=$max_len -dict="$dict" -artifact_prefix="$findings/" \
      -print_final_stats=1 "$corpus" "$fuzz_dir/seeds/$target" >"$fuzz_dir/$target.log" 2>&1; then
    echo "sanitize: fuzz_$target FOUND A PROBLEM; log: $fuzz_dir/$target.log" >&2
    grep -E -A30 "^==[0-9]+==ERROR|runtime error|SUMMARY|terminate called|deadly signal" \
      "$fuzz_dir/$target.log" | head -60 >&2 || true
    ls "$findings" >&2
    status=1
  fi
  echo "sanitize: fuzz_$target: $(grep -E '^stat::number_of_executed_units' "$fuzz_dir/$target.log" |
    awk '{print $2}') runs in $((SECONDS - start)) s" >&2
  return $status
}

# The targets run side by side, one per core (each still gets FUZZ_SECONDS of one core): on
# two cores the four take two rounds, 90 s, instead of 180 s one after another.
rm -f "$fuzz_dir/failed"
running=0
for target in csg gltf sidecar dict; do
  if ((running >= $(nproc))); then
    wait -n || true
    running=$((running - 1))
  fi
  { fuzz_one "$target" || touch "$fuzz_dir/failed"; } &
  running=$((running + 1))
done
wait
status=0
[[ -e $fuzz_dir/failed ]] && status=1
exit $status
