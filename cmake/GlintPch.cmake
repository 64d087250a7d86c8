# Precompiled headers for the targets with many source files that include the same heavy
# third-party headers: the test binaries (GoogleTest, nlohmann/json, OpenImageIO's imageio.h)
# and the glint executable (CLI11, fmt, json). Measured on the 2-core machine: a full cold build
# gains nothing (the headers' own compiles take what the files save: 1,895 against 1,883 CPU
# seconds), but a test file rebuilt alone does (gltf_loader_test.cpp 45 -> 37.5 s), which is
# the development loop. Only headers from outside glint go in: a file that forgets one of
# glint's own includes still fails to compile. GLINT_PCH=OFF builds without.
option(GLINT_PCH "Precompile the common third-party headers of the tests and the executable" ON)

# glint_pch(target header...): `target` precompiles the standard headers most of glint's files
# include, and the given ones.
#
# GCC only: ccache cannot reuse Clang's precompiled headers from another clone (a .pch records
# its headers' times and paths), so under Clang, the sanitizer build's compiler, they would turn
# every test file into a cache miss.
function(glint_pch target)
  if(GLINT_PCH AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_precompile_headers(${target} PRIVATE <algorithm> <cmath> <filesystem> <fstream>
                              <functional> <memory> <sstream> <string> <vector> ${ARGN})
  endif()
endfunction()
