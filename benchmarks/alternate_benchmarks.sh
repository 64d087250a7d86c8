#!/usr/bin/env bash
# Runs shading_bench, path_bench and the features_bench rows the integrators move, from two
# builds alternately (base, new, base, new, ...), so that a change in the machine's load hits
# both; writes one Google Benchmark JSON per (build, benchmark, round) into OUT, which
# benchmarks/alternate_report.py tables.
#
#   benchmarks/alternate_benchmarks.sh BASE_BUILD NEW_BUILD OUT [ROUNDS=3]
#   python3 benchmarks/alternate_report.py OUT
set -euo pipefail
base=$1 new=$2 out=$3 rounds=${4:-3}
mkdir -p "$out"
for round in $(seq 1 "$rounds"); do
  for side in base new; do
    dir=$base
    [[ $side == new ]] && dir=$new
    for bench in shading_bench path_bench; do
      "$dir/benchmarks/$bench" --benchmark_out="$out/$side.$bench.$round.json" \
        --benchmark_out_format=json >/dev/null
    done
    "$dir/benchmarks/features_bench" \
      --benchmark_filter='BM_PlainVsMinimal|BM_Effect_(area_light|fog|texture|glass)' \
      --benchmark_out="$out/$side.features_bench.$round.json" --benchmark_out_format=json >/dev/null
  done
done
