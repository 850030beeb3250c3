#include "deform/key_posing.h"

namespace sweepd::deform {

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
    glm::quat turn = joint_rotation[j];
    if (anchor.is_joint_key()) {
      const int parent = skeleton.joints[j].parent;
      if (parent >= 0) turn = halfway(joint_rotation[parent], turn);
    }
    const KeyEllipse& rest = sweep.rest_keys[k];
    KeyEllipse& posed = keys[k];
    posed.centre = pose_joint[j] + turn * (rest.centre - rest_joint[j]);
    posed.orientation = glm::normalize(turn * rest.orientation);
    posed.a = rest.a;
    posed.b = rest.b;
    posed.offset = rest.offset;  // in the key's own frame: it turns with the key
  }
}

}  // namespace sweepd::deform
