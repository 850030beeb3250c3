// pose_hash: a stable 64-bit hash (FNV-1a) of a pose's numbers, its rotations then its root
// translation, as their bytes: names a frame's pose in EXR headers ("poseHash"), the same for
// the same pose whether sweepctl or sweepd wrote the file.
#pragma once

#include <cstdint>

#include "deform/model/pose.h"

namespace sweepd::deform {

std::uint64_t pose_hash(const Pose& pose);

}  // namespace sweepd::deform
