#include "client/frame_shard.h"

#include <stdexcept>

namespace sweepd::client {

std::optional<FrameShard> parse_frame_shard(std::string_view text) {
  const std::size_t slash = text.find('/');
  if (slash == std::string_view::npos) return std::nullopt;
  const std::optional<int> index = console::parse_frame_number(text.substr(0, slash));
  const std::optional<int> count = console::parse_frame_number(text.substr(slash + 1));
  if (!index || !count || *count < 1 || *index >= *count) return std::nullopt;
  return FrameShard{*index, *count};
}

std::optional<FrameShard> frame_shard_from_environment(
    const std::function<std::optional<std::string>(const char*)>& get) {
  const std::optional<std::string> index = get("JOB_COMPLETION_INDEX");
  const std::optional<std::string> count = get("JOB_COMPLETIONS");
  if (!index && !count) return std::nullopt;
  if (!index) throw std::invalid_argument("JOB_COMPLETIONS is set but JOB_COMPLETION_INDEX is not");
  if (!count) {
    throw std::invalid_argument(
        "JOB_COMPLETION_INDEX is set but JOB_COMPLETIONS is not (set it in the Job's env to "
        "spec.completions)");
  }
  const std::optional<FrameShard> shard = parse_frame_shard(*index + "/" + *count);
  if (!shard) {
    throw std::invalid_argument("JOB_COMPLETION_INDEX=" + *index + " JOB_COMPLETIONS=" + *count +
                                ": expected 0 <= index < completions");
  }
  return shard;
}

std::optional<console::FrameRange> shard_frames(const console::FrameRange& range,
                                                const FrameShard& shard) {
  // Shard i owns [first + floor(i * n / N), first + floor((i + 1) * n / N)).
  const long long n = range.count();
  const int begin = range.first + static_cast<int>(shard.index * n / shard.count);
  const int end = range.first + static_cast<int>((shard.index + 1LL) * n / shard.count);
  if (begin == end) return std::nullopt;
  return console::FrameRange{begin, end - 1};
}

}  // namespace sweepd::client
