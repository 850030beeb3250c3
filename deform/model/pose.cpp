#include "deform/model/pose.h"

#include <cmath>

namespace sweepd::deform {

namespace {

bool finite(const glm::quat& q) {
  return std::isfinite(q.w) && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
}

std::string joint_label(const Skeleton& skeleton, int j) {
  return "joint " + std::to_string(j) + " ('" + skeleton.joints[j].name + "')";
}

}  // namespace

Pose rest_pose(const Skeleton& skeleton) {
  Pose pose;
  pose.local_rotations.reserve(skeleton.joints.size());
  for (const Joint& joint : skeleton.joints) pose.local_rotations.push_back(joint.rest_rotation);
  if (!skeleton.joints.empty()) pose.root_translation = skeleton.joints[0].rest_translation;
  return pose;
}

std::string normalize_and_validate(Pose& pose, const Skeleton& skeleton, double length_tolerance) {
  if (pose.local_rotations.size() != skeleton.joints.size())
    return "the pose has " + std::to_string(pose.local_rotations.size()) +
           " joint rotations, the skeleton " + std::to_string(skeleton.joints.size()) + " joints";
  const glm::vec3& t = pose.root_translation;
  if (!(std::isfinite(t.x) && std::isfinite(t.y) && std::isfinite(t.z)))
    return "the root translation is NaN or infinite";
  for (int j = 0; j < skeleton.size(); ++j) {
    glm::quat& q = pose.local_rotations[j];
    if (!finite(q)) return joint_label(skeleton, j) + " has a NaN or infinite rotation";
    // In double: a quaternion of tiny float components still has a usable direction.
    const double length =
        std::sqrt(double{q.w} * q.w + double{q.x} * q.x + double{q.y} * q.y + double{q.z} * q.z);
    if (!(length > 1e-30))
      return joint_label(skeleton, j) + " has a zero-length rotation quaternion";
    if (std::abs(length - 1.0) > length_tolerance)
      return joint_label(skeleton, j) + " has a rotation of length " + std::to_string(length) +
             ", not 1";
    if (std::abs(length - 1.0) > 1e-6) {
      q = glm::quat(static_cast<float>(q.w / length), static_cast<float>(q.x / length),
                    static_cast<float>(q.y / length), static_cast<float>(q.z / length));
    }
  }
  return {};
}

}  // namespace sweepd::deform
