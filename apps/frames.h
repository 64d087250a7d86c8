// glint — frame ranges and numbered file patterns for image sequences.
//
// A pattern names one file per frame with a run of '#' standing for the frame number,
// zero-padded to the run's length: 'out/frame_####.exr' is out/frame_0042.exr for frame 42
// (numbers wider than the run are written in full). `glint render --frames` and
// `glint tonemap` share these rules.
#pragma once

#include <string>
#include <vector>

namespace glint::app {

// "A-B[:STEP]" or a single "A": frames A, A+STEP, ... up to and including B. A and B may be
// 0 or positive, A <= B, STEP >= 1. Throws std::invalid_argument naming what is wrong.
std::vector<int> parseFrameRange(const std::string& text);

// True when `pattern` has a run of '#'.
bool hasFramePattern(const std::string& pattern);

// `pattern` with its last run of '#' replaced by `frame`, zero-padded to the run's length.
std::string framePath(const std::string& pattern, int frame);

}  // namespace glint::app
