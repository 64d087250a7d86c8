// glint — the signal handlers of InterruptGuard: only async-signal-safe calls (write, unlink,
// _exit) and lock-free atomics.
#include "apps/interrupt.h"

#include <unistd.h>

#include <csignal>
#include <cstring>

#include "image/io.h"

namespace glint::app {

namespace {

std::atomic<bool> interruptedFlag{false};
std::atomic<int> firstSignal{0};
std::atomic<const char*> firstLine{nullptr};
struct sigaction previousInt, previousTerm;

void say(const char* text) {
  const ssize_t ignored = ::write(STDERR_FILENO, text, std::strlen(text));
  (void)ignored;
}

void onSignal(int sig) {
  int expected = 0;
  if (firstSignal.compare_exchange_strong(expected, sig)) {
    interruptedFlag.store(true);
    say("\n");
    if (const char* line = firstLine.load()) say(line);
    say("\n");
    return;
  }
  if (const char* temp = temporaryOutputInFlight()) ::unlink(temp);
  say("\nglint: interrupted again: quit without writing\n");
  ::_exit(128 + sig);
}

}  // namespace

InterruptGuard::InterruptGuard(const char* firstMessage) {
  firstLine.store(firstMessage);
  interruptedFlag.store(false);
  firstSignal.store(0);
  struct sigaction action {};
  action.sa_handler = onSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, &previousInt);
  sigaction(SIGTERM, &action, &previousTerm);
}

InterruptGuard::~InterruptGuard() {
  sigaction(SIGINT, &previousInt, nullptr);
  sigaction(SIGTERM, &previousTerm, nullptr);
}

const std::atomic<bool>* InterruptGuard::flag() const { return &interruptedFlag; }
int InterruptGuard::signal() const { return firstSignal.load(); }

}  // namespace glint::app
