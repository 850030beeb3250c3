#include "deform/model/forward_kinematics.h"

#include <cassert>
#include <glm/gtc/matrix_transform.hpp>

namespace sweepd::deform {

void forward_kinematics(const Skeleton& skeleton, const Pose& pose, std::span<glm::mat4> world) {
  assert(world.size() == skeleton.joints.size());
  assert(pose.local_rotations.size() == skeleton.joints.size());
  if (skeleton.joints.empty()) return;
  const glm::vec3 root_shift = pose.root_translation - skeleton.joints[0].rest_translation;
  for (int j = 0; j < skeleton.size(); ++j) {
    const Joint& joint = skeleton.joints[j];
    const glm::vec3 translation =
        joint.parent < 0 ? joint.rest_translation + root_shift : joint.rest_translation;
    glm::mat4 local = glm::mat4_cast(pose.local_rotations[j]);
    local[0] *= joint.rest_scale.x;
    local[1] *= joint.rest_scale.y;
    local[2] *= joint.rest_scale.z;
    local[3] = glm::vec4(translation, 1.0f);
    world[j] = joint.parent < 0 ? local : world[joint.parent] * local;
  }
}

std::vector<glm::mat4> world_rest_inverse_matrices(const Skeleton& skeleton) {
  std::vector<glm::mat4> inverse = skeleton.world_rest_matrices();
  for (glm::mat4& m : inverse) m = glm::inverse(m);
  return inverse;
}

void skinning_matrices(std::span<const glm::mat4> world_pose,
                       std::span<const glm::mat4> world_rest_inverse,
                       std::span<glm::mat4> skinning) {
  assert(world_pose.size() == world_rest_inverse.size() && skinning.size() == world_pose.size());
  for (std::size_t j = 0; j < world_pose.size(); ++j)
    skinning[j] = world_pose[j] * world_rest_inverse[j];
}

}  // namespace sweepd::deform
