#include "motion/named_joints.h"

#include <stdexcept>

#include "deform/rig/rig_naming.h"

namespace sweepd::motion {

std::vector<int> named_joints(const deform::Skeleton& skeleton, const deform::RigMap& model_rig,
                              std::span<const std::string> names) {
  const deform::NameRoles named = deform::match_name_roles(names);
  const std::array<int, deform::kRigRoleCount> model_roles = deform::rig_roles(model_rig);
  std::vector<int> joints(names.size(), -1);
  for (std::size_t role = 0; role < named.roles.size(); ++role)
    if (named.roles[role] >= 0) joints[named.roles[role]] = model_roles[role];
  std::vector<int> named_by(skeleton.joints.size(), -1);  // which name drives a model joint
  std::string unknown, twice;
  for (std::size_t i = 0; i < names.size(); ++i) {
    for (int j = 0; j < skeleton.size(); ++j)
      if (skeleton.joints[j].name == names[i]) joints[i] = j;
    if (joints[i] < 0) {
      unknown += (unknown.empty() ? "'" : ", '") + names[i] + "'";
      continue;
    }
    int& first = named_by[joints[i]];
    if (first >= 0 && twice.empty())
      twice = "'" + names[first] + "' and '" + names[i] + "' both name model joint '" +
              skeleton.joints[joints[i]].name + "'";
    first = static_cast<int>(i);
  }
  if (!unknown.empty()) {
    std::string model_names;
    for (const deform::Joint& joint : skeleton.joints)
      model_names += (model_names.empty() ? "" : ", ") + joint.name;
    throw std::invalid_argument("unknown joint names " + unknown +
                                ": neither a joint of the model (" + model_names +
                                ") nor a role the names' convention" +
                                (named.convention.empty() ? std::string(" (none recognised)")
                                                          : " (" + named.convention + ")") +
                                " gives a joint of it");
  }
  if (!twice.empty()) throw std::invalid_argument(twice);
  return joints;
}

deform::Pose pose_from_named_rotations(const deform::Skeleton& skeleton,
                                       std::span<const int> joints,
                                       std::span<const glm::quat> rotations,
                                       const glm::vec3& root_translation) {
  deform::Pose pose = deform::rest_pose(skeleton);
  for (std::size_t i = 0; i < joints.size(); ++i) pose.local_rotations[joints[i]] = rotations[i];
  pose.root_translation = root_translation;
  return pose;
}

}  // namespace sweepd::motion
