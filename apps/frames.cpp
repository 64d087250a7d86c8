// glint — frame ranges and numbered file patterns.
#include "apps/frames.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <regex>

#include "geometry/error.h"

namespace glint::app {

namespace fs = std::filesystem;

// A bound on one run's frame list (a typo such as 0-999999999 would otherwise allocate
// gigabytes): a million frames is over ten hours of film at 24 fps.
constexpr int kMaxFrames = 1'000'000;

std::vector<int> FrameRange::frames() const {
  std::vector<int> out;
  for (long f = first; f <= last; f += step) out.push_back(int(f));
  return out;
}

FrameRange parseFrameRange(const std::string& text) {
  static const std::regex re(R"(^(\d{1,9})(?:-(\d{1,9}))?(?::(\d{1,9}))?$)");
  std::smatch m;
  if (!std::regex_match(text, m, re))
    throw InputError(fmt::format("--frames '{}': expected A-B[:STEP] or A", text));
  FrameRange r;
  r.first = std::stoi(m[1]);
  r.last = m[2].matched ? std::stoi(m[2]) : r.first;
  r.step = m[3].matched ? std::stoi(m[3]) : 1;
  if (r.last < r.first)
    throw InputError(fmt::format("--frames '{}': the last frame is before the first", text));
  if (r.step < 1) throw InputError(fmt::format("--frames '{}': the step must be >= 1", text));
  if ((r.last - r.first) / r.step >= kMaxFrames)
    throw InputError(
        fmt::format("--frames '{}': more than {} frames in one run", text, kMaxFrames));
  return r;
}

std::string FramePattern::path(int frame) const {
  if (!isPattern()) return text;
  return (folder / fmt::format("{}{:0{}d}{}", head, frame, width, tail)).string();
}

FramePattern parseFramePattern(const std::string& text) {
  FramePattern p;
  p.text = text;
  fs::path path(text);
  std::string name = path.filename().string();
  if (path.parent_path().string().find('#') != std::string::npos)
    throw InputError(fmt::format("'{}': '#' may only stand in the file name", text));
  size_t first = name.find('#');
  if (first == std::string::npos) return p;
  size_t last = name.find_first_not_of('#', first);
  if (last == std::string::npos) last = name.size();
  if (name.find('#', last) != std::string::npos)
    throw InputError(fmt::format("'{}': more than one run of '#'", text));
  p.folder = path.parent_path();
  p.head = name.substr(0, first);
  p.tail = name.substr(last);
  p.width = int(last - first);
  return p;
}

std::vector<int> findFrames(const FramePattern& p, const std::optional<FrameRange>& range) {
  fs::path folder = p.folder.empty() ? fs::path(".") : p.folder;
  std::vector<int> frames;
  std::error_code ec;
  fs::directory_iterator it(folder, ec);
  if (ec)
    throw InputError(fmt::format("no frames match '{}': cannot list folder '{}': {}", p.text,
                                 folder.string(), ec.message()));
  for (const fs::directory_entry& entry : it) {
    std::string name = entry.path().filename().string();
    if (name.size() < p.head.size() + p.tail.size() + size_t(p.width)) continue;
    if (!name.starts_with(p.head) || !name.ends_with(p.tail)) continue;
    std::string digits = name.substr(p.head.size(), name.size() - p.head.size() - p.tail.size());
    if (digits.size() > 9 ||
        !std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); }))
      continue;
    int frame = std::stoi(digits);
    if (fmt::format("{:0{}d}", frame, p.width) != digits) continue;
    if (range && !range->contains(frame)) continue;
    if (!entry.is_regular_file(ec)) continue;
    frames.push_back(frame);
  }
  std::sort(frames.begin(), frames.end());
  if (frames.empty())
    throw InputError(range ? fmt::format("no frames match '{}' in --frames {}-{}:{}", p.text,
                                         range->first, range->last, range->step)
                           : fmt::format("no frames match '{}'", p.text));
  return frames;
}

}  // namespace glint::app
