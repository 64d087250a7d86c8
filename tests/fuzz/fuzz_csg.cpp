// glint fuzzing — the reverse-polish CSG text format (scenes/csg_rpn.h), parsed in memory.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "scenes/csg_rpn.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  glint::fuzz::expectCleanResult([&] { glint::parseCsgRpn(text, "fuzz.csg"); });
  return 0;
}
