#include "motion/clip_up_axis.h"

#include <cmath>
#include <glm/gtc/quaternion.hpp>
#include <stdexcept>
#include <vector>

#include "deform/rig/rig_map.h"

namespace sweepd::motion {

namespace {

// (x, y, z) -> (x, z, -y): -90° about X, taking +Z up to +Y up.
glm::vec3 turned(const glm::vec3& v) { return {v.x, v.z, -v.y}; }

}  // namespace

std::optional<UpAxis> up_axis_from_name(std::string_view name) {
  if (name == "y") return UpAxis::kY;
  if (name == "z") return UpAxis::kZ;
  return std::nullopt;
}

const char* to_string(UpAxis axis) { return axis == UpAxis::kZ ? "z" : "y"; }

deform::Skeleton clip_rest_skeleton(const Clip& clip) {
  deform::Skeleton skeleton;
  for (const ClipJoint& joint : clip.joints)
    skeleton.joints.push_back({.name = joint.name,
                               .parent = joint.parent,
                               .rest_translation = joint.offset,
                               .rest_rotation = joint.rest_rotation,
                               .rest_scale = glm::vec3(1.0f)});
  return skeleton;
}

UpAxis detect_up_axis(const Clip& clip) {
  if (clip.joints.empty()) return UpAxis::kY;
  const deform::Skeleton skeleton = clip_rest_skeleton(clip);
  deform::RigMap map;
  try {
    map = deform::detect_rig_map(skeleton);
  } catch (const std::invalid_argument&) {
    return UpAxis::kY;
  }
  const std::vector<glm::mat4> world = skeleton.world_rest_matrices();
  const auto at = [&](int joint) { return glm::vec3(world[joint][3]); };
  const int left = map.left_leg.foot, right = map.right_leg.foot, head = map.neck.head;
  const glm::vec3 up = left >= 0 && right >= 0 && head >= 0
                           ? at(head) - (at(left) + at(right)) / 2.0f
                           : deform::rest_torso_up(map, world);
  return std::abs(up.z) > std::abs(up.y) ? UpAxis::kZ : UpAxis::kY;
}

void turn_z_up_to_y_up(Clip& clip) {
  if (clip.keyframed())
    throw std::invalid_argument("only a channel (BVH) clip is turned upright; glTF clips are Y-up");
  const glm::quat turn = glm::angleAxis(static_cast<float>(-M_PI / 2.0), glm::vec3(1, 0, 0));
  for (ClipJoint& joint : clip.joints) {
    joint.offset = turned(joint.offset);
    if (joint.end_site) joint.end_site = turned(*joint.end_site);
    joint.rest_rotation = glm::normalize(turn * joint.rest_rotation * glm::conjugate(turn));
    for (std::size_t c = 0; c < joint.channels.size(); ++c) {
      Channel& channel = joint.channels[c];
      const bool rotation = is_rotation(channel);
      if (channel == Channel::kZrotation || channel == Channel::kZposition) {
        channel = rotation ? Channel::kYrotation : Channel::kYposition;
      } else if (channel == Channel::kYrotation || channel == Channel::kYposition) {
        channel = rotation ? Channel::kZrotation : Channel::kZposition;
        for (int f = 0; f < clip.frame_count; ++f) {
          float& value = clip.values[static_cast<std::size_t>(f) * clip.channel_count +
                                     joint.channel_offset + c];
          value = -value;
        }
      }
    }
  }
}

}  // namespace sweepd::motion
