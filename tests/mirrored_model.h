// A model reflected through x = 0 with Left and Right swapped in its joint names
// (LeftArm <-> RightArm, LHipJoint <-> RHipJoint): the same kind of body with its sides
// exchanged, for tests that check nothing depends on which side is left.
// Input: a Model (by value). Output: the mirrored Model (positions, normals, winding so the
// normals still point out, joints' rest translations and rotations, joint names).
#pragma once

#include <cctype>
#include <string>
#include <utility>

#include "deform/model/model.h"

namespace sweepd::test_models {

inline deform::Model mirrored(deform::Model model) {
  for (glm::vec3& p : model.positions) p.x = -p.x;
  for (glm::vec3& n : model.normals) n.x = -n.x;
  for (std::size_t t = 0; t + 2 < model.indices.size(); t += 3)
    std::swap(model.indices[t + 1], model.indices[t + 2]);
  for (deform::Joint& joint : model.skeleton.joints) {
    joint.rest_translation.x = -joint.rest_translation.x;
    joint.rest_rotation.y = -joint.rest_rotation.y;  // M R M with M = diag(-1, 1, 1)
    joint.rest_rotation.z = -joint.rest_rotation.z;
    std::string& n = joint.name;
    if (n.starts_with("Left")) {
      n = "Right" + n.substr(4);
    } else if (n.starts_with("Right")) {
      n = "Left" + n.substr(5);
    } else if (n.size() > 1 && (n[0] == 'L' || n[0] == 'R') && std::isupper(n[1])) {
      n[0] = n[0] == 'L' ? 'R' : 'L';
    }
  }
  return model;
}

}  // namespace sweepd::test_models
