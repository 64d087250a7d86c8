# Precompiled headers for the targets with many source files that include the same heavy
# third-party headers: the test binaries (GoogleTest and nlohmann/json alone take the compiler
# about 2.5 s per file to parse, and the test files are most of a build) and the glint
# executable (CLI11, fmt, json). Only headers from outside glint go in: a file that forgets
# one of glint's own includes still fails to compile. GLINT_PCH=OFF builds without.
option(GLINT_PCH "Precompile the common third-party headers of the tests and the executable" ON)

# glint_pch(target header...): `target` precompiles the standard headers most of glint's files
# include, and the given ones.
function(glint_pch target)
  if(GLINT_PCH)
    target_precompile_headers(${target} PRIVATE <algorithm> <cmath> <filesystem> <fstream>
                              <functional> <memory> <sstream> <string> <vector> ${ARGN})
  endif()
endfunction()
