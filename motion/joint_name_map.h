// JointNameMap: which clip joint drives which model joint, when names and rig roles do not
// say it (motion/retarget.h, matching step 1). Plain data: io/json/joint_name_map_json.h reads it
// from a file; a caller may also build it in code.
//
//   source  names the map in error messages (a file name, or "" for a map built in code)
//   pairs   clip joint name -> model joint name, or nothing to leave that clip joint unmapped
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace sweepd::motion {

struct JointNamePair {
  std::string clip_joint;
  std::optional<std::string> model_joint;  // nothing: leave clip_joint unmapped
};

struct JointNameMap {
  std::string source;
  std::vector<JointNamePair> pairs;
};

}  // namespace sweepd::motion
