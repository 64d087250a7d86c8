// glint — frame ranges and numbered file patterns for image sequences, shared by
// `glint render --frames` and `glint tonemap`.
//
// A pattern names one file per frame with one run of '#' in its file name standing for the
// frame number, zero-padded to the run's length: 'out/frame_####.exr' is out/frame_0042.exr
// for frame 42 (numbers wider than the run are written in full).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace glint::app {

// Frames first, first + step, ... up to and including last.
struct FrameRange {
  int first = 0, last = 0, step = 1;

  bool contains(int f) const { return f >= first && f <= last && (f - first) % step == 0; }
  std::vector<int> frames() const;
};

// "A-B[:STEP]" or a single "A", with 0 <= A <= B and STEP >= 1. Throws InputError naming
// what is wrong.
FrameRange parseFrameRange(const std::string& text);

struct FramePattern {
  std::string text;  // as given
  std::filesystem::path folder;
  std::string head, tail;  // the file name around the run
  int width = 0;           // 0: a single file, not a pattern

  bool isPattern() const { return width > 0; }
  // The file of `frame` (the text itself when it is not a pattern).
  std::string path(int frame) const;
};

// Splits `text` around its run of '#'. Throws InputError for '#' in a folder name or two runs
// in the file name.
FramePattern parseFramePattern(const std::string& text);

// The existing frames of `pattern`, sorted, restricted to `range` when given. A name matches
// only with the number written as the pattern writes it (padded to the run's width), so
// 'f_1.exr' and 'f_00001.exr' are not frame 1 of 'f_####.exr'. Throws InputError when none
// match or the folder cannot be listed.
std::vector<int> findFrames(const FramePattern& pattern, const std::optional<FrameRange>& range);

}  // namespace glint::app
