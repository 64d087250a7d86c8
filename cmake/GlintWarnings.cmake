# Warnings on for glint's own code (dependencies are included as SYSTEM headers).
function(glint_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wno-missing-field-initializers
                         # GCC only: locals shadowing locals (Clang's -Wshadow also flags members).
                         $<$<CXX_COMPILER_ID:GNU>:-Wshadow=local>)
endfunction()
