// glint benchmarks — shared start-up: the `--out FILE` option every benchmark program takes
// next to Google Benchmark's own flags.
#pragma once

#include <benchmark/benchmark.h>

#include <cstring>
#include <string>
#include <vector>

namespace glint::bench {

// Removes `--out FILE` from the arguments, initialises Google Benchmark with the rest (which
// rejects nothing it knows) and returns FILE ("" when absent).
inline std::string initialize(int argc, char** argv) {
  std::string out;
  static std::vector<char*> args;  // Google Benchmark keeps pointers into argv
  args.clear();
  for (int i = 0; i < argc; ++i) {
    if (std::strcmp(argv[i], "--out") == 0 && i + 1 < argc)
      out = argv[++i];
    else
      args.push_back(argv[i]);
  }
  int n = int(args.size());
  benchmark::Initialize(&n, args.data());
  return out;
}

}  // namespace glint::bench
