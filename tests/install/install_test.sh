#!/usr/bin/env bash
# `cmake --install` into a fresh prefix, then the installed glint on its own: it must find its
# OpenImageIO plugin in PREFIX/lib/glint and its OpenColorIO config in PREFIX/share/glint,
# not the build folder's plugin or the source tree's config that a glint run from the build
# folder uses (image/install_layout.h).
# Usage: install_test.sh BUILD_DIR
set -euo pipefail
build=$1
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT

cmake --install "$build" --prefix "$prefix" >"$prefix/install.log"
for f in bin/glint lib/glint/libglint_oiio.so lib/glint/libglint_openvdb.so share/glint/ocio/config.ocio; do
  [[ -f "$prefix/$f" ]] || { echo "FAIL: cmake --install made no $f"; cat "$prefix/install.log"; exit 1; }
done

cat >"$prefix/ball.json" <<'JSON'
{"render": {"width": 32, "height": 24, "spp": 2},
 "cameras": [{"name": "c", "position": [0, 0, 4], "look_at": [0, 0, 0], "yfov_degrees": 40}],
 "lights": [{"type": "point", "position": [2, 3, 4], "intensity": 30}],
 "materials": [{"name": "m", "type": "lambert", "diffuse": [0.7, 0.4, 0.2]}],
 "objects": [{"type": "sphere", "radius": 1, "material": "m"}]}
JSON

# A PNG needs the plugin: glibc's loader names the file it opened (LD_DEBUG=files).
env -u GLINT_OIIO_PLUGIN -u OCIO LD_DEBUG=files "$prefix/bin/glint" render "$prefix/ball.json" \
  -o "$prefix/ball.exr" -o "$prefix/ball.png" --quiet 2>"$prefix/ld.log" || { echo "FAIL: installed glint render"; tail -20 "$prefix/ld.log"; exit 1; }
[[ -s "$prefix/ball.png" ]] || { echo "FAIL: no PNG written"; exit 1; }
grep -q "file=$prefix/lib/glint/libglint_oiio.so" "$prefix/ld.log" ||
  { echo "FAIL: the plugin was not loaded from $prefix/lib/glint:"; grep -i "glint_oiio" "$prefix/ld.log" | head; exit 1; }

# The config: an unknown display's error names the config glint loaded.
set +e
msg=$(env -u OCIO "$prefix/bin/glint" tonemap "$prefix/ball.exr" -o "$prefix/x.png" --display Nope 2>&1)
rc=$?
set -e
[[ $rc -eq 2 ]] || { echo "FAIL: expected exit code 2 for an unknown display, got $rc: $msg"; exit 1; }
[[ "$msg" == *"'$prefix/share/glint/ocio/config.ocio'"* ]] ||
  { echo "FAIL: the installed glint did not use the installed config: $msg"; exit 1; }
echo "PASS: installed glint uses $prefix/lib/glint and $prefix/share/glint"
