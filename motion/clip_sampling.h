// Clip sampling: which pose of a clip played on a model a request names — a frame index, or a
// time in seconds (optionally at another frame rate), optionally looping — checked, then taken
// from the player (motion/clip_poses.h: motion::Retargeter or motion::OwnSkeletonClip; so a
// frame index gives exactly its pose_at_frame, as `sweepctl pose --bvh --frame` does).
//
// Input:  ClipSample: exactly one of frame / seconds; loop; frames_per_second (0: the clip's).
//   frame    without loop must be < frame_count; with loop, taken modulo frame_count.
//   seconds  must be finite; at a rate f other than the clip's, t seconds are clip time
//            t * f * frame_time. Without loop it must lie in [0, duration]; with loop it is
//            wrapped into it (a one-frame clip: 0).
// Output: the model's deform::Pose. Problems throw std::invalid_argument naming the value and
//         the clip's range (e.g. "frame 5000 is past the clip's last frame 2750").
#pragma once

#include <cstdint>
#include <optional>

#include "deform/model/pose.h"
#include "motion/clip_poses.h"

namespace sweepd::motion {

struct ClipSample {
  std::optional<std::uint32_t> frame = std::nullopt;
  std::optional<double> seconds = std::nullopt;
  bool loop = false;
  float frames_per_second = 0.0f;  // with seconds; 0: the clip's own rate
};

deform::Pose sample_clip(const ClipPoses& clip, const ClipSample& sample);

}  // namespace sweepd::motion
