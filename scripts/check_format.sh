#!/usr/bin/env bash
# Fails when a C++ source file differs from what clang-format makes of it (.clang-format at the
# root: Google style at 100 columns). Every tracked .h and .cpp is checked, in a few seconds, so
# scripts/test.sh runs it before the build. To format a file: clang-format -i FILE; to format
# the tree: scripts/check_format.sh --fix.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
mapfile -t files < <(git ls-files '*.h' '*.cpp')
if [[ ${1:-} == --fix ]]; then
  printf '%s\0' "${files[@]}" | xargs -0 -n 32 -P "$(nproc)" clang-format -i
  exit 0
fi
bad=()
for f in "${files[@]}"; do
  clang-format --dry-run -Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if ((${#bad[@]} > 0)); then
  echo "check_format: ${#bad[@]} file(s) are not as clang-format makes them:" >&2
  printf '  %s\n' "${bad[@]}" >&2
  echo "check_format: run scripts/check_format.sh --fix (or clang-format -i FILE)" >&2
  exit 1
fi
echo "check_format: ${#files[@]} files formatted"
