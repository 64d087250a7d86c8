// glint — progress bar.
#include "renderer/progress.h"

#include <unistd.h>

namespace glint {

std::string readableDuration(double seconds) {
  char text[48];
  if (seconds < 1e-3)
    std::snprintf(text, sizeof text, "%.0f µs", seconds * 1e6);
  else if (seconds < 1)
    std::snprintf(text, sizeof text, "%.0f ms", seconds * 1e3);
  else if (seconds < 90)
    std::snprintf(text, sizeof text, "%.1f s", seconds);
  else if (seconds < 90 * 60)
    std::snprintf(text, sizeof text, "%.0f min", seconds / 60);
  else if (seconds < 48 * 3600)
    std::snprintf(text, sizeof text, "%.1f h", seconds / 3600);
  else if (seconds < 730 * 86400)
    std::snprintf(text, sizeof text, "%.0f days", seconds / 86400);
  else
    std::snprintf(text, sizeof text, "%.1f years", seconds / (365.25 * 86400));
  return text;
}

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
  draw(total_.load(), true);
  finished_ = true;
}

void ProgressBar::setTotal(uint64_t total) {
  std::lock_guard<std::mutex> lock(drawMutex_);
  total_ = total ? total : 1;
}

void ProgressBar::setNote(std::string note) {
  std::lock_guard<std::mutex> lock(drawMutex_);
  note_ = std::move(note);
  if (enabled_ && !finished_) draw(done_.load(), false);
}

void ProgressBar::message(const std::string& line) {
  std::lock_guard<std::mutex> lock(drawMutex_);
  if (enabled_ && !finished_) {
    std::fprintf(out_, "\r\033[K%s\n", line.c_str());
    draw(done_.load(), false);
  } else {
    std::fprintf(out_, "%s\n", line.c_str());
  }
  std::fflush(out_);
}

void ProgressBar::draw(uint64_t done, bool final) {
  constexpr int kWidth = 30;
  const uint64_t total = total_.load();
  double fraction = double(std::min(done, total)) / double(total);
  double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  int filled = int(fraction * kWidth);
  std::string bar(size_t(filled), '=');
  if (filled < kWidth) bar += '>' + std::string(size_t(kWidth - filled - 1), ' ');
  std::string eta;
  if (final)
    eta = readableDuration(elapsed);
  else if (fraction > 0)
    eta = "ETA " + readableDuration(elapsed * (1 - fraction) / fraction);
  const std::string note = note_.empty() ? "" : "  " + note_;
  std::fprintf(out_, "\r%s [%s] %3d%% %s%s\033[K%s", label_.c_str(), bar.c_str(),
               int(fraction * 100), eta.c_str(), note.c_str(), final ? "\n" : "");
  std::fflush(out_);
}

}  // namespace glint
