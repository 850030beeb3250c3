#include "console/frame_range.h"

#include <charconv>

namespace sweepd::console {

std::optional<int> parse_frame_number(std::string_view text) {
  int value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() || value < 0)
    return std::nullopt;
  return value;
}

std::optional<FrameRange> parse_frame_range(std::string_view text) {
  const std::size_t dash = text.find('-');
  const std::optional<int> first = parse_frame_number(text.substr(0, dash));
  const std::optional<int> last =
      dash == std::string_view::npos ? first : parse_frame_number(text.substr(dash + 1));
  if (!first || !last || *last < *first) return std::nullopt;
  return FrameRange{*first, *last};
}

std::string frame_range_problem(const FrameRange& range, int frame_count) {
  if (range.last < frame_count) return "";
  return "the clip has frames 0-" + std::to_string(frame_count - 1) + "; frame " +
         std::to_string(range.last) + " does not exist";
}

}  // namespace sweepd::console
