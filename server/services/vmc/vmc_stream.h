// VmcStream: what a VMC stream's messages (protocol.vmc.info) have said so far, and the pose it
// gives a model. apply() reads one packet's messages (osc_packet.h), in order:
//   /VMC/Ext/Bone/Pos  s fff ffff   a HumanBodyBones bone's local position and rotation, in
//                                   Unity's frame (unity_frame.h); a name that is not one of
//                                   Unity's 55 (deform/rig/human_body_bones.h) is dropped
//   /VMC/Ext/Root/Pos  s fff ffff [fff fff]  the avatar's root; VMC 2.1's scale and offset,
//                                   when present, are read past and not used
//   /VMC/Ext/OK        i [i i [i]]  the sender's state: ends a frame
//   /VMC/Ext/T         f            the sender's time: ends a frame
// A message with those addresses and other type tags (a short one, ints for floats) or a value
// that is not finite (or a zero rotation) is dropped and counted; every other address (blend
// shapes, cameras, trackers, anything unknown) is ignored and counted. A packet that is a bundle
// ends a frame once, whatever it holds; so does a lone OK or T.
//
// pose_for(skeleton, bones): the model's rest pose, each bone the stream has sent replacing its
// joint's local rotation (the sender's local rotation, mirrored into glTF's frame: a stream of
// the same skeleton's own local rotations poses it exactly); the bone on joint 0 also sets the
// root translation (its position); other bones' positions are not used (a Pose moves only its
// root). The root's transform, when sent, is then applied to joint 0 (rotation before, and
// position added to, its own). Bones a stream has not sent (yet) stay at rest; a bone keeps its
// last value until it is sent again.
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "deform/model/pose.h"
#include "deform/model/skeleton.h"
#include "deform/rig/human_body_bones.h"
#include "server/services/vmc/osc_packet.h"

namespace sweepd::server {

// What a receiver counts (server/http/metrics_text.h names them in /metrics).
struct VmcCounters {
  std::uint64_t packets = 0;           // datagrams received
  std::uint64_t bundles = 0;           // bundles read (nested ones too)
  std::uint64_t messages = 0;          // messages read
  std::uint64_t bones = 0;             // Bone/Pos messages applied
  std::uint64_t frames = 0;            // frames ended (each poses the stream's model once)
  std::uint64_t dropped_packets = 0;   // not OSC 1.0 (torn, short, fuzzed): nothing applied
  std::uint64_t dropped_messages = 0;  // a VMC address with wrong type tags or values
  std::uint64_t ignored_messages = 0;  // addresses the receiver does not read
  std::uint64_t frames_without_model = 0;  // ended while the stream's model is not held
};

class VmcStream {
 public:
  // Returns true when the packet ends a frame.
  bool apply(const OscPacket& packet, VmcCounters& counters);
  deform::Pose pose_for(const deform::Skeleton& skeleton,
                        const std::array<int, deform::kHumanBodyBoneCount>& bones) const;

 private:
  struct BoneState {
    bool sent = false;
    glm::vec3 position{0.0f};
    glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
  };
  // Returns false for a message to drop (wrong types or values).
  bool apply_bone(const OscMessage& message, VmcCounters& counters);
  bool apply_root(const OscMessage& message);

  std::array<BoneState, deform::kHumanBodyBoneCount> bones_{};
  glm::vec3 root_position_{0.0f};
  glm::quat root_rotation_{1.0f, 0.0f, 0.0f, 0.0f};
};

}  // namespace sweepd::server
