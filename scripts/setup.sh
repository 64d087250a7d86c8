#!/usr/bin/env bash
# Installs the Debian 12 packages glint needs that are missing; quiet and fast when all are
# present (one dpkg-query, no apt-get), then the browser test's npm packages. Safe to run again.
# Uses sudo when not root.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config
  # a compiler cache: a second build of the same sources (another clone, the sanitizer build
  # run again) takes under two minutes instead of a quarter of an hour (compiler_cache.sh)
  ccache
  libembree-dev libtbb-dev
  libopenimageio-dev openimageio-tools libopenexr-dev python3-imath
  libopencolorio-dev opencolorio-tools
  nlohmann-json3-dev libassimp-dev libdraco-dev libmeshoptimizer-dev
  libcli11-dev libfmt-dev
  # VDB media: OpenVDB reads .vdb files (scenes/vdb_file.cpp); NanoVDB (header-only) holds the
  # grids the renderer samples (materials/vdb_volume.h); OpenVDB's headers include Boost's,
  # which libopenvdb-dev does not pull in
  libopenvdb-dev libnanovdb-dev libboost-dev
  # glint preview: the HTTP server (header-only); its browser test drives Debian's Chromium
  # from Node.js (installed below when the machine has no node)
  libcpp-httplib-dev chromium
  libgtest-dev libbenchmark-dev
  # scripts/check_format.sh (.clang-format); scripts/code_size.py finds functions with ctags
  clang-format universal-ctags
  python3 python3-matplotlib
  # scripts/sanitize.sh: Clang with its ASan/UBSan/libFuzzer runtimes and llvm-symbolizer
  clang libclang-rt-14-dev llvm
  # scripts/slurm: the Slurm test and benchmark bring up a one-node cluster on this machine
  slurmctld slurmd slurm-client munge
  # The Python module (python/, docs/python.md): built with pybind11 against Python 3's headers,
  # returns numpy arrays; its tests run under pytest, and the example notebook runs headless
  # through nbclient (nbconvert) on the ipykernel kernel
  pybind11-dev python3-dev python3-numpy python3-pytest
  python3-nbclient python3-nbconvert python3-ipykernel
)

# Node.js and npm for the browser test: Debian's unless the machine already has a node (a
# NodeSource node bundles its own npm, and Debian's npm package would conflict with it).
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  PACKAGES+=(nodejs npm)
fi

# One dpkg-query for all packages; anything not reported as installed is missing.
installed=$(dpkg-query -W -f='${Package} ${db:Status-Status}\n' "${PACKAGES[@]}" 2>/dev/null |
            awk '$2 == "installed" { print $1 }' || true)
missing=()
for pkg in "${PACKAGES[@]}"; do
  grep -qx "$pkg" <<<"$installed" || missing+=("$pkg")
done

if ((${#missing[@]} > 0)); then
  echo "glint setup: installing ${missing[*]}" >&2
  SUDO=""
  if [[ $(id -u) -ne 0 ]]; then
    command -v sudo >/dev/null || { echo "glint setup: need root or sudo to install packages" >&2; exit 1; }
    SUDO="sudo"
  fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# The browser test's npm packages (playwright-core, pinned by tests/browser/package-lock.json);
# it drives the chromium installed above, so no browser is downloaded.
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
if [[ ! -d "$root/tests/browser/node_modules/playwright-core" ]]; then
  echo "glint setup: npm ci in tests/browser" >&2
  npm ci --prefix "$root/tests/browser" --no-audit --no-fund --loglevel=error >/dev/null
fi
