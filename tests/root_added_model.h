// A model with one more joint above its skeleton's first root: what Mixamo-to-Unity and Unreal
// exports carry ("Root" above the hips or pelvis), a node that the clips leave at rest while the
// hips take the body's heading. The new joint sits at the origin with no turn, so every joint's
// world rest transform, the mesh and the skin weights mean what they meant.
// Input: a Model (by value) and the new joint's name. Output: the Model with that joint first
// (index 0) and every other joint one index on, in the skeleton and in the skin's joint indices.
#pragma once

#include <string>

#include "deform/model/model.h"

namespace sweepd::test_models {

inline deform::Model root_added(deform::Model model, const std::string& name = "Root") {
  for (deform::Joint& joint : model.skeleton.joints) ++joint.parent;  // a root's -1 becomes 0
  model.skeleton.joints.insert(model.skeleton.joints.begin(), deform::Joint{.name = name});
  for (auto& joints : model.skin_joints)
    for (auto& j : joints) ++j;
  return model;
}

}  // namespace sweepd::test_models
