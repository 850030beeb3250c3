// A model reflected through x = 0 with Left and Right swapped in its joint names
// (LeftArm <-> RightArm, LHipJoint <-> RHipJoint, after a namespace such as Mixamo's
// mixamorig:LeftArm, and as a suffix: Unreal's thigh_l <-> thigh_r, Blender's arm.L): the same
// kind of body with its sides exchanged, for tests that check nothing depends on which side is
// left. A name left unswapped would tell the rig map its left side is on its right, so the body
// would be read as facing backwards.
// Input: a Model (by value). Output: the mirrored Model (positions, normals, winding so the
// normals still point out, joints' rest translations and rotations, joint names).
#pragma once

#include <cctype>
#include <string>
#include <utility>

#include "deform/model/model.h"

namespace sweepd::test_models {

// `name` with its side marker swapped: a Left/Right or L/R (before a capital) prefix after
// any namespace up to a ':', else a _l/_r or .l/.r suffix (either case); unchanged without one.
inline std::string side_swapped(const std::string& name) {
  const std::size_t start = name.rfind(':') == std::string::npos ? 0 : name.rfind(':') + 1;
  const std::string space = name.substr(0, start);
  std::string n = name.substr(start);
  if (n.starts_with("Left")) return space + "Right" + n.substr(4);
  if (n.starts_with("Right")) return space + "Left" + n.substr(5);
  if (n.size() > 1 && (n[0] == 'L' || n[0] == 'R') && std::isupper(n[1])) {
    n[0] = n[0] == 'L' ? 'R' : 'L';
    return space + n;
  }
  const std::size_t last = n.size() - 1;
  if (n.size() > 2 && (n[last - 1] == '_' || n[last - 1] == '.')) {
    const char side = n[last];
    if (side == 'l' || side == 'L') n[last] = side == 'l' ? 'r' : 'R';
    else if (side == 'r' || side == 'R') n[last] = side == 'r' ? 'l' : 'L';
  }
  return space + n;
}

inline deform::Model mirrored(deform::Model model) {
  for (glm::vec3& p : model.positions) p.x = -p.x;
  for (glm::vec3& n : model.normals) n.x = -n.x;
  for (std::size_t t = 0; t + 2 < model.indices.size(); t += 3)
    std::swap(model.indices[t + 1], model.indices[t + 2]);
  for (deform::Joint& joint : model.skeleton.joints) {
    joint.rest_translation.x = -joint.rest_translation.x;
    joint.rest_rotation.y = -joint.rest_rotation.y;  // M R M with M = diag(-1, 1, 1)
    joint.rest_rotation.z = -joint.rest_rotation.z;
    joint.name = side_swapped(joint.name);
  }
  return model;
}

}  // namespace sweepd::test_models
