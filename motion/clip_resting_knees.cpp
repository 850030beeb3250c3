#include "motion/clip_resting_knees.h"

#include "motion/body_contacts.h"

namespace sweepd::motion {

std::array<std::vector<std::uint8_t>, 2> clip_resting_knees(const Clip& clip,
                                                            std::array<int, 2> knees, float floor,
                                                            float ankle_height, float hip_height) {
  std::array<std::vector<std::uint8_t>, 2> resting;
  for (int side = 0; side < 2; ++side)
    if (knees[side] >= 0) resting[side].assign(clip.frame_count, 0);
  if (resting[0].empty() && resting[1].empty()) return resting;
  const float highest = floor + ankle_height + BodyContacts::kPartContactHeight * hip_height;
  std::vector<glm::quat> local(clip.joints.size()), world;
  std::vector<glm::vec3> translation(clip.joints.size()), position;
  for (int f = 0; f < clip.frame_count; ++f) {
    clip.local_pose(f, local, translation);
    clip_forward_kinematics(clip, local, translation, world, position);
    for (int side = 0; side < 2; ++side)
      if (knees[side] >= 0) resting[side][f] = position[knees[side]].y <= highest;
  }
  return resting;
}

}  // namespace sweepd::motion
