// Failures of many frames said once per cause (issue 52: one cause was printed once per frame,
// thousands of times): "560 frames failed (1441-2000): server error InvalidArgument: frame N is
// past the clip's last frame 1440".
//
//   frame_failure_lines  {frame: why} -> a line per cause, in the order of each cause's first
//                        frame; a why that names its own frame ("frame 1441 is past ...") is the
//                        same cause as the others' and says "frame N" in the line
//   frame_list           ascending frames -> "3, 7-9, 12", at most `most` runs, then
//                        "and K more frames"
#pragma once

#include <map>
#include <string>
#include <vector>

namespace sweepd::console {

std::vector<std::string> frame_failure_lines(const std::map<int, std::string>& failures);

std::string frame_list(const std::vector<int>& ascending_frames, int most = 12);

}  // namespace sweepd::console
