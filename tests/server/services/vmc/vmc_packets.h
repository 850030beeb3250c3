// VMC packets as a sender writes them, made with liblo (Debian's liblo-dev: the library senders
// on Linux use): a Bone/Pos message, a frame's bundle (every bone of a pose, then /VMC/Ext/OK and
// /VMC/Ext/T, as VSeeFace and VirtualMotionCapture send a frame), and any message's bytes.
#pragma once

#include <lo/lo.h>

#include <cstddef>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <string>
#include <vector>

namespace sweepd::test {

// One bone's transform in Unity's frame, as Bone/Pos carries it.
struct VmcBone {
  std::string name;
  glm::vec3 position{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
};

inline lo_message vmc_bone_message(const VmcBone& bone) {
  lo_message message = lo_message_new();
  lo_message_add_string(message, bone.name.c_str());
  lo_message_add_float(message, bone.position.x);
  lo_message_add_float(message, bone.position.y);
  lo_message_add_float(message, bone.position.z);
  lo_message_add_float(message, bone.rotation.x);
  lo_message_add_float(message, bone.rotation.y);
  lo_message_add_float(message, bone.rotation.z);
  lo_message_add_float(message, bone.rotation.w);
  return message;
}

// A message's bytes on the wire (frees it).
inline std::vector<std::byte> osc_bytes(lo_message message, const char* address) {
  std::vector<std::byte> bytes(lo_message_length(message, address));
  std::size_t size = bytes.size();
  lo_message_serialise(message, address, bytes.data(), &size);
  lo_message_free(message);
  return bytes;
}

// A frame's bundle, to send with lo_send_bundle; free with lo_bundle_free_recursive.
inline lo_bundle vmc_frame_bundle(const std::vector<VmcBone>& bones, float seconds) {
  lo_bundle bundle = lo_bundle_new(LO_TT_IMMEDIATE);
  for (const VmcBone& bone : bones)
    lo_bundle_add_message(bundle, "/VMC/Ext/Bone/Pos", vmc_bone_message(bone));
  lo_message ok = lo_message_new();
  lo_message_add_int32(ok, 1);
  lo_bundle_add_message(bundle, "/VMC/Ext/OK", ok);
  lo_message time = lo_message_new();
  lo_message_add_float(time, seconds);
  lo_bundle_add_message(bundle, "/VMC/Ext/T", time);
  return bundle;
}

inline std::vector<std::byte> bundle_bytes(lo_bundle bundle) {
  std::size_t size = lo_bundle_length(bundle);
  std::vector<std::byte> bytes(size);
  lo_bundle_serialise(bundle, bytes.data(), &size);
  return bytes;
}

}  // namespace sweepd::test
