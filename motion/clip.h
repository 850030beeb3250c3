// Clip: the animation clip of motion/ — a joint hierarchy with per-frame channel values (a BVH
// file read by io/bvh/bvh_load.h, or a clip built in code) or with keyframe tracks (a glTF
// animation read by io/gltf/gltf_clip_load.h; motion/keyframe_track.h).
//
// Joints are in file order, which is parents first (parent index < own index; roots have -1).
// Each joint has a rest offset from its parent and the channels it animates, in file order.
// Channel values of all frames sit in one row-major buffer:
//   values  frame_count × channel_count floats; a joint's channels of frame f start at
//           values[f * channel_count + joint.channel_offset].
// Rotation values are degrees. Position values and offsets are already multiplied by the
// loader's length scale, so they are in the caller's units (e.g. metres).
// A keyframed clip has no channels or values: its tracks give joints' local rotations and
// translations at any time (glTF semantics: a track replaces the rest value; joints without
// one keep rest_rotation and offset). Its frames are times start_time + f * frame_time.
// Sampling lives here and in motion/keyframe_track.h only: local_pose (a frame) and
// local_pose_at_time (any time) serve both kinds, and the players (motion/clip_poses.h) call
// them.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "motion/keyframe_track.h"

namespace sweepd::motion {

enum class Channel : std::uint8_t {
  kXposition,
  kYposition,
  kZposition,
  kXrotation,
  kYrotation,
  kZrotation,
};

// The BVH spelling of the channel: "Xposition" ... "Zrotation".
std::string_view channel_name(Channel channel);
// The channel with that exact BVH spelling, or nothing.
std::optional<Channel> channel_from_name(std::string_view name);
bool is_rotation(Channel channel);
// Unit axis of the channel: +X, +Y or +Z.
glm::vec3 channel_axis(Channel channel);

struct ClipJoint {
  std::string name;
  int parent = -1;                    // index into Clip::joints, -1 for a root
  glm::vec3 offset{0.0f};             // rest translation from the parent, scaled
  std::vector<Channel> channels;      // in file order (any subset, any order)
  int channel_offset = 0;             // index of the first channel within a frame's row
  std::optional<glm::vec3> end_site;  // the "End Site" offset, scaled, when the file has one
  // Rotation relative to the parent when nothing drives it: the identity for BVH (whose rest
  // pose has every channel zero); a glTF node's rest rotation.
  glm::quat rest_rotation{1.0f, 0.0f, 0.0f, 0.0f};
};

struct Clip {
  std::vector<ClipJoint> joints;
  int channel_count = 0;              // sum of the joints' channel counts
  int frame_count = 0;                // data rows present in the file
  int header_frame_count = 0;         // what the file's "Frames:" line claims
  float frame_time = 0.0f;            // seconds per frame, > 0
  std::vector<float> values;          // frame_count × channel_count, row-major
  std::vector<std::string> warnings;  // problems that did not stop loading, in words
  std::vector<KeyframeTrack> tracks;  // a keyframed clip's tracks (then values is empty)
  float start_time = 0.0f;            // a keyframed clip: the time of its frame 0 (its first key)
  float end_time = 0.0f;              // a keyframed clip: its last key's time

  float frames_per_second() const { return 1.0f / frame_time; }
  bool keyframed() const { return !tracks.empty(); }
  // Seconds from frame 0 to the clip's end: (frame_count - 1) * frame_time, or a keyframed
  // clip's end_time - start_time.
  double duration() const;
  // The channel values of one frame (channel_count floats).
  std::span<const float> frame(int frame) const;
  // Index of the joint with this exact name, or -1.
  int find(std::string_view name) const;

  // Of a channel clip (BVH): the rotation of joint relative to its parent at frame, its
  // rest_rotation times the rotation channels composed in file order, so "Zrotation Yrotation
  // Xrotation" gives Rz * Ry * Rx (applied to column vectors); rest_rotation when the joint has
  // no rotation channels.
  // Requires 0 <= joint < joints.size() and 0 <= frame < frame_count.
  glm::quat local_rotation(int joint, int frame) const;
  // Translation of joint relative to its parent at frame: offset plus its position channels.
  glm::vec3 local_translation(int joint, int frame) const;
  // Local rotation and translation of every joint at frame, into caller-owned buffers:
  // local_rotation and local_translation, or a keyframed clip's tracks at the frame's time.
  //   rotations, translations  joints.size() each
  void local_pose(int frame, std::span<glm::quat> rotations,
                  std::span<glm::vec3> translations) const;
  // The same at `seconds` after frame 0, clamped to [0, duration()]: a channel clip's frames
  // on either side with rotations slerped and translations lerped; a keyframed clip's tracks
  // sampled per the glTF spec (motion/keyframe_track.h). NaN is std::invalid_argument.
  void local_pose_at_time(double seconds, std::span<glm::quat> rotations,
                          std::span<glm::vec3> translations) const;
  // Of a keyframed clip whose tracks are set: start_time and end_time from its first and last
  // key, frame_time the smallest interval between two keys of one track (a clip baked at every
  // frame of a 30 fps scene gets 1/30 s; 1/30 s when every track has one key), frame_count
  // (and header_frame_count) the frames that fit.
  void set_keyframed_timing();
};

// World rotations and positions of a clip's joints from their local ones (local_pose's).
//   local, translation  joints.size() each; world, position  resized to joints.size()
void clip_forward_kinematics(const Clip& motion, std::span<const glm::quat> local,
                             std::span<const glm::vec3> translation, std::vector<glm::quat>& world,
                             std::vector<glm::vec3>& position);

}  // namespace sweepd::motion
