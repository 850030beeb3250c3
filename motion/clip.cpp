#include "motion/clip.h"

#include <array>
#include <cstddef>

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
  glm::quat rotation = glm::identity<glm::quat>();
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

void Clip::local_pose(int frame, std::span<glm::quat> rotations,
                      std::span<glm::vec3> translations) const {
  for (std::size_t j = 0; j < joints.size(); ++j) {
    rotations[j] = local_rotation(static_cast<int>(j), frame);
    translations[j] = local_translation(static_cast<int>(j), frame);
  }
}

}  // namespace sweepd::motion
