// A model with its joints renamed, for tests that check nothing depends on the names a rig
// happens to use: a namespace prefix on every name (Mixamo's "mixamorig:"), names made up from
// the joint's index (no convention matches: the rig map comes from the skeleton's shape), or
// another convention's names for the joints of the model's own rig map (Unreal's pelvis,
// spine_01, thigh_l, ...; the joints it has no role for become "bone_<index>").
// Input: a Model (by value), and for the convention a RigMap of its skeleton.
// Output: the Model with new joint names; nothing else changes.
#pragma once

#include <string>
#include <vector>

#include "deform/model/model.h"
#include "deform/rig/rig_map.h"

namespace sweepd::test_models {

inline deform::Model prefixed_joint_names(deform::Model model, const std::string& prefix) {
  for (deform::Joint& joint : model.skeleton.joints) joint.name = prefix + joint.name;
  return model;
}

inline deform::Model meaningless_joint_names(deform::Model model) {
  for (int j = 0; j < model.skeleton.size(); ++j)
    model.skeleton.joints[j].name = "j" + std::to_string(j);
  return model;
}

inline deform::Model unreal_joint_names(deform::Model model, const deform::RigMap& map) {
  std::vector<std::string> names(model.skeleton.size());
  for (int j = 0; j < model.skeleton.size(); ++j) names[j] = "bone_" + std::to_string(j);
  auto name = [&](int joint, const std::string& unreal) {
    if (joint >= 0) names[joint] = unreal;
  };
  for (std::size_t i = 0; i < map.torso.chain.size(); ++i)
    name(map.torso.chain[i], i == 0 ? "pelvis" : "spine_0" + std::to_string(i));
  for (std::size_t i = 0; i + 1 < map.neck.chain.size(); ++i)
    name(map.neck.chain[i], "neck_0" + std::to_string(i + 1));
  name(map.neck.head, "head");
  for (const auto& [arm, leg, side] :
       {std::tuple{&map.left_arm, &map.left_leg, "_l"}, {&map.right_arm, &map.right_leg, "_r"}}) {
    const std::string s = side;
    name(arm->clavicle, "clavicle" + s);
    name(arm->upper, "upperarm" + s);
    name(arm->lower, "lowerarm" + s);
    name(arm->hand, "hand" + s);
    name(leg->upper, "thigh" + s);
    name(leg->lower, "calf" + s);
    name(leg->foot, "foot" + s);
    name(leg->toe, "ball" + s);
  }
  for (int j = 0; j < model.skeleton.size(); ++j) model.skeleton.joints[j].name = names[j];
  return model;
}

}  // namespace sweepd::test_models
