// Joint name map JSON: the file a user writes when a clip's joint names and rig roles do not
// say which model joint each clip joint drives (`sweepctl pose --bvh-map MAP.json`).
//
// Format: one object, clip joint name -> model joint name, or null to leave that clip joint
// unmapped:
//   {"LFingers": "LeftHandFinger1", "Head": null}
// Output: a motion::JointNameMap (motion/joint_name_map.h), pairs by clip joint name, its
// source the path.
// Whether the names exist is checked against the clip and the model by motion::Retargeter.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "motion/joint_name_map.h"

namespace sweepd::io {

// Throws LoadError naming the file: not JSON, not an object, a value neither a string nor null.
motion::JointNameMap load_joint_name_map_json(const std::filesystem::path& path);

// The same from JSON text (UploadClip.joint_name_map): `source` names it in errors and becomes
// the map's source.
motion::JointNameMap parse_joint_name_map_json(std::string_view text, const std::string& source);

}  // namespace sweepd::io
