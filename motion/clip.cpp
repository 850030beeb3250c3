#include "motion/clip.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>

namespace sweepd::motion {

namespace {
constexpr std::array<std::string_view, 6> kChannelNames = {"Xposition", "Yposition", "Zposition",
                                                           "Xrotation", "Yrotation", "Zrotation"};

const float* joint_row(const Clip& motion, int joint, int frame) {
  return motion.values.data() + static_cast<std::size_t>(frame) * motion.channel_count +
         motion.joints[joint].channel_offset;
}
}  // namespace

std::string_view channel_name(Channel channel) {
  return kChannelNames[static_cast<std::size_t>(channel)];
}

std::optional<Channel> channel_from_name(std::string_view name) {
  for (std::size_t i = 0; i < kChannelNames.size(); ++i) {
    if (kChannelNames[i] == name) return static_cast<Channel>(i);
  }
  return std::nullopt;
}

bool is_rotation(Channel channel) {
  return channel == Channel::kXrotation || channel == Channel::kYrotation ||
         channel == Channel::kZrotation;
}

glm::vec3 channel_axis(Channel channel) {
  glm::vec3 axis(0.0f);
  axis[static_cast<int>(channel) % 3] = 1.0f;
  return axis;
}

std::span<const float> Clip::frame(int frame) const {
  return std::span<const float>(values).subspan(static_cast<std::size_t>(frame) * channel_count,
                                                static_cast<std::size_t>(channel_count));
}

int Clip::find(std::string_view name) const {
  for (std::size_t j = 0; j < joints.size(); ++j) {
    if (joints[j].name == name) return static_cast<int>(j);
  }
  return -1;
}

glm::quat Clip::local_rotation(int joint, int frame) const {
  const float* row = joint_row(*this, joint, frame);
  glm::quat rotation = joints[joint].rest_rotation;
  const std::vector<Channel>& channels = joints[joint].channels;
  for (std::size_t c = 0; c < channels.size(); ++c) {
    if (!is_rotation(channels[c])) continue;
    rotation = rotation * glm::angleAxis(glm::radians(row[c]), channel_axis(channels[c]));
  }
  return rotation;
}

glm::vec3 Clip::local_translation(int joint, int frame) const {
  const float* row = joint_row(*this, joint, frame);
  glm::vec3 translation = joints[joint].offset;
  const std::vector<Channel>& channels = joints[joint].channels;
  for (std::size_t c = 0; c < channels.size(); ++c) {
    if (is_rotation(channels[c])) continue;
    translation[static_cast<int>(channels[c])] += row[c];
  }
  return translation;
}

double Clip::duration() const {
  return keyframed() ? double{end_time} - start_time : (frame_count - 1) * double{frame_time};
}

void Clip::local_pose(int frame, std::span<glm::quat> rotations,
                      std::span<glm::vec3> translations) const {
  if (keyframed()) return local_pose_at_time(frame * double{frame_time}, rotations, translations);
  for (std::size_t j = 0; j < joints.size(); ++j) {
    rotations[j] = local_rotation(static_cast<int>(j), frame);
    translations[j] = local_translation(static_cast<int>(j), frame);
  }
}

void Clip::local_pose_at_time(double seconds, std::span<glm::quat> rotations,
                              std::span<glm::vec3> translations) const {
  if (std::isnan(seconds)) throw std::invalid_argument("the time to sample is NaN");
  seconds = std::clamp(seconds, 0.0, duration());
  if (keyframed()) {
    for (std::size_t j = 0; j < joints.size(); ++j) {
      rotations[j] = joints[j].rest_rotation;
      translations[j] = joints[j].offset;
    }
    float value[4];
    for (const KeyframeTrack& track : tracks) {
      sample_track(track, start_time + seconds, value);
      if (track.path == TrackPath::kRotation)
        rotations[track.joint] = glm::quat(value[3], value[0], value[1], value[2]);
      else
        translations[track.joint] = glm::vec3(value[0], value[1], value[2]);
    }
    return;
  }
  const double frame_position = seconds / frame_time;
  const int last = frame_count - 1;
  const int first = std::min(static_cast<int>(std::floor(frame_position)), last);
  const int second = std::min(first + 1, last);
  const float alpha = static_cast<float>(frame_position - first);
  local_pose(first, rotations, translations);
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const int joint = static_cast<int>(j);
    rotations[j] = glm::slerp(rotations[j], local_rotation(joint, second), alpha);
    translations[j] = glm::mix(translations[j], local_translation(joint, second), alpha);
  }
}

void Clip::set_keyframed_timing() {
  float start = std::numeric_limits<float>::infinity(), end = -start;
  double gap = std::numeric_limits<double>::infinity();
  for (const KeyframeTrack& track : tracks) {
    start = std::min(start, track.times.front());
    end = std::max(end, track.times.back());
    for (std::size_t k = 1; k < track.times.size(); ++k)
      gap = std::min(gap, double{track.times[k]} - track.times[k - 1]);
  }
  start_time = start;
  end_time = end;
  frame_time = std::isfinite(gap) ? static_cast<float>(gap) : 1.0f / 30.0f;
  frame_count = static_cast<int>(std::floor(duration() / frame_time + 1e-3)) + 1;
  header_frame_count = frame_count;
}

void clip_forward_kinematics(const Clip& motion, std::span<const glm::quat> local,
                             std::span<const glm::vec3> translation, std::vector<glm::quat>& world,
                             std::vector<glm::vec3>& position) {
  world.resize(motion.joints.size());
  position.resize(motion.joints.size());
  for (std::size_t b = 0; b < motion.joints.size(); ++b) {
    const int parent = motion.joints[b].parent;
    world[b] = parent < 0 ? local[b] : world[parent] * local[b];
    position[b] = parent < 0 ? translation[b] : position[parent] + world[parent] * translation[b];
  }
}

}  // namespace sweepd::motion
