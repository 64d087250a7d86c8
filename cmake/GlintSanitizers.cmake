# Sanitizer and fuzzing builds (issue 8); scripts/sanitize.sh drives both from one build folder.
#
# GLINT_SANITIZE: AddressSanitizer (with LeakSanitizer) and UndefinedBehaviorSanitizer on all of
#   glint's own code, tests and tools. Any report aborts (-fno-sanitize-recover=all), so a test
#   that triggers one fails. Embree, TBB, OpenImageIO and the other Debian libraries are not
#   instrumented.
# GLINT_FUZZ: libFuzzer targets for the scene loaders (tests/fuzz). Needs Clang and
#   GLINT_SANITIZE. Only the loaders' room (glint_scenes) gets coverage instrumentation
#   (-fsanitize=fuzzer-no-link), which keeps the renderer's tests at sanitizer speed; the fuzz
#   executables link the libFuzzer driver with -fsanitize=fuzzer.
option(GLINT_SANITIZE "Build with AddressSanitizer and UndefinedBehaviorSanitizer" OFF)
option(GLINT_FUZZ "Build the libFuzzer targets in tests/fuzz (Clang, with GLINT_SANITIZE)" OFF)

if(GLINT_SANITIZE)
  set(glint_sanitize_flags -fsanitize=address,undefined -fno-sanitize-recover=all
                           -fno-omit-frame-pointer)
  # Third-party headers whose inline code UBSan would otherwise check (the file says why).
  add_compile_options(
    "-fsanitize-ignorelist=${CMAKE_SOURCE_DIR}/tests/sanitizers/ubsan_ignore.txt")
  # Must come before any target is defined: every object and every link is instrumented.
  add_compile_options(${glint_sanitize_flags})
  add_link_options(${glint_sanitize_flags})
endif()

if(GLINT_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "GLINT_FUZZ needs Clang (libFuzzer); configure with "
                        "-DCMAKE_CXX_COMPILER=clang++ (scripts/sanitize.sh does)")
  endif()
  if(NOT GLINT_SANITIZE)
    message(FATAL_ERROR "GLINT_FUZZ needs GLINT_SANITIZE=ON: a fuzzer without AddressSanitizer "
                        "misses most memory errors")
  endif()
endif()

# Coverage instrumentation for code the fuzzers should explore; a no-op unless GLINT_FUZZ.
function(glint_fuzz_instrument target)
  if(GLINT_FUZZ)
    target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link)
  endif()
endfunction()
