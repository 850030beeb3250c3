#include "server/services/vmc/vmc_stream.h"

#include <cmath>
#include <cstring>
#include <string_view>

#include "server/services/vmc/unity_frame.h"

namespace sweepd::server {
namespace {

constexpr std::string_view kBonePos = "/VMC/Ext/Bone/Pos";
constexpr std::string_view kRootPos = "/VMC/Ext/Root/Pos";
constexpr std::string_view kOk = "/VMC/Ext/OK";
constexpr std::string_view kTime = "/VMC/Ext/T";
// A name, a position (3 floats) and a rotation (x, y, z, w).
constexpr std::string_view kTransform = "sfffffff";
// VMC 2.1's root: the same, then a scale and an offset (3 floats each).
constexpr std::string_view kRootWithScale = "sfffffffffffff";

// The position and rotation of a transform message (kTransform's layout), if finite and the
// rotation is not zero; otherwise false, and `position` and `rotation` keep their values (a
// dropped Root/Pos must not leave the root half written).
bool read_transform(const OscMessage& message, glm::vec3& position, glm::quat& rotation) {
  lo_arg** argument = message.arguments();
  float value[7];
  for (int i = 0; i < 7; ++i) {
    // liblo's argument pointers are 4-byte aligned, its lo_arg union 8: copy, not lo_arg::f.
    std::memcpy(&value[i], argument[1 + i], sizeof(float));
    if (!std::isfinite(value[i])) return false;
  }
  const glm::quat read(value[6], value[3], value[4], value[5]);
  const float length = glm::length(read);
  if (!(length > 1e-6f)) return false;
  position = {value[0], value[1], value[2]};
  rotation = read / length;
  return true;
}

bool only_ints(std::string_view types) {
  return types.find_first_not_of('i') == std::string_view::npos;
}

}  // namespace

bool VmcStream::apply(const OscPacket& packet, VmcCounters& counters) {
  counters.bundles += packet.bundles;
  bool frame_ends = packet.bundles > 0;
  for (const OscMessage& message : packet.messages) {
    ++counters.messages;
    const std::string_view address = message.address;
    bool read = true;
    if (address == kBonePos) {
      read = message.types == kTransform && apply_bone(message, counters);
    } else if (address == kRootPos) {
      read =
          (message.types == kTransform || message.types == kRootWithScale) && apply_root(message);
    } else if (address == kOk) {
      const std::size_t count = message.types.size();
      read = (count == 1 || count == 3 || count == 4) && only_ints(message.types);
      frame_ends = frame_ends || read;
    } else if (address == kTime) {
      read = message.types == "f";
      frame_ends = frame_ends || read;
    } else {
      ++counters.ignored_messages;
    }
    if (!read) ++counters.dropped_messages;
  }
  return frame_ends;
}

bool VmcStream::apply_bone(const OscMessage& message, VmcCounters& counters) {
  const int bone =
      deform::human_body_bone_index(reinterpret_cast<const char*>(message.arguments()[0]));
  BoneState state;
  if (bone < 0 || !read_transform(message, state.position, state.rotation)) return false;
  state.sent = true;
  bones_[bone] = state;
  ++counters.bones;
  return true;
}

bool VmcStream::apply_root(const OscMessage& message) {
  return read_transform(message, root_position_, root_rotation_);
}

deform::Pose VmcStream::pose_for(const deform::Skeleton& skeleton,
                                 const std::array<int, deform::kHumanBodyBoneCount>& bones) const {
  deform::Pose pose = deform::rest_pose(skeleton);
  for (int bone = 0; bone < deform::kHumanBodyBoneCount; ++bone) {
    const int joint = bones[bone];
    if (joint < 0 || !bones_[bone].sent) continue;
    pose.local_rotations[joint] = unity_mirrored(bones_[bone].rotation);
    if (joint == 0) pose.root_translation = unity_mirrored(bones_[bone].position);
  }
  if (!pose.local_rotations.empty()) {
    const glm::quat root = unity_mirrored(root_rotation_);
    pose.local_rotations[0] = root * pose.local_rotations[0];
    pose.root_translation = unity_mirrored(root_position_) + root * pose.root_translation;
  }
  return pose;
}

}  // namespace sweepd::server
