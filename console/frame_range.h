// FrameRange: which frames of a clip a program plays, written "A-B" (inclusive, 0-based) or
// "A" (one frame) on command lines (sweepctl --frames, render_frames --frames).
//
//   parse_frame_range   text -> range; nothing for anything else ("12x", "5-3", "-1")
//   parse_frame_number  text -> a whole non-negative decimal number; nothing for anything else
//                       ("+1", " 1", "1x")
//   frame_range_problem range, the clip's frame count -> "" or why the range does not fit
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace sweepd::console {

struct FrameRange {
  int first = 0, last = 0;  // inclusive, 0 <= first <= last
  int count() const { return last - first + 1; }
};

std::optional<FrameRange> parse_frame_range(std::string_view text);
std::optional<int> parse_frame_number(std::string_view text);

// "the clip has frames 0-N; frame L does not exist" when last >= frame_count, else "".
std::string frame_range_problem(const FrameRange& range, int frame_count);

}  // namespace sweepd::console
