# Warnings on for glint's own code (dependencies are included as SYSTEM headers).
function(glint_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow=local
                         -Wno-missing-field-initializers)
endfunction()
