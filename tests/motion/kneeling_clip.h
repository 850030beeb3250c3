// A kneeling clip made from a CMU clip (issue 48 item 3: a knee resting on the floor beside its
// own planted foot): the clip's first 600 frames with the legs set, on every frame, to kneel
// on the left knee (left thigh straight down, shin back along the floor, foot stretched so its
// top lies on the floor) with the right foot planted ahead (right thigh forward, shin straight
// down), the root lowered until the left knee is at the height the clip's ankles stand at on
// its first frame. The root keeps neither the clip's path nor its turns (the spine, head and arms
// move as in the walk): it stands and faces as the clip starts and sways by 3 % of the clip's
// hip height across and back over 2 s (at most 0.21 of it a second, about half a contact's
// 0.4 L/s), so the clip moves the knee as slowly as a resting part: held, it should stand still.
// kneeling_rocking: the same kneel, but the hip rocks back and forth over a knee that stands:
// the left thigh swings by `degrees` each way over 2 s (the knee bends against it, so the shin
// stays on the floor) and the root moves so that the clip's left knee stays where it is.
#pragma once

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "motion/clip.h"
#include "tests/motion/clip_world_positions.h"

namespace sweepd::motion::test_clips {

// rock_degrees 0: the swaying kneel; else the rocking one.
inline Clip kneeling_clip(Clip clip, float rock_degrees) {
  if (clip.frame_count < 600) throw std::invalid_argument("kneeling needs 600 frames");
  clip.frame_count = clip.header_frame_count = 600;
  clip.values.resize(static_cast<std::size_t>(clip.frame_count) * clip.channel_count);
  const auto channel = [&](const std::string& joint, Channel which) {
    for (const ClipJoint& j : clip.joints) {
      if (j.name != joint) continue;
      for (std::size_t c = 0; c < j.channels.size(); ++c)
        if (j.channels[c] == which) return j.channel_offset + static_cast<int>(c);
    }
    throw std::invalid_argument("kneeling needs the CMU joint " + joint);
  };
  const auto joint = [&](const std::string& name) {
    for (std::size_t j = 0; j < clip.joints.size(); ++j)
      if (clip.joints[j].name == name) return static_cast<int>(j);
    throw std::invalid_argument("kneeling needs the CMU joint " + name);
  };
  // Degrees about each leg joint's X axis (CMU: positive bends the knee, lifts the thigh back).
  struct Set {
    const char* joint;
    float x;
  };
  const Set legs[] = {{"LeftUpLeg", 0.0f},    {"LeftLeg", 90.0f},  {"LeftFoot", 80.0f},
                      {"RightUpLeg", -95.0f}, {"RightLeg", 95.0f}, {"RightFoot", 0.0f}};
  const int x = channel("Hips", Channel::kXposition), y = channel("Hips", Channel::kYposition),
            z = channel("Hips", Channel::kZposition);
  const std::vector<glm::vec3> standing = clip_world_positions(clip, 0);
  const float ankles = std::min(standing[joint("LeftFoot")].y, standing[joint("RightFoot")].y);
  const float hip = standing[0].y - ankles;
  const float x0 = clip.values[x], z0 = clip.values[z];
  glm::vec3 knee_at_start(0.0f);
  const int turns[3] = {channel("Hips", Channel::kXrotation), channel("Hips", Channel::kYrotation),
                        channel("Hips", Channel::kZrotation)};
  for (int f = 0; f < clip.frame_count; ++f) {
    float* row = &clip.values[static_cast<std::size_t>(f) * clip.channel_count];
    const double phase = 2.0 * std::numbers::pi * f * clip.frame_time / 2.0;
    const float rock = rock_degrees * static_cast<float>(std::sin(phase));
    for (const Set& set : legs) {
      const bool left_thigh = std::string(set.joint) == "LeftUpLeg";
      const bool left_knee = std::string(set.joint) == "LeftLeg";
      row[channel(set.joint, Channel::kXrotation)] = set.x + (left_thigh  ? rock
                                                              : left_knee ? -rock
                                                                          : 0.0f);
      row[channel(set.joint, Channel::kYrotation)] = 0.0f;
      row[channel(set.joint, Channel::kZrotation)] = 0.0f;
    }
    for (const int turn : turns) row[turn] = clip.values[turn];
    const bool sway = rock_degrees == 0.0f;
    row[x] = x0 + (sway ? 0.03f * hip * static_cast<float>(std::sin(phase)) : 0.0f);
    row[z] = z0 + (sway ? 0.03f * hip * static_cast<float>(std::sin(2.0 * phase)) : 0.0f);
    const glm::vec3 knee = clip_world_positions(clip, f)[joint("LeftLeg")];
    row[y] -= knee.y - ankles;
    if (f == 0) knee_at_start = knee;
    if (!sway) row[x] -= knee.x - knee_at_start.x, row[z] -= knee.z - knee_at_start.z;
  }
  return clip;
}

inline Clip kneeling(Clip clip) { return kneeling_clip(std::move(clip), 0.0f); }
inline Clip kneeling_rocking(Clip clip, float degrees) {
  return kneeling_clip(std::move(clip), degrees);
}

}  // namespace sweepd::motion::test_clips
