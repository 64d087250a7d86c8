// glint — a terminal progress bar with ETA, safe to advance from worker threads.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

namespace glint {

class ProgressBar {
 public:
  // Draws on `out` only when `enabled` (callers pass: stderr is a TTY and not --quiet).
  ProgressBar(std::string label, uint64_t total, bool enabled, std::FILE* out = stderr);
  ~ProgressBar();
  void advance(uint64_t n = 1);
  void finish();  // draws 100% and ends the line
  // A new end (a budgeted render learns it as it goes), and a note drawn after the ETA
  // ("64 spp, error 1.2%"). Not for worker threads.
  void setTotal(uint64_t total);
  void setNote(std::string note);
  // Prints `line` on a line of its own above the bar (on `out` even when the bar is off).
  void message(const std::string& line);

 private:
  void draw(uint64_t done, bool final);
  std::string label_;
  std::string note_;
  std::atomic<uint64_t> total_;
  bool enabled_;
  std::FILE* out_;
  std::atomic<uint64_t> done_{0};
  std::mutex drawMutex_;
  std::chrono::steady_clock::time_point start_, lastDraw_;
  bool finished_ = false;
};

// "850 µs", "3.4 s", "12 min", "5.2 h", "171 days", "3.1 years": a duration read at a glance.
std::string readableDuration(double seconds);

// True when the stream is attached to a terminal.
bool isTerminal(std::FILE* stream);

}  // namespace glint
