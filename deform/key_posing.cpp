#include "deform/key_posing.h"

namespace sweepd::deform {

namespace {

// The turn of the joint key at joint j: halfway between its upper and its lower link.
glm::quat joint_key_turn(const Skeleton& skeleton, std::span<const glm::quat> joint_rotation,
                         int j) {
  const int parent = skeleton.joints[j].parent;
  return parent >= 0 ? halfway(joint_rotation[parent], joint_rotation[j]) : joint_rotation[j];
}

}  // namespace

glm::quat halfway(const glm::quat& a, const glm::quat& b) {
  const glm::quat b_near = glm::dot(a, b) < 0.0f ? -b : b;
  return glm::normalize(a + b_near);  // slerp(a, b, 0.5) exactly: the bisector of the arc
}

void pose_key_ellipses(const BoundSweep& sweep, const Skeleton& skeleton,
                       std::span<const glm::quat> joint_rotation,
                       std::span<const glm::vec3> rest_joint, std::span<const glm::vec3> pose_joint,
                       std::span<KeyEllipse> keys) {
  for (std::size_t k = 0; k < sweep.rest_keys.size(); ++k) {
    const KeyAnchor& anchor = sweep.anchors[k];
    const int j = anchor.joint;
    const glm::quat turn =
        anchor.is_joint_key() ? joint_key_turn(skeleton, joint_rotation, j) : joint_rotation[j];
    glm::quat orientation_turn = turn;
    if (sweep.part == BodyPart::kNeck && !anchor.is_joint_key()) {
      const glm::quat from = joint_key_turn(skeleton, joint_rotation, j);
      const glm::quat to = joint_key_turn(skeleton, joint_rotation, anchor.next_joint);
      orientation_turn = glm::slerp(from, glm::dot(from, to) < 0.0f ? -to : to, anchor.fraction);
    }
    const KeyEllipse& rest = sweep.rest_keys[k];
    KeyEllipse& posed = keys[k];
    posed.centre = pose_joint[j] + turn * (rest.centre - rest_joint[j]);
    posed.orientation = glm::normalize(orientation_turn * rest.orientation);
    posed.a = rest.a;
    posed.b = rest.b;
    posed.offset = rest.offset;  // in the key's own frame: it turns with the key
  }
}

}  // namespace sweepd::deform
