#include "deform/model/pose_hash.h"

#include <cstddef>

namespace sweepd::deform {

std::uint64_t pose_hash(const Pose& pose) {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  auto mix = [&](const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) hash = (hash ^ bytes[i]) * 0x100000001b3ull;
  };
  mix(pose.local_rotations.data(), pose.local_rotations.size() * sizeof(glm::quat));
  mix(&pose.root_translation, sizeof(pose.root_translation));
  return hash;
}

}  // namespace sweepd::deform
