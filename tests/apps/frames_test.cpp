// Tests for frame ranges and numbered file patterns (apps/frames.h) and for sequences
// rendered with `glint render --frames`.
#include "apps/frames.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "test_support.h"

namespace glint::app {
namespace {

TEST(Frames, RangesWithAndWithoutStep) {
  EXPECT_EQ(parseFrameRange("3"), (std::vector<int>{3}));
  EXPECT_EQ(parseFrameRange("0-4"), (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_EQ(parseFrameRange("1-10:4"), (std::vector<int>{1, 5, 9}));
  EXPECT_EQ(parseFrameRange("7-7:3"), (std::vector<int>{7}));
}

TEST(Frames, BadRangesAreRejectedWithTheReason) {
  for (const char* bad : {"", "a-b", "5-2", "1-4:0", "-3", "1-", "1-4:", "1.5-3", "1-4:x"}) {
    try {
      parseFrameRange(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("--frames"), std::string::npos) << e.what();
    }
  }
}

TEST(Frames, PatternsArePaddedToTheRunOfHashes) {
  EXPECT_EQ(framePath("out/frame_####.exr", 42), "out/frame_0042.exr");
  EXPECT_EQ(framePath("f#.png", 7), "f7.png");
  EXPECT_EQ(framePath("f##.png", 12345), "f12345.png");     // wider numbers are written in full
  EXPECT_EQ(framePath("a#/b_###.exr", 3), "a#/b_003.exr");  // the last run is the frame
  EXPECT_EQ(framePath("still.exr", 3), "still.exr");
  EXPECT_TRUE(hasFramePattern("x_#.exr"));
  EXPECT_FALSE(hasFramePattern("x.exr"));
}

}  // namespace
}  // namespace glint::app
