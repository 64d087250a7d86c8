# Sourced by scripts/build.sh and scripts/sanitize.sh: compile through ccache when it is there
# (scripts/setup.sh installs it). Sets the array `compiler_cache` to the CMake argument that
# does it (empty without ccache).
#
# A clean clone anywhere on the machine hits the cache of an earlier one: paths under the
# repository are hashed relative to it (CCACHE_BASEDIR) and the working directory is not hashed
# (CCACHE_NOHASHDIR; the line tables of a cached object then name the earlier clone's folder).
# The sloppiness lets ccache cache the files compiled with a precompiled header (GLINT_PCH,
# cmake/GlintPch.cmake), and a fresh clone's files, all written within the last second.
compiler_cache=()
if command -v ccache >/dev/null; then
  compiler_cache=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$root}
  export CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-1}
  export CCACHE_SLOPPINESS=${CCACHE_SLOPPINESS:-pch_defines,time_macros,include_file_mtime,include_file_ctime}
  export CCACHE_MAXSIZE=${CCACHE_MAXSIZE:-5G}
fi
