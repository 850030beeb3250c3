#include "deform/model/joint_flexion.h"

#include <cmath>
#include <glm/gtc/quaternion.hpp>
#include <stdexcept>
#include <vector>

namespace sweepd::deform {
namespace {

struct Links {
  glm::vec3 upper, lower;
};

Links rest_links(const Skeleton& skeleton, int joint) {
  const Joint& j = skeleton.joints.at(joint);
  const std::vector<int> children = skeleton.children(joint);
  if (j.parent < 0 || children.empty())
    throw std::invalid_argument("joint '" + j.name +
                                "' needs a parent and a child to have a flexion");
  const std::vector<glm::mat4> world = skeleton.world_rest_matrices();
  auto position = [&](int k) { return glm::vec3(world[k][3]); };
  return {position(joint) - position(j.parent), position(children.front()) - position(joint)};
}

// The world rest rotation of the joint's parent (identity for a root), any rest scale dropped.
glm::quat parent_rest_rotation(const Skeleton& skeleton, int joint) {
  const int parent = skeleton.joints.at(joint).parent;
  if (parent < 0) return glm::quat(1, 0, 0, 0);
  glm::mat3 rotation(skeleton.world_rest_matrices()[parent]);
  for (int c = 0; c < 3; ++c) rotation[c] = glm::normalize(rotation[c]);
  return glm::quat_cast(rotation);
}

// The links' flexion about `axis` (unit), in degrees: only their components orthogonal to the
// axis bend about it.
float flexion_degrees(const Links& links, glm::vec3 axis) {
  const glm::vec3 upper = links.upper - glm::dot(links.upper, axis) * axis;
  const glm::vec3 lower = links.lower - glm::dot(links.lower, axis) * axis;
  return glm::degrees(std::atan2(glm::dot(glm::cross(upper, lower), axis), glm::dot(upper, lower)));
}

}  // namespace

float rest_flexion_degrees(const Skeleton& skeleton, int joint, glm::vec3 world_axis) {
  return flexion_degrees(rest_links(skeleton, joint), glm::normalize(world_axis));
}

void flex_joint(const Skeleton& skeleton, Pose& pose, int joint, glm::vec3 world_axis,
                float degrees) {
  const glm::vec3 axis = glm::normalize(world_axis);
  turn_joint(skeleton, pose, joint, axis,
             degrees - flexion_degrees(rest_links(skeleton, joint), axis));
}

void turn_joint(const Skeleton& skeleton, Pose& pose, int joint, glm::vec3 world_axis,
                float degrees) {
  // The world turn expressed in the parent's frame, applied before the rest rotation.
  const glm::vec3 local_axis = glm::inverse(glm::normalize(parent_rest_rotation(skeleton, joint))) *
                               glm::normalize(world_axis);
  pose.local_rotations.at(joint) = glm::normalize(
      glm::angleAxis(glm::radians(degrees), local_axis) * skeleton.joints[joint].rest_rotation);
}

}  // namespace sweepd::deform
