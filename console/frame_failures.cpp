#include "console/frame_failures.h"

#include <cctype>
#include <cstddef>

namespace sweepd::console {
namespace {

// `why` with every "frame F" of the failed frame's own number F written "frame N".
std::string cause_of(int frame, const std::string& why) {
  const std::string own = "frame " + std::to_string(frame);
  std::string cause;
  std::size_t from = 0;
  for (std::size_t at = why.find(own); at != std::string::npos; at = why.find(own, at + 1)) {
    const std::size_t end = at + own.size();
    const bool word_before = at > 0 && std::isalnum(static_cast<unsigned char>(why[at - 1]));
    const bool digit_after = end < why.size() && std::isdigit(static_cast<unsigned char>(why[end]));
    if (word_before || digit_after) continue;  // "keyframe 12", "frame 123" for frame 12
    cause += why.substr(from, at - from) + "frame N";
    from = end;
  }
  return cause + why.substr(from);
}

}  // namespace

std::vector<std::string> frame_failure_lines(const std::map<int, std::string>& failures) {
  std::vector<std::string> causes;  // in the order of their first frame
  std::map<std::string, std::vector<int>> frames_of;
  for (const auto& [frame, why] : failures) {  // ascending frames
    const std::string cause = cause_of(frame, why);
    std::vector<int>& frames = frames_of[cause];
    if (frames.empty()) causes.push_back(cause);
    frames.push_back(frame);
  }
  std::vector<std::string> lines;
  for (const std::string& cause : causes) {
    const std::vector<int>& frames = frames_of[cause];
    if (frames.size() == 1) {  // its own words, its own number
      lines.push_back("frame " + std::to_string(frames[0]) + " failed: " +
                      failures.at(frames[0]));
    } else {
      lines.push_back(std::to_string(frames.size()) + " frames failed (" + frame_list(frames) +
                      "): " + cause);
    }
  }
  return lines;
}

std::string frame_list(const std::vector<int>& ascending_frames, int most) {
  std::string list;
  int runs = 0;
  for (std::size_t i = 0; i < ascending_frames.size();) {
    std::size_t end = i + 1;  // the run is [i, end)
    while (end < ascending_frames.size() && ascending_frames[end] == ascending_frames[end - 1] + 1)
      ++end;
    if (runs == most) {
      list += ", and " + std::to_string(ascending_frames.size() - i) + " more frames";
      break;
    }
    list += (runs > 0 ? ", " : "") + std::to_string(ascending_frames[i]);
    if (end - i > 1) list += "-" + std::to_string(ascending_frames[end - 1]);
    ++runs;
    i = end;
  }
  return list;
}

}  // namespace sweepd::console
