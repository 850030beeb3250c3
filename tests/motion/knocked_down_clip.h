// A knock-down clip made from a CMU clip (issue 48: "the body lowered until it lies on the
// floor"): the clip's first 600 frames, in which from frame 100 to 300 the root sinks from its
// own height to 15 % of it while tipping over backwards by 90° about its own X axis (a smooth
// step), then stays down. The clip's hips and back end on its floor, where any body whose
// proportions are not the clip's pushes some part through the model's. Tipped by +90° instead
// (pitch_degrees), it falls forwards, onto its hands.
#pragma once

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "motion/clip.h"

namespace sweepd::motion::test_clips {

inline Clip knocked_down(Clip clip, float pitch_degrees = -90.0f) {
  const ClipJoint& root = clip.joints.at(0);
  int height = -1, pitch = -1;
  for (std::size_t c = 0; c < root.channels.size(); ++c) {
    if (root.channels[c] == Channel::kYposition) height = root.channel_offset + static_cast<int>(c);
    if (root.channels[c] == Channel::kXrotation) pitch = root.channel_offset + static_cast<int>(c);
  }
  if (height < 0 || pitch < 0 || clip.frame_count < 600)
    throw std::invalid_argument(
        "knocked_down needs a root with Yposition and Xrotation, 600 frames");
  clip.frame_count = clip.header_frame_count = 600;
  clip.values.resize(static_cast<std::size_t>(clip.frame_count) * clip.channel_count);
  for (int f = 0; f < clip.frame_count; ++f) {
    const float x = std::clamp((f - 100) / 200.0f, 0.0f, 1.0f);
    const float down = x * x * (3.0f - 2.0f * x);
    float* row = &clip.values[static_cast<std::size_t>(f) * clip.channel_count];
    row[height] *= 1.0f - 0.85f * down;
    row[pitch] += pitch_degrees * down;
  }
  return clip;
}

}  // namespace sweepd::motion::test_clips
