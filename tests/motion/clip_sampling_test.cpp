// sample_clip: a frame index is exactly Retargeter::pose_at_frame (looping wraps it), a time is
// pose_at_time of the clip time (at another rate scaled, looping wrapped), and what cannot be
// sampled — past the end, NaN, both or neither of frame and time — is refused naming it.
#include "motion/clip_sampling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "io/bvh/bvh_load.h"
#include "motion/retarget.h"

namespace sweepd::motion::clip_sampling_test {
namespace {

// A root and a child; 3 frames at 10 frames/s (duration 0.2 s), the child turning 10° a frame.
Retargeter three_frame_clip() {
  std::string text =
      "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 1 0\n"
      "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
      "  JOINT Spine\n  {\n    OFFSET 0 1 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n"
      "    End Site\n    {\n      OFFSET 0 1 0\n    }\n  }\n}\nMOTION\nFrames: 3\n"
      "Frame Time: 0.1\n";
  for (int f = 0; f < 3; ++f) text += "0 1 0 0 0 0 " + std::to_string(10 * f) + " 0 0\n";
  deform::Skeleton skeleton;
  skeleton.joints = {{.name = "Hips", .rest_translation = {0, 1, 0}},
                     {.name = "Spine", .parent = 0, .rest_translation = {0, 1, 0}}};
  return Retargeter(io::parse_bvh(text, "three.bvh"), skeleton);
}

bool same_bits(const deform::Pose& a, const deform::Pose& b) {
  return a.local_rotations.size() == b.local_rotations.size() &&
         std::memcmp(a.local_rotations.data(), b.local_rotations.data(),
                     a.local_rotations.size() * sizeof(glm::quat)) == 0 &&
         a.root_translation == b.root_translation;
}

std::string refusal(const Retargeter& clip, const ClipSample& sample) {
  try {
    sample_clip(clip, sample);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "(sampled)";
}

TEST(ClipSampling, FramesAreTheRetargetersFramesAndLoopingWrapsThem) {
  const Retargeter clip = three_frame_clip();
  EXPECT_TRUE(same_bits(sample_clip(clip, {.frame = 2}), clip.pose_at_frame(2)));
  EXPECT_TRUE(same_bits(sample_clip(clip, {.frame = 7, .loop = true}), clip.pose_at_frame(1)));
  EXPECT_EQ(refusal(clip, {.frame = 3}),
            "frame 3 is past the clip's last frame 2 (ask with loop to wrap)");
}

TEST(ClipSampling, TimesAreClipTimeAtTheAskedRateAndLoopingWrapsThem) {
  const Retargeter clip = three_frame_clip();
  EXPECT_TRUE(same_bits(sample_clip(clip, {.seconds = 0.15}), clip.pose_at_time(0.15)));
  // At 20 frames/s the clip plays twice as fast: 0.05 s is clip time 0.1 s.
  EXPECT_TRUE(same_bits(sample_clip(clip, {.seconds = 0.05, .frames_per_second = 20.0f}),
                        clip.pose_at_time(0.05 * 20.0f * 0.1f)));
  EXPECT_TRUE(same_bits(sample_clip(clip, {.seconds = -0.05, .loop = true}),
                        clip.pose_at_time(std::fmod(-0.05, clip.duration()) + clip.duration())));
  EXPECT_NE(refusal(clip, {.seconds = 0.25}).find("outside the clip's 0 to 0.2 s"),
            std::string::npos);
  EXPECT_NE(refusal(clip, {.seconds = std::numeric_limits<double>::quiet_NaN()})
                .find("not a finite number"),
            std::string::npos);
  EXPECT_NE(refusal(clip, {.seconds = 0.1, .frames_per_second = -1.0f}).find("frames per second"),
            std::string::npos);
}

TEST(ClipSampling, ExactlyOneOfFrameAndTime) {
  const Retargeter clip = three_frame_clip();
  EXPECT_EQ(refusal(clip, {}), "a clip sample needs exactly one of a frame and a time");
  EXPECT_EQ(refusal(clip, {.frame = 1, .seconds = 0.1}),
            "a clip sample needs exactly one of a frame and a time");
}

}  // namespace
}  // namespace sweepd::motion::clip_sampling_test
