// FrameShard: the slice of a frame range one render process owns, so that N processes (a
// Kubernetes Indexed Job, a shell loop over hosts) render a range between them with no frame
// twice and none left out.
//
//   parse_frame_shard(text)        "I/N" (0 <= I < N) -> shard; nothing for anything else
//   frame_shard_from_environment(get)
//                                  JOB_COMPLETION_INDEX and JOB_COMPLETIONS (set by an Indexed
//                                  Job; Kubernetes sets the index, the Job's spec the count)
//                                  -> shard; nothing when neither is set; std::invalid_argument
//                                  naming the variable when one is missing or malformed
//   shard_frames(range, shard)     the shard's frames: contiguous, sizes differing by at most
//                                  one, in index order; nothing when the shard gets no frame
//                                  (more shards than frames)
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "console/frame_range.h"

namespace sweepd::client {

struct FrameShard {
  int index = 0, count = 1;  // 0 <= index < count
};

std::optional<FrameShard> parse_frame_shard(std::string_view text);

// `get` reads one environment variable (nothing when unset); std::getenv in the tools.
std::optional<FrameShard> frame_shard_from_environment(
    const std::function<std::optional<std::string>(const char*)>& get);

std::optional<console::FrameRange> shard_frames(const console::FrameRange& range,
                                                const FrameShard& shard);

}  // namespace sweepd::client
