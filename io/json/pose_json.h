// Pose JSON: a pose written by hand (or saved by sweepd) for `sweepctl pose --pose FILE`.
//
// Format (both keys optional; any other key is an error):
//   {
//     "root_translation": [x, y, z],                 // joint 0's local translation (metres)
//     "rotations": {
//       "LeftForeArm": {"axis": [1, 0, 0], "degrees": 90},   // axis need not be unit length
//       "Neck": [w, x, y, z]                                 // a quaternion, normalised on load
//     }
//   }
// Rotations are LOCAL to the joint's parent and replace the joint's rest rotation (see
// deform/model/pose.h); joints not listed keep their rest rotation, a missing root_translation
// keeps joint 0's rest translation. Joints are named, never numbered.
#pragma once

#include <filesystem>

#include "deform/model/pose.h"
#include "deform/model/skeleton.h"

namespace sweepd::io {

// Throws LoadError naming the file and the problem: not JSON, an unknown key, a joint name the
// skeleton lacks, an array of the wrong length or with non-numbers, NaN or infinite numbers, a
// zero-length axis or quaternion.
deform::Pose load_pose_json(const std::filesystem::path& path, const deform::Skeleton& skeleton);

// Writes the root translation and, as [w, x, y, z], every rotation that differs from the rest
// rotation, so that load_pose_json gives the same pose back exactly. Throws
// std::invalid_argument when the pose does not fit the skeleton and std::runtime_error naming
// the file when it cannot be written.
void save_pose_json(const deform::Pose& pose, const deform::Skeleton& skeleton,
                    const std::filesystem::path& path);

}  // namespace sweepd::io
