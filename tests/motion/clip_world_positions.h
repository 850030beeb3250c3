// A clip's world joint positions at a frame, by plain forward kinematics over
// Clip::local_pose: the tests' own reference, independent of motion::Retargeter.
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <vector>

#include "motion/clip.h"

namespace sweepd::motion {

inline std::vector<glm::vec3> clip_world_positions(const Clip& motion, int frame) {
  std::vector<glm::quat> rotations(motion.joints.size()), world(motion.joints.size());
  std::vector<glm::vec3> translations(motion.joints.size()), positions(motion.joints.size());
  motion.local_pose(frame, rotations, translations);
  for (std::size_t b = 0; b < motion.joints.size(); ++b) {
    const int parent = motion.joints[b].parent;
    world[b] = parent < 0 ? rotations[b] : world[parent] * rotations[b];
    positions[b] =
        parent < 0 ? translations[b] : positions[parent] + world[parent] * translations[b];
  }
  return positions;
}

}  // namespace sweepd::motion
