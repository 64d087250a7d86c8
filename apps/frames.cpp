// glint — frame ranges and numbered file patterns.
#include "apps/frames.h"

#include <charconv>
#include <stdexcept>

namespace glint::app {

namespace {

int parseFrameNumber(const std::string& text, const std::string& what, const std::string& whole) {
  int value = 0;
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (text.empty() || ec != std::errc() || ptr != end)
    throw std::invalid_argument("--frames '" + whole + "': " + what + " '" + text +
                                "' is not a whole number (expected A-B[:STEP])");
  return value;
}

}  // namespace

std::vector<int> parseFrameRange(const std::string& text) {
  std::string range = text, stepText;
  if (size_t colon = text.find(':'); colon != std::string::npos) {
    range = text.substr(0, colon);
    stepText = text.substr(colon + 1);
  }
  int first = 0, last = 0, step = 1;
  if (size_t dash = range.find('-'); dash != std::string::npos) {
    first = parseFrameNumber(range.substr(0, dash), "first frame", text);
    last = parseFrameNumber(range.substr(dash + 1), "last frame", text);
  } else {
    first = last = parseFrameNumber(range, "frame", text);
  }
  if (!stepText.empty() || text.find(':') != std::string::npos)
    step = parseFrameNumber(stepText, "step", text);
  if (first < 0) throw std::invalid_argument("--frames '" + text + "': frames start at 0");
  if (last < first)
    throw std::invalid_argument("--frames '" + text + "': the last frame is before the first");
  if (step < 1) throw std::invalid_argument("--frames '" + text + "': the step must be >= 1");
  std::vector<int> frames;
  for (long f = first; f <= last; f += step) frames.push_back(int(f));
  return frames;
}

bool hasFramePattern(const std::string& pattern) { return pattern.find('#') != std::string::npos; }

std::string framePath(const std::string& pattern, int frame) {
  size_t end = pattern.rfind('#');
  if (end == std::string::npos) return pattern;
  size_t begin = end;
  while (begin > 0 && pattern[begin - 1] == '#') --begin;
  const size_t width = end - begin + 1;
  std::string number = std::to_string(frame);
  if (number.size() < width) number.insert(0, width - number.size(), '0');
  return pattern.substr(0, begin) + number + pattern.substr(end + 1);
}

}  // namespace glint::app
