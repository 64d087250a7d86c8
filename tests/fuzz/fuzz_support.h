// glint fuzzing — the contract every loader fuzz target checks (see tests/fuzz/README.md).
#pragma once

#include <cstdio>
#include <cstdlib>

#include "scenes/errors.h"

namespace glint::fuzz {

// Runs `load` on one fuzz input. A SceneError that names a file is the loaders' documented
// answer to bad input. Everything else is a finding: a SceneError without a location aborts
// here, any other exception escapes (std::terminate), and ASan/UBSan reports, hangs and huge
// allocations are caught by the sanitizers and libFuzzer's -timeout and -rss_limit_mb.
template <class Load>
void expectCleanResult(Load&& load) {
  try {
    load();
  } catch (const SceneError& e) {
    if (e.where().file.empty()) {
      std::fprintf(stderr, "SceneError without a file: %s\n", e.what());
      std::abort();
    }
  }
}

}  // namespace glint::fuzz
