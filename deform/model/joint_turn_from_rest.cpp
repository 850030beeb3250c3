#include "deform/model/joint_turn_from_rest.h"

#include <algorithm>
#include <cmath>

namespace sweepd::deform {

float joint_turn_from_rest(const Skeleton& skeleton, std::span<const glm::quat> joint_rotation,
                           int joint) {
  const int parent = skeleton.joints[joint].parent;
  const glm::quat upper = parent >= 0 ? joint_rotation[parent] : glm::quat(1, 0, 0, 0);
  const glm::quat relative = glm::conjugate(upper) * joint_rotation[joint];
  // |w| = cos(angle / 2); the shorter arc either sign of the quaternion represents.
  return 2.0f * std::acos(std::clamp(std::abs(relative.w) / glm::length(relative), 0.0f, 1.0f));
}

}  // namespace sweepd::deform
