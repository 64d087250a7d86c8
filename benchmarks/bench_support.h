// glint benchmarks — shared start-up: the `--out FILE` option every benchmark program takes
// next to Google Benchmark's own flags.
#pragma once

#include <benchmark/benchmark.h>
#include <time.h>

#include <cstring>
#include <map>
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

// CPU seconds used by the whole process so far, every thread. Rates per CPU second hold on a
// machine busy with other work, where wall-clock rates fall with the share of cores left.
inline double processCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// Prints like the console reporter and keeps the counters of every measured (iteration) run by
// benchmark function, for a program's own summary: value("BM_X", "Mrays/s"), 0 when absent
// (e.g. filtered out).
class CounterReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& run : runs)
      if (run.run_type == Run::RT_Iteration)
        for (const auto& [name, counter] : run.counters)
          counters_[run.run_name.function_name][name] = double(counter);
    ConsoleReporter::ReportRuns(runs);
  }
  double value(const std::string& function, const std::string& counter) const {
    auto f = counters_.find(function);
    if (f == counters_.end()) return 0;
    auto c = f->second.find(counter);
    return c == f->second.end() ? 0 : c->second;
  }

 private:
  std::map<std::string, std::map<std::string, double>> counters_;
};

}  // namespace glint::bench
