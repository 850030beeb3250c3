// Tests for console::frame_failure_lines / frame_list: failures of many frames are said once per
// cause with their count and frames; a cause naming its own frame groups as "frame N"; a lone
// frame keeps its own words.
#include "console/frame_failures.h"

#include <gtest/gtest.h>

namespace sweepd::console {
namespace {

TEST(FrameFailures, ManyFramesOfOneCauseAreOneLineWithTheirCount) {
  std::map<int, std::string> failures;
  for (int frame = 1441; frame <= 2000; ++frame)
    failures[frame] = "server error InvalidArgument: frame " + std::to_string(frame) +
                      " is past the clip's last frame 1440";
  const std::vector<std::string> lines = frame_failure_lines(failures);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0],
            "560 frames failed (1441-2000): server error InvalidArgument: frame N is past the "
            "clip's last frame 1440");
}

TEST(FrameFailures, EachCauseIsALineInTheOrderOfItsFirstFrame) {
  const std::map<int, std::string> failures = {{3, "a:1: connection refused"},
                                               {4, "a:1: connection refused"},
                                               {5, "server error InvalidPose: frame 5 is NaN"},
                                               {9, "a:1: connection refused"}};
  const std::vector<std::string> lines = frame_failure_lines(failures);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0], "3 frames failed (3-4, 9): a:1: connection refused");
  EXPECT_EQ(lines[1], "frame 5 failed: server error InvalidPose: frame 5 is NaN");  // its own words
}

TEST(FrameFailures, OnlyTheFramesOwnNumberIsWrittenN) {
  // "frame 12" in frame 1's message is another frame; "frame 10" is not "frame 1" followed by 0.
  const std::map<int, std::string> failures = {{1, "frame 1 after frame 12 and frame 10"},
                                               {2, "frame 2 after frame 12 and frame 10"}};
  const std::vector<std::string> lines = frame_failure_lines(failures);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0], "2 frames failed (1-2): frame N after frame 12 and frame 10");
}

TEST(FrameFailures, AListOfFramesIsRunsCutAfterTheMost) {
  EXPECT_EQ(frame_list({3, 7, 8, 9, 12}), "3, 7-9, 12");
  EXPECT_EQ(frame_list({}), "");
  EXPECT_EQ(frame_list({1, 3, 5, 7, 8}, 2), "1, 3, and 3 more frames");
}

}  // namespace
}  // namespace sweepd::console
