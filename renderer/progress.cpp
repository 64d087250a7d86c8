// glint — progress bar.
#include "renderer/progress.h"

#include <unistd.h>

namespace glint {

bool isTerminal(std::FILE* stream) { return ::isatty(::fileno(stream)) == 1; }

ProgressBar::ProgressBar(std::string label, uint64_t total, bool enabled, std::FILE* out)
    : label_(std::move(label)), total_(total ? total : 1), enabled_(enabled), out_(out) {
  start_ = lastDraw_ = std::chrono::steady_clock::now();
  if (enabled_) draw(0, false);
}

ProgressBar::~ProgressBar() {
  if (enabled_ && !finished_) {
    std::fputc('\n', out_);
    std::fflush(out_);
  }
}

void ProgressBar::advance(uint64_t n) {
  uint64_t done = done_.fetch_add(n) + n;
  if (!enabled_) return;
  auto now = std::chrono::steady_clock::now();
  std::unique_lock<std::mutex> lock(drawMutex_, std::try_to_lock);
  if (!lock.owns_lock() || now - lastDraw_ < std::chrono::milliseconds(100)) return;
  lastDraw_ = now;
  draw(done, false);
}

void ProgressBar::finish() {
  if (!enabled_ || finished_) return;
  std::lock_guard<std::mutex> lock(drawMutex_);
  draw(total_, true);
  finished_ = true;
}

void ProgressBar::draw(uint64_t done, bool final) {
  constexpr int kWidth = 30;
  double fraction = double(std::min(done, total_)) / double(total_);
  double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  int filled = int(fraction * kWidth);
  std::string bar(size_t(filled), '=');
  if (filled < kWidth) bar += '>' + std::string(size_t(kWidth - filled - 1), ' ');
  char eta[32] = "";
  if (final)
    std::snprintf(eta, sizeof eta, "%.1fs", elapsed);
  else if (fraction > 0)
    std::snprintf(eta, sizeof eta, "ETA %.0fs", elapsed * (1 - fraction) / fraction);
  std::fprintf(out_, "\r%s [%s] %3d%% %s\033[K%s", label_.c_str(), bar.c_str(),
               int(fraction * 100), eta, final ? "\n" : "");
  std::fflush(out_);
}

}  // namespace glint
