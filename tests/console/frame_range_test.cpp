// Tests for console::parse_frame_range / frame_range_problem: "A-B" and "A" parse, anything
// else (trailing letters, reversed, negative, empty) does not; a range past the clip's end is
// named.
#include "console/frame_range.h"

#include <gtest/gtest.h>

namespace sweepd::console {
namespace {

TEST(FrameRange, ParsesARangeOrOneFrame) {
  const std::optional<FrameRange> range = parse_frame_range("3-239");
  ASSERT_TRUE(range.has_value());
  EXPECT_EQ(range->first, 3);
  EXPECT_EQ(range->last, 239);
  EXPECT_EQ(range->count(), 237);
  const std::optional<FrameRange> one = parse_frame_range("12");
  ASSERT_TRUE(one.has_value());
  EXPECT_EQ(one->first, 12);
  EXPECT_EQ(one->last, 12);
}

TEST(FrameRange, RefusesAnythingElse) {
  for (const char* text : {"12x", "1-2x", "5-3", "-1", "1-", "", "a-b", " 1-2"})
    EXPECT_FALSE(parse_frame_range(text).has_value()) << text;
}

TEST(FrameRange, NamesFramesPastTheClipsEnd) {
  EXPECT_EQ(frame_range_problem({0, 9}, 10), "");
  EXPECT_EQ(frame_range_problem({5, 10}, 10), "the clip has frames 0-9; frame 10 does not exist");
}

}  // namespace
}  // namespace sweepd::console
