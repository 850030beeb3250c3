#include "motion/clip_arms_through_floor.h"

#include <algorithm>
#include <limits>

namespace sweepd::motion {

std::vector<std::uint8_t> clip_arms_through_floor(const Clip& clip, std::span<const int> torso,
                                                  std::array<int, 2> arms, float floor,
                                                  float hip_height) {
  std::vector<std::uint8_t> through(clip.frame_count, 0);
  if (torso.empty() || !(hip_height > 0.0f)) return through;
  // Each arm's joints: its upper joint and every joint below it (the hand's and fingers' too:
  // a model whose forearm carries the hand maps no clip joint to the wrist).
  std::array<std::vector<int>, 2> arm_joints;
  for (int side = 0; side < 2; ++side)
    for (int j = 0; j < static_cast<int>(clip.joints.size()) && arms[side] >= 0; ++j)
      for (int up = j; up >= 0; up = clip.joints[up].parent)
        if (up == arms[side]) {
          arm_joints[side].push_back(j);
          break;
        }
  const float highest = floor + kLyingTorsoHeight * hip_height;
  std::vector<glm::quat> local(clip.joints.size()), world;
  std::vector<glm::vec3> translation(clip.joints.size()), position;
  const auto lowest = [&](std::span<const int> joints) {
    float y = std::numeric_limits<float>::infinity();
    for (const int joint : joints)
      if (joint >= 0) y = std::min(y, position[joint].y);
    return y;
  };
  for (int f = 0; f < clip.frame_count; ++f) {
    clip.local_pose(f, local, translation);
    clip_forward_kinematics(clip, local, translation, world, position);
    if (lowest(torso) > highest) continue;
    for (int side = 0; side < 2; ++side)
      if (lowest(arm_joints[side]) < floor) through[f] |= static_cast<std::uint8_t>(1 << side);
  }
  return through;
}

}  // namespace sweepd::motion
