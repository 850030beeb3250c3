// A clip at a lower frame rate: every `step`-th frame of it, each lasting `step` times as long
// (what a 30 Hz export of a 120 Hz capture holds). For tests that check nothing depends on the
// clip's rate.
#pragma once

#include <stdexcept>

#include "motion/clip.h"

namespace sweepd::motion::test_clips {

inline Clip every_nth_frame(Clip clip, int step) {
  if (step < 1 || clip.keyframed())
    throw std::invalid_argument("every_nth_frame needs a step of 1 or more and a framed clip");
  const std::size_t width = static_cast<std::size_t>(clip.channel_count);
  int kept = 0;
  for (int f = 0; f < clip.frame_count; f += step, ++kept)
    std::copy_n(clip.values.begin() + f * width, width, clip.values.begin() + kept * width);
  clip.values.resize(kept * width);
  clip.frame_count = clip.header_frame_count = kept;
  clip.frame_time *= static_cast<float>(step);
  return clip;
}

}  // namespace sweepd::motion::test_clips
