#include "motion/clip_sampling.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace sweepd::motion {
namespace {

std::string seconds_text(double seconds) {
  char text[48];
  std::snprintf(text, sizeof text, "%g s", seconds);
  return text;
}

// The clip time (its own rate) of a request's seconds, checked and wrapped.
double clip_seconds(const ClipPoses& clip, const ClipSample& sample) {
  const double seconds = *sample.seconds;
  if (!std::isfinite(seconds))
    throw std::invalid_argument("the time to sample is " + seconds_text(seconds) +
                                ", not a finite number");
  const float rate = sample.frames_per_second;
  if (!std::isfinite(rate) || rate < 0.0f)
    throw std::invalid_argument("frames per second " + std::to_string(rate) +
                                ": expected a finite rate > 0, or 0 for the clip's own");
  const double own = rate > 0.0f ? seconds * rate * clip.motion().frame_time : seconds;
  const double duration = clip.duration();
  if (sample.loop) {
    if (duration <= 0.0) return 0.0;
    const double wrapped = std::fmod(own, duration);
    return wrapped < 0.0 ? wrapped + duration : wrapped;
  }
  if (own < 0.0 || own > duration)
    throw std::invalid_argument("time " + seconds_text(seconds) + " is outside the clip's 0 to " +
                                seconds_text(duration) + (rate > 0.0f ? " at its own rate" : "") +
                                " (ask with loop to wrap)");
  return own;
}

}  // namespace

deform::Pose sample_clip(const ClipPoses& clip, const ClipSample& sample) {
  if (sample.frame.has_value() == sample.seconds.has_value())
    throw std::invalid_argument("a clip sample needs exactly one of a frame and a time");
  if (sample.seconds) return clip.pose_at_time(clip_seconds(clip, sample));
  const std::uint32_t count = static_cast<std::uint32_t>(clip.frame_count());
  std::uint32_t frame = *sample.frame;
  if (sample.loop) {
    frame %= count;
  } else if (frame >= count) {
    throw std::invalid_argument("frame " + std::to_string(frame) +
                                " is past the clip's last frame " + std::to_string(count - 1) +
                                " (ask with loop to wrap)");
  }
  return clip.pose_at_frame(static_cast<int>(frame));
}

}  // namespace sweepd::motion
