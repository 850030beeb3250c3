// Which frames a clip rests a knee on its floor (motion/clip_resting_knees.h): none on CMU's
// walks, the left knee on every frame of the kneeling clip (tests/motion/kneeling_clip.h, whose
// left knee joint stands exactly at the height of the walk's ankles on its first frame) and
// never the right, whose foot is planted ahead with the thigh level.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <numeric>
#include <string>

#include "io/bvh/bvh_load.h"
#include "motion/clip_resting_knees.h"
#include "tests/motion/clip_world_positions.h"
#include "tests/motion/kneeling_clip.h"

namespace sweepd::motion {
namespace {

namespace fs = std::filesystem;

int joint(const Clip& clip, const std::string& name) {
  for (std::size_t j = 0; j < clip.joints.size(); ++j)
    if (clip.joints[j].name == name) return static_cast<int>(j);
  return -1;
}

int count(const std::vector<std::uint8_t>& frames) {
  return std::accumulate(frames.begin(), frames.end(), 0);
}

// CMU's floor is y = 0; its ankles and hip as the walk stands on its first frame.
std::array<std::vector<std::uint8_t>, 2> resting(const Clip& walk, const Clip& clip) {
  const std::vector<glm::vec3> standing = clip_world_positions(walk, 0);
  const float ankles =
      std::min(standing[joint(walk, "LeftFoot")].y, standing[joint(walk, "RightFoot")].y);
  return clip_resting_knees(clip, {joint(clip, "LeftLeg"), joint(clip, "RightLeg")}, 0.0f, ankles,
                            standing[0].y);
}

TEST(ClipRestingKnees, NoneInAWalkTheLeftKneeInAKneel) {
  const fs::path motion = fs::path(SWEEPD_SHARED_DATA) / "motion";
  if (!fs::exists(motion / "cmu_01_01.bvh")) GTEST_SKIP() << "shared data absent: " << motion;
  const Clip walk = io::load_bvh(motion / "cmu_01_01.bvh");
  for (const char* name : {"cmu_01_01.bvh", "cmu_01_03.bvh"}) {
    const Clip clip = io::load_bvh(motion / name);
    const auto knees = resting(walk, clip);
    EXPECT_EQ(count(knees[0]), 0) << name;
    EXPECT_EQ(count(knees[1]), 0) << name;
  }
  const Clip kneel = test_clips::kneeling(walk);
  const auto knees = resting(walk, kneel);
  EXPECT_EQ(count(knees[0]), kneel.frame_count);
  EXPECT_EQ(count(knees[1]), 0);
}

TEST(ClipRestingKnees, ASideWithoutAKneeHasNoFrames) {
  const fs::path file = fs::path(SWEEPD_SHARED_DATA) / "motion/cmu_01_01.bvh";
  if (!fs::exists(file)) GTEST_SKIP() << "shared data absent: " << file;
  const Clip walk = io::load_bvh(file);
  const auto knees = clip_resting_knees(walk, {-1, joint(walk, "RightLeg")}, 0.0f, 0.1f, 1.0f);
  EXPECT_TRUE(knees[0].empty());
  EXPECT_EQ(knees[1].size(), static_cast<std::size_t>(walk.frame_count));
}

}  // namespace
}  // namespace sweepd::motion
