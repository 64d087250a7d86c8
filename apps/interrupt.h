// glint — Ctrl-C and SIGTERM during a render: the first asks the render to stop and write what
// it has; the second ends the process at once.
#pragma once

#include <atomic>

namespace glint::app {

// While alive, SIGINT and SIGTERM (what Slurm sends at a job's time limit) set flag() and print
// one line saying the passes done will be written; a second signal removes an image write's
// temporary file (image/io.h temporaryOutputInFlight) and exits with 128 + the signal, writing
// nothing over any output. The previous handlers come back on destruction. One at a time.
class InterruptGuard {
 public:
  // `firstMessage` is printed on the first signal (a string literal: the handler keeps it).
  explicit InterruptGuard(
      const char* firstMessage =
          "glint: interrupted: stopping and writing the passes done (again: quit without "
          "writing)");
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

  const std::atomic<bool>* flag() const;
  bool interrupted() const { return flag()->load(); }
  int signal() const;  // the first signal received, or 0
};

}  // namespace glint::app
